//! A run stopped by a signal, and what it leaves: Ctrl-C (SIGINT) or `kill` (SIGTERM) during
//! `run` lets the renders in progress finish, says how many jobs are saved and how to resume, and
//! exits with 130 (143); a rerun resumes from them. Once both exited 130 with no word. The temporary
//! files a `kill -9` leaves (atomic writes never renamed) are removed by the next run. Without a
//! terminal, progress is plain lines on stderr (once there was nothing until the end).

use crate::support::common::{Tmp, records, scene};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Long enough on one worker (about 200 jobs of up to 10 M rays: tens of seconds on a fast core)
/// that a test stopping it after its first saved jobs never sees it finish; each job is short, so
/// the renders in progress finish soon after the signal.
fn long_spec() -> String {
    format!(
        r#"name = "long"
scenes = ["{}"]
resolution = [96, 96]
replicates = 50
[reference]
rays = 256
replicates = 2
[[table]]
name = "t"
rays = [256, 1024]
rows = [
  {{ distribution = "uniform", sequence = "random" }},
  {{ distribution = "sine-cosine", sequence = "fibonacci" }},
]
"#,
        scene("cornell-box.toml")
    )
}

/// `hemilab run` on one worker, without --quiet, stderr to `log` (not a terminal).
fn start(t: &Tmp, log: &str) -> Child {
    Command::new(env!("CARGO_BIN_EXE_hemilab"))
        .args(["run", "long.toml", "--out", "out", "--reference-dir", "ref", "--threads", "1"])
        .current_dir(&t.0)
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(t.path(log)).unwrap())
        .spawn()
        .expect("start hemilab")
}

/// Waits (up to two minutes) until `ready`; panics if the run ends first.
fn wait_for(child: &mut Child, what: &str, ready: &dyn Fn() -> bool) {
    let start = Instant::now();
    while !ready() {
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended ({status}) before {what}");
        }
        assert!(start.elapsed() < Duration::from_secs(120), "no {what} after two minutes");
        std::thread::sleep(Duration::from_millis(50));
    }
}

fn signal(child: &Child, sig: i32) {
    // SAFETY: sends a signal to our own child process.
    assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, sig) }, 0);
}

fn saved(t: &Tmp) -> usize {
    records(&t.path("out")).len()
}

fn temporary_files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-") || n.contains(".link-"))
        .collect();
    v.sort();
    v
}

/// The number before " of 200 jobs are saved in out".
fn saved_in_message(line: &str) -> usize {
    let before = line.split(" of 200 jobs are saved in out; rerun `").next().unwrap();
    before.rsplit(' ').next().unwrap().parse().unwrap_or_else(|_| panic!("no count in: {line}"))
}

#[test]
fn a_signal_stops_a_run_that_says_what_is_saved_and_resumes() {
    let t = Tmp::new("interrupt");
    t.spec("long.toml", &long_spec());
    let log = |name: &str| std::fs::read_to_string(t.path(name)).unwrap_or_default();

    let mut run = start(&t, "1.log");
    wait_for(&mut run, "a job was saved and a progress line printed", &|| {
        saved(&t) > 0 && log("1.log").lines().any(|l| l.starts_with("jobs: "))
    });
    signal(&run, libc::SIGINT);
    let status = run.wait().unwrap();
    let text = log("1.log");
    assert_eq!(status.code(), Some(130), "{text}");
    assert!(
        text.contains("interrupted (SIGINT): stopping after the renders in progress, which are kept"),
        "{text}"
    );
    let last = text.lines().last().unwrap();
    assert!(
        last.starts_with("interrupted (SIGINT): stopped; ") && last.ends_with("to resume from them"),
        "{text}"
    );
    assert!(last.contains(" --out out --reference-dir ref --threads 1` "), "the command to rerun: {last}");
    let first = saved_in_message(last);
    assert_eq!(first, saved(&t), "the message counts the saved records: {text}");
    assert!(first < 200, "{text}");
    // The files a person opens hold every saved job, not only the journal (once results.csv held 1
    // row while the message said 16 of 16 jobs were saved).
    let csv = std::fs::read_to_string(t.path("out/results.csv")).unwrap();
    assert_eq!(csv.lines().count(), first + 1, "a header and one row per saved job:\n{csv}");
    let json = hemilab::results::from_json(&std::fs::read_to_string(t.path("out/results.json")).unwrap());
    assert_eq!(json.unwrap().len(), first, "results.json alone holds every saved job");
    assert!(!t.path("out/results.journal.jsonl").exists(), "the journal is folded in");
    assert!(temporary_files(&t.path("out")).is_empty() && temporary_files(&t.path("out/images")).is_empty());

    // Each saved image says where it came from.
    let image = t.path("out").join(&records(&t.path("out"))[0].image);
    let p = hemilab::image::decode_exr_provenance(&std::fs::read(&image).unwrap()).unwrap().unwrap();
    assert_eq!((p.json["image"].as_str(), p.json["spec"].as_str()), (Some("job"), Some("long")), "{p:?}");
    assert!(p.json["rays"] == 256 || p.json["rays"] == 1024, "{p:?}");
    assert!(p.json["reference"].as_str().unwrap().starts_with("cornell-box-96x96-"), "{p:?}");
    assert_eq!(p.json["hemilab_version"], env!("CARGO_PKG_VERSION"));
    // So does the reference it was measured against, and its manifest's camera is JSON.
    let stem = p.json["reference"].as_str().unwrap().trim_end_matches(".exr").to_string();
    let r = std::fs::read(t.path("ref").join(format!("{stem}.exr"))).unwrap();
    let r = hemilab::image::decode_exr_provenance(&r).unwrap().unwrap();
    assert_eq!((r.json["image"].as_str(), r.json["rays"].as_u64()), (Some("reference"), Some(256)), "{r:?}");
    assert!(r.json.get("time_s").is_none(), "no render time: the bytes are the same every build");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.path("ref").join(format!("{stem}.json"))).unwrap())
            .unwrap();
    assert_eq!(manifest["camera"]["projection"], "perspective", "{manifest}");
    assert_eq!(manifest["camera"]["eye"], serde_json::json!([278.0, 273.0, -800.0]), "{manifest}");
    assert_eq!(r.json["camera"], manifest["camera"]);

    // A `kill -9` leaves temporary files; the rerun removes those of writers that are gone (PID
    // 4194304 is above Linux's largest), and no other.
    let host = hemilab::io::host_tag();
    let stale = [format!(".x.exr.tmp-{host}-4194304"), format!(".results.json.tmp-{host}-4194304")];
    let alive = format!(".y.exr.tmp-{host}-1");
    std::fs::write(t.path("out/images").join(&stale[0]), b"half").unwrap();
    std::fs::write(t.path("out").join(&stale[1]), b"half").unwrap();
    std::fs::write(t.path("out/images").join(&alive), b"being written").unwrap();

    // The rerun resumes from the saved jobs; SIGTERM stops it the same way, with 143.
    let mut run = start(&t, "2.log");
    wait_for(&mut run, "more jobs were saved", &|| saved(&t) > first);
    signal(&run, libc::SIGTERM);
    let status = run.wait().unwrap();
    let text = log("2.log");
    assert_eq!(status.code(), Some(143), "{text}");
    assert!(text.starts_with("note: removed 2 temporary file(s) an interrupted run left in out"), "{text}");
    assert_eq!(temporary_files(&t.path("out/images")), [alive]);
    let last = text.lines().last().unwrap();
    assert!(last.starts_with("terminated (SIGTERM): stopped; "), "{text}");
    let second = saved_in_message(last);
    assert!(second > first, "resumed from {first} saved jobs, not from none: {text}");
    assert_eq!(second, saved(&t));
}

/// Ctrl-C while a reference is being built ends the command at once (no job is running to finish);
/// the reference's lock file goes with it, as it goes after a finished build.
#[test]
fn a_signal_during_a_reference_build_leaves_no_lock_file() {
    let t = Tmp::new("interrupt-lock");
    // About 300 M rays on one thread: tens of seconds, far longer than the test waits.
    t.spec("long.toml", &long_spec().replace("rays = 256\nreplicates = 2", "rays = 16384\nreplicates = 2"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_hemilab"))
        .args(["reference", "long.toml", "--reference-dir", "ref", "--threads", "1", "--quiet"])
        .current_dir(&t.0)
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(t.path("r.log")).unwrap())
        .spawn()
        .expect("start hemilab");
    let locks = || -> Vec<String> {
        std::fs::read_dir(t.path("ref"))
            .map(|d| {
                d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                    .filter(|n| n.ends_with(".lock"))
                    .collect()
            })
            .unwrap_or_default()
    };
    wait_for(&mut child, "the reference's lock was taken", &|| !locks().is_empty());
    signal(&child, libc::SIGINT);
    let status = child.wait().unwrap();
    let text = std::fs::read_to_string(t.path("r.log")).unwrap();
    assert_eq!(status.code(), Some(130), "{text}");
    assert!(locks().is_empty(), "left behind: {:?}\n{text}", locks());
}

/// Ctrl-C during `render`: the message says how long it had rendered and that nothing was written
/// (once it said "stopped before any job ran … rerun to go on" after seconds of work, and a render
/// does not resume).
#[test]
fn a_signal_stops_render_which_says_nothing_was_written() {
    let t = Tmp::new("interrupt-render");
    // About a billion rays on one thread: far longer than the test waits, well under 30 minutes.
    let mut child = Command::new(env!("CARGO_BIN_EXE_hemilab"))
        .args([
            "render",
            &scene("cornell-box.toml"),
            "--rays",
            "16384",
            "--resolution",
            "256x256",
            "--output",
            "img.exr",
            "--threads",
            "1",
        ])
        .current_dir(&t.0)
        .stdout(std::fs::File::create(t.path("r.out")).unwrap())
        .stderr(std::fs::File::create(t.path("r.log")).unwrap())
        .spawn()
        .expect("start hemilab");
    let out = || std::fs::read_to_string(t.path("r.out")).unwrap_or_default();
    wait_for(&mut child, "the render's plan", &|| out().contains("render plan: "));
    std::thread::sleep(Duration::from_millis(300));
    signal(&child, libc::SIGINT);
    let status = child.wait().unwrap();
    let text = std::fs::read_to_string(t.path("r.log")).unwrap();
    assert_eq!(status.code(), Some(130), "{text}");
    let last = text.lines().last().unwrap_or_default();
    assert!(last.starts_with("interrupted (SIGINT): stopped after "), "{last}");
    assert!(last.contains("the image was not finished and nothing was written (img.exr"), "{last}");
    assert!(last.contains("a render does not resume") && !last.contains("before any job ran"), "{last}");
    assert!(!t.path("img.exr").exists() && !t.path("img.png").exists());
}

/// Ctrl-C during advise's sweep: its progress lines are labelled by phase, and the message says how
/// many jobs are kept, where, and the command that resumes from them (once it said nothing was
/// saved, while the rerun reused all but a few); the rerun reuses them.
#[test]
fn a_signal_stops_advise_which_says_what_it_kept_and_resumes() {
    let t = Tmp::new("interrupt-advise");
    let reference = format!("{}/reference", env!("CARGO_MANIFEST_DIR"));
    let args = |quiet: bool| {
        let mut v = vec![
            "advise".to_string(),
            scene("cornell-box.toml"),
            "--rays".into(),
            "64,128,256,512".into(),
            "--out".into(),
            "adv".into(),
            "--reference-dir".into(),
            reference.clone(),
            "--threads".into(),
            "1".into(),
        ];
        if quiet {
            v.push("--quiet".into());
        }
        v
    };
    let mut child = Command::new(env!("CARGO_BIN_EXE_hemilab"))
        .args(args(false))
        .current_dir(&t.0)
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(t.path("a.log")).unwrap())
        .spawn()
        .expect("start hemilab");
    let log = || std::fs::read_to_string(t.path("a.log")).unwrap_or_default();
    wait_for(&mut child, "a progress line of the sweep", &|| log().lines().any(|l| l.starts_with("sweep: ")));
    signal(&child, libc::SIGINT);
    let status = child.wait().unwrap();
    let text = log();
    assert_eq!(status.code(), Some(130), "{text}");
    assert!(text.contains("resolution 32x32 ("), "the resolution and why, at the start: {text}");
    let last = text.lines().last().unwrap();
    assert!(
        last.starts_with("interrupted (SIGINT): stopped; ") && last.ends_with("to resume from them"),
        "{last}"
    );
    assert!(last.contains(" jobs are saved in ") && last.contains(".adv.partial"), "{last}");
    let kept: usize = last.split(" of ").next().unwrap().rsplit(' ').next().unwrap().parse().unwrap();
    assert!(kept > 0, "{last}");
    // The rerun reuses what was kept.
    let o = Command::new(env!("CARGO_BIN_EXE_hemilab")).args(args(true)).current_dir(&t.0).output().unwrap();
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let reused: usize = out
        .split(" reused")
        .next()
        .and_then(|s| s.rsplit(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no reuse count in {out}"));
    assert!(reused >= kept, "kept {kept}, reused {reused}: {out}");
    assert!(out.starts_with("scene 'cornell-box': 30 triangles, no alpha masks"), "{out}");
}

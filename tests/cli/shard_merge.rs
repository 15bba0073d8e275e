//! `run --shard K/N` and `merge` through the real binary: concurrent shards merged equal one plain
//! run but for the times, the merged report is whole, a killed shard resumes, an incomplete or
//! mixed merge writes nothing, and `--shard auto` reads Slurm's and Kubernetes' variables.

use crate::support::common;

use common::*;
use hemilab::results::{JobResult, TIME_COLUMNS};
use hemilab::shard::Shard;
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// The batch-scheduler variables `--shard auto` reads: cleared, so a test run inside a Slurm job
/// or a Kubernetes pod sees only what the test sets.
const SCHEDULER_VARS: [&str; 4] =
    ["SLURM_ARRAY_TASK_ID", "SLURM_ARRAY_TASK_COUNT", "SLURM_ARRAY_TASK_MIN", "JOB_COMPLETION_INDEX"];

fn hemilab(t: &Tmp, args: &[&str], env: &[(&str, &str)]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_hemilab"));
    c.args(args).current_dir(&t.0);
    for v in SCHEDULER_VARS {
        c.env_remove(v);
    }
    for (k, v) in env {
        c.env(k, v);
    }
    c
}

fn output(mut c: Command) -> Output {
    c.output().expect("run hemilab")
}

/// `results.csv` with every time column dropped.
fn csv_without_times(out: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..header.len()).filter(|&i| !TIME_COLUMNS.contains(&header[i])).collect();
    assert!(keep.len() + TIME_COLUMNS.len() == header.len(), "every time column is in the file");
    text.lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            keep.iter().map(|&i| f[i]).collect::<Vec<_>>().join(",")
        })
        .collect()
}

fn without_times(rs: &[JobResult]) -> Vec<JobResult> {
    rs.iter().map(JobResult::without_times).collect()
}

/// Files of a directory (not below), sorted.
fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn concurrent_shards_merge_into_the_plain_run() {
    let t = Tmp::new("shards");
    let spec = t.spec("tiny.toml", &tiny_spec(64, ""));
    // Three shards started together, no reference yet: one builds it, the others wait for it.
    let children: Vec<_> = (0..3)
        .map(|k| {
            let shard = format!("{k}/3");
            let mut c = hemilab(
                &t,
                &["run", "tiny.toml", "--shard", &shard, "--reference-dir", "ref", "--quiet"],
                &[],
            );
            c.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap()
        })
        .collect();
    let outs: Vec<Output> = children.into_iter().map(|c| c.wait_with_output().unwrap()).collect();
    for o in &outs {
        assert!(o.status.success(), "{}", stderr(o));
    }
    let built = outs.iter().filter(|o| stderr(o).contains("rendering a new one")).count();
    assert_eq!(built, 1, "the reference is built once");
    let refs: Vec<String> = files(&t.path("ref")).into_iter().filter(|f| !f.ends_with(".lock")).collect();
    assert_eq!(refs.len(), 2, "one image and one manifest, no temporary leftovers: {refs:?}");

    let dirs: Vec<String> = (0..3).map(|k| format!("out/tiny/shard-{k}-of-3")).collect();
    let mut counts = Vec::new();
    for d in &dirs {
        assert!(t.path(d).join("shard.json").exists(), "{d}");
        assert!(!t.path(d).join("index.html").exists(), "a shard writes no report of its own");
        counts.push(records(&t.path(d)).len());
    }
    assert_eq!(counts.iter().sum::<usize>(), 16, "{counts:?}");
    assert!(counts.iter().all(|&c| c > 0), "{counts:?}");

    let mut args = vec!["merge", "tiny.toml"];
    args.extend(dirs.iter().map(String::as_str));
    args.extend(["--reference-dir", "ref", "--quiet"]);
    let o = output(hemilab(&t, &args, &[]));
    assert!(o.status.success(), "{}", stderr(&o));

    // One plain run, with a reference of its own.
    t.run_ok(&spec, "plain", "plain-ref", &[]);
    let (merged, plain) = (t.path("out/tiny"), t.path("plain"));
    assert_eq!(without_times(&records(&merged)), without_times(&records(&plain)));
    assert_eq!(csv_without_times(&merged), csv_without_times(&plain));
    for r in records(&plain) {
        let a = std::fs::read(merged.join(&r.image)).unwrap();
        assert_eq!(a, std::fs::read(plain.join(&r.image)).unwrap(), "{}", r.image);
    }
    // The whole report: every file the plain run wrote, and the same aggregates and slopes.
    let report: Vec<String> = files(&merged).into_iter().filter(|f| !f.starts_with("shard-")).collect();
    assert_eq!(report, files(&plain));
    assert_eq!(files(&merged.join("images")), files(&plain.join("images")));
    let page = std::fs::read_to_string(merged.join("report.md")).unwrap();
    assert!(page.contains("Merged from 3 shard directories") && page.contains("one machine"), "{page}");
    // Slopes against rays and the aggregates' error columns depend on no time.
    let vs_rays = |p: &Path| {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(p.join("slopes.json")).unwrap()).unwrap();
        let groups = v.as_array().unwrap().clone();
        groups
            .iter()
            .flat_map(|g| g["slopes"].as_array().unwrap().clone())
            .map(|s| s["vs_rays"].clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(vs_rays(&merged), vs_rays(&plain));
    let rmse_columns = |p: &Path| {
        let text = std::fs::read_to_string(p.join("aggregates.csv")).unwrap();
        text.lines().map(|l| l.split(',').take(16).collect::<Vec<_>>().join(",")).collect::<Vec<_>>()
    };
    assert_eq!(rmse_columns(&merged), rmse_columns(&plain));
    let timing: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(merged.join("timing.json")).unwrap()).unwrap();
    assert_eq!(timing["machines"], 1);
    let per_shard = timing["shards"].as_array().unwrap();
    assert_eq!(per_shard.len(), 3);
    let traced: usize = per_shard.iter().map(|s| s["records"].as_array().unwrap().len()).sum();
    assert_eq!(traced, 16, "every record traced to the shard (and machine) that timed it");
}

#[test]
fn an_incomplete_or_mixed_merge_writes_nothing() {
    let t = Tmp::new("merge-refused");
    t.spec("tiny.toml", &tiny_spec(64, ""));
    for k in 0..3 {
        let shard = format!("{k}/3");
        let o = output(hemilab(
            &t,
            &["run", "tiny.toml", "--shard", &shard, "--reference-dir", "ref", "--quiet"],
            &[],
        ));
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let before = t.listing();
    let merge = |dirs: &[&str], spec: &str| {
        let mut args = vec!["merge", spec];
        args.extend(dirs);
        args.extend(["--reference-dir", "ref", "--out", "merged", "--quiet"]);
        output(hemilab(&t, &args, &[]))
    };
    let o = merge(&["out/tiny/shard-0-of-3", "out/tiny/shard-2-of-3"], "tiny.toml");
    let e = assert_error(&o, "6 of 16 planned jobs are missing");
    assert!(e.contains("shard 1/3 (6 of its 6 jobs; no directory of it given)"), "{e}");
    assert_eq!(t.listing(), before, "nothing written");

    // A shard whose run stopped early: named as unfinished, with its directory.
    let d1 = t.path("out/tiny/shard-1-of-3");
    let mut rs = records(&d1);
    rs.truncate(1);
    std::fs::write(d1.join("results.json"), hemilab::results::to_json(&rs)).unwrap();
    let o = merge(&["out/tiny/shard-0-of-3", "out/tiny/shard-1-of-3", "out/tiny/shard-2-of-3"], "tiny.toml");
    let e = assert_error(&o, "5 of 16 planned jobs are missing");
    assert!(e.contains("shard 1/3 (5 of its 6 jobs; unfinished in out/tiny/shard-1-of-3"), "{e}");
    assert!(!t.path("merged").exists());

    // Another spec: the same name and scenes, another seed.
    t.spec("other.toml", &tiny_spec(64, "").replace("seed = 3", "seed = 4"));
    let o = merge(&["out/tiny/shard-0-of-3"], "other.toml");
    let e = assert_error(&o, &format!("out/tiny/shard-0-of-3/{}", "shard.json"));
    assert!(e.contains("another version of spec 'tiny'") && e.contains("one spec only"), "{e}");
    // Another name.
    t.spec("renamed.toml", &tiny_spec(64, "").replace("name = \"tiny\"", "name = \"renamed\""));
    let e =
        assert_error(&merge(&["out/tiny/shard-0-of-3"], "renamed.toml"), "out/tiny/shard-0-of-3/shard.json");
    assert!(e.contains("ran spec 'tiny'"), "{e}");
    // Shards of two different splits.
    let o = output(hemilab(
        &t,
        &["run", "tiny.toml", "--shard", "0/2", "--reference-dir", "ref", "--quiet"],
        &[],
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = merge(&["out/tiny/shard-0-of-3", "out/tiny/shard-0-of-2"], "tiny.toml");
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("merge the shards of one split"), "{e}");
    // A directory that is no shard.
    let e = assert_error(&merge(&["ref"], "tiny.toml"), "ref/shard.json");
    assert!(e.contains("hemilab run --shard K/N"), "{e}");
    // The references the shards used are not where the merge looks.
    let o = output(hemilab(
        &t,
        &["merge", "tiny.toml", "out/tiny/shard-0-of-3", "--reference-dir", "elsewhere", "--out", "merged"],
        &[],
    ));
    let e = assert_error(&o, "no usable reference for scene 'cornell-box' in elsewhere");
    assert!(e.contains("the --reference-dir the shards used"), "{e}");
    assert!(!t.path("merged").exists(), "nothing written by any refused merge");
}

#[test]
fn duplicates_must_be_identical() {
    let t = Tmp::new("merge-dup");
    t.spec("tiny.toml", &tiny_spec(64, ""));
    for k in 0..2 {
        let shard = format!("{k}/2");
        let o = output(hemilab(
            &t,
            &["run", "tiny.toml", "--shard", &shard, "--reference-dir", "ref", "--quiet"],
            &[],
        ));
        assert!(o.status.success(), "{}", stderr(&o));
    }
    // Shard 1 again elsewhere (another session: other times, same results): merged once.
    let o = output(hemilab(
        &t,
        &["run", "tiny.toml", "--shard", "1/2", "--out", "again", "--reference-dir", "ref", "--quiet"],
        &[],
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    let args = ["merge", "tiny.toml", "out/tiny/shard-0-of-2", "out/tiny/shard-1-of-2", "again"];
    let o =
        output(hemilab(&t, &[&args[..], &["--reference-dir", "ref", "--out", "m", "--quiet"]].concat(), &[]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(records(&t.path("m")).len(), 16);
    // A duplicate that differs is refused.
    let mut rs = records(&t.path("again"));
    rs[0].rmse += 1e-9;
    std::fs::write(t.path("again/results.json"), hemilab::results::to_json(&rs)).unwrap();
    let o = output(hemilab(
        &t,
        &[&args[..], &["--reference-dir", "ref", "--out", "m2", "--quiet"]].concat(),
        &[],
    ));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("with different results"), "{}", stderr(&o));
    assert!(!t.path("m2").exists());
}

#[test]
fn shard_auto_reads_slurm_and_kubernetes() {
    let t = Tmp::new("shard-auto");
    let spec = t.spec("tiny.toml", &tiny_spec(64, ""));
    let slurm = [("SLURM_ARRAY_TASK_ID", "1"), ("SLURM_ARRAY_TASK_COUNT", "3")];
    let o = output(hemilab(
        &t,
        &["run", "tiny.toml", "--shard", "auto", "--reference-dir", "ref", "--quiet"],
        &slurm,
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("shard 1/3"), "{}", stdout(&o));
    let got = records(&t.path("out/tiny/shard-1-of-3"));
    let text = std::fs::read_to_string(&spec).unwrap();
    let plan = hemilab::plan::plan(&hemilab::spec::parse_spec(&text, &spec).unwrap());
    let want = hemilab::shard::select(&plan, Shard::new(1, 3).unwrap(), |_| unreachable!(), 3);
    let brief = |r: &JobResult| {
        (r.distribution.clone(), r.sequence.clone(), r.seed_mode.clone(), r.rays, r.replicate)
    };
    let want: Vec<_> = want
        .jobs
        .iter()
        .map(|j| {
            (j.distribution.to_string(), j.sequence.to_string(), j.seed_mode.to_string(), j.rays, j.replicate)
        })
        .collect();
    assert_eq!(got.iter().map(brief).collect::<Vec<_>>(), want, "exactly shard 1/3");
    let manifest = std::fs::read_to_string(t.path("out/tiny/shard-1-of-3/shard.json")).unwrap();
    assert!(manifest.contains("\"shard\": 1") && manifest.contains("\"shards\": 3"), "{manifest}");

    // Kubernetes: the index, and N from --shards.
    let o = output(hemilab(
        &t,
        &["run", "tiny.toml", "--shard", "auto", "--shards", "3", "--reference-dir", "ref", "--quiet"],
        &[("JOB_COMPLETION_INDEX", "2")],
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(t.path("out/tiny/shard-2-of-3/results.json").exists());

    // Neither: one clear error, exit 2, nothing run.
    let before = t.listing();
    let o = output(hemilab(
        &t,
        &["run", "tiny.toml", "--shard", "auto", "--reference-dir", "ref", "--quiet"],
        &[],
    ));
    let e = assert_error(&o, "--shard auto");
    assert!(e.contains("SLURM_ARRAY_TASK_ID") && e.contains("JOB_COMPLETION_INDEX"), "{e}");
    assert_eq!(t.listing(), before);
    // A shard that does not exist is clap's usage error.
    let o = output(hemilab(&t, &["run", "tiny.toml", "--shard", "3/3"], &[]));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("0 to 2 (0-based)"), "{}", stderr(&o));
}

/// Seconds of work per shard on the Cornell box, so that a shard can be killed mid-run.
fn slow_spec() -> String {
    format!(
        r#"name = "slow"
scenes = ["{}"]
resolution = [64, 48]
replicates = 3
[reference]
rays = 256
replicates = 2
[[table]]
name = "t"
rays = [512, 1024, 2048]
rows = [
  {{ distribution = "sine-cosine", sequence = "random" }},
  {{ distribution = "sine-cosine", sequence = "fibonacci", seed_mode = "shift" }},
]
"#,
        scene("cornell-box.toml")
    )
}

#[test]
fn a_killed_shard_resumes() {
    let t = Tmp::new("shard-kill");
    t.spec("slow.toml", &slow_spec());
    // The separate reference step, then shards that may not build one.
    let o = output(hemilab(&t, &["reference", "slow.toml", "--reference-dir", "ref", "--quiet"], &[]));
    assert!(o.status.success(), "{}", stderr(&o));
    let shard = |out: &str| {
        let args = ["run", "slow.toml", "--shard", "0/2", "--out", out, "--reference-dir", "ref"];
        hemilab(&t, &[&args[..], &["--no-build-reference", "--quiet"]].concat(), &[])
    };
    let whole = output(shard("whole"));
    assert!(whole.status.success(), "{}", stderr(&whole));
    let whole = records(&t.path("whole"));

    let mut c = shard("killed");
    let mut child = c.stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
    let results = t.path("killed/results.json");
    let done_before = loop {
        let n = std::fs::read_to_string(&results).ok().and_then(|s| hemilab::results::from_json(&s).ok());
        if let Some(rs) = n.filter(|rs| !rs.is_empty()) {
            child.kill().unwrap();
            break rs;
        }
        assert!(child.try_wait().unwrap().is_none(), "the shard finished before it could be killed");
        std::thread::sleep(std::time::Duration::from_millis(2));
    };
    assert!(!child.wait().unwrap().success(), "killed");
    // What the killed run had written may have grown between the read and the kill.
    let at_kill = records(&t.path("killed"));
    assert!(at_kill.len() >= done_before.len() && at_kill.len() < whole.len(), "{}", at_kill.len());
    eprintln!("killed after {} of {} jobs", at_kill.len(), whole.len());

    let o = output(shard("killed"));
    assert!(o.status.success(), "{}", stderr(&o));
    let resumed = records(&t.path("killed"));
    assert_eq!(
        without_times(&resumed),
        without_times(&whole),
        "the resumed shard equals an uninterrupted one"
    );
    for r in &at_kill {
        let again = resumed.iter().find(|x| x.key == r.key).unwrap();
        assert_eq!(again.times.first(), r.times.first(), "{}: not rendered again", r.image);
    }
}

/// One shard's image cut short: `merge` checks the shards' files before it writes, names the
/// shard's own file (once it named the merged copy, after writing the results and images) and
/// writes nothing.
#[test]
fn a_truncated_shard_image_is_named_and_nothing_is_written() {
    let t = Tmp::new("merge-truncated");
    t.spec("tiny.toml", &tiny_spec(64, ""));
    for k in 0..2 {
        let shard = format!("{k}/2");
        let o = output(hemilab(
            &t,
            &["run", "tiny.toml", "--shard", &shard, "--reference-dir", "ref", "--quiet"],
            &[],
        ));
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let d1 = t.path("out/tiny/shard-1-of-2");
    let image = records(&d1)[0].image.clone();
    let bytes = std::fs::read(d1.join(&image)).unwrap();
    std::fs::write(d1.join(&image), &bytes[..bytes.len() / 2]).unwrap();
    let before = t.listing();
    let args = ["merge", "tiny.toml", "out/tiny/shard-0-of-2", "out/tiny/shard-1-of-2"];
    let o =
        output(hemilab(&t, &[&args[..], &["--reference-dir", "ref", "--out", "m", "--quiet"]].concat(), &[]));
    let e = assert_error(&o, &format!("out/tiny/shard-1-of-2/{image}"));
    assert!(e.contains("not a readable EXR"), "{e}");
    assert!(!t.path("m").exists(), "nothing written");
    assert_eq!(t.listing(), before);
}

/// Shards run one after another into one `--out` (once only the last shard's records were kept,
/// the others' dropped): a second shard is refused there, before any work, naming the directory,
/// the shard it holds and what to do; the first shard's records are all still there, and a rerun of
/// the same shard resumes as before. A whole run into a shard's directory keeps its records too.
#[test]
fn a_second_shard_into_one_out_is_refused_and_no_record_is_dropped() {
    let t = Tmp::new("shard-one-out");
    t.spec("tiny.toml", &tiny_spec(64, ""));
    let shard = |k: u32| {
        let shard = format!("{k}/3");
        output(hemilab(
            &t,
            &["run", "tiny.toml", "--shard", &shard, "--out", "one", "--reference-dir", "ref", "--quiet"],
            &[],
        ))
    };
    let o = shard(0);
    assert!(o.status.success(), "{}", stderr(&o));
    let first = records(&t.path("one"));
    assert!(!first.is_empty());
    let before = t.listing();
    let e = assert_error(&shard(1), "one");
    assert!(e.contains("holds shard 0/3 of spec 'tiny'") && e.contains("hemilab merge"), "{e}");
    assert_eq!(t.listing(), before, "nothing written");
    assert_eq!(without_times(&records(&t.path("one"))), without_times(&first));
    // The same shard again resumes.
    let o = shard(0);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(without_times(&records(&t.path("one"))), without_times(&first));

    // A shard into a whole run's directory would keep only its own part of the records: refused.
    let o = output(hemilab(
        &t,
        &["run", "tiny.toml", "--out", "whole", "--reference-dir", "ref", "--quiet"],
        &[],
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    let whole = records(&t.path("whole"));
    let o = output(hemilab(
        &t,
        &["run", "tiny.toml", "--shard", "1/3", "--out", "whole", "--reference-dir", "ref", "--quiet"],
        &[],
    ));
    let e = assert_error(&o, "whole");
    assert!(e.contains("records of jobs of other shards"), "{e}");
    assert_eq!(records(&t.path("whole")).len(), whole.len());
}

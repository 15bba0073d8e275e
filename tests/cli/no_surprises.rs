//! No surprises before work starts: `render` and `advise` say first what they will cost on this
//! machine (time and bytes) and refuse, with exit status 2 and nothing written, what would take
//! longer than `--max-minutes` (once `render --rays 1048576 --resolution 8192x8192` started days of
//! work without a word); `plan` counts a moving camera's references (it said 1 and about 8 minutes
//! for a spec that needed 12 and took 26.5) and the bytes a run writes; each pipeline's advice has
//! a folder of its own, and an `--out` holding another question's advice is refused.

use crate::support::common::{Tmp, scene, stderr, stdout};

#[test]
fn render_says_what_it_costs_and_refuses_days_of_work() {
    let t = Tmp::new("render-forecast");
    let huge = [
        "render",
        &scene("cornell-box.toml"),
        "--rays",
        "1048576",
        "--resolution",
        "8192x8192",
        "--output",
        "big.exr",
    ];
    let o = t.hemilab(&huge);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("render plan: 1 image: ≈ "), "the forecast comes with the refusal: {e}");
    assert!(
        e.contains("--max-minutes 30: this would take about ") && e.contains("nothing was started"),
        "{e}"
    );
    // The suggested limit is whole minutes, above the forecast.
    let need: f64 = e.rsplit("--max-minutes ").next().unwrap().trim().parse().unwrap();
    assert!(need > 30.0 * 60.0, "days of work, in minutes: {need}");
    assert!(t.listing().is_empty(), "nothing written: {:?}", t.listing());
    // A lower limit refuses a small render too; a small render within it runs and says its plan.
    let small =
        ["render", &scene("cornell-box.toml"), "--rays", "4", "--resolution", "32x24", "--output", "s.exr"];
    let o = t.hemilab(&[&small[..], &["--max-minutes", "0.000001"]].concat());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(t.listing().is_empty(), "{:?}", t.listing());
    let o = t.hemilab(&small);
    assert!(o.status.success(), "{}", stderr(&o));
    let line = stdout(&o).lines().find(|l| l.starts_with("render plan: ")).unwrap_or_default().to_string();
    assert!(line.contains("1 image: ≈ ") && line.contains(" written"), "{}", stdout(&o));
    // Bytes: the EXR and the PNG written, within a factor of three of the forecast.
    let written: u64 = ["s.exr", "s.png"].iter().map(|f| std::fs::metadata(t.path(f)).unwrap().len()).sum();
    let forecast = bytes(&line);
    assert!(
        (written as f64 / 3.0..=written as f64 * 3.0).contains(&forecast),
        "{forecast} vs {written}: {line}"
    );
}

/// The bytes a forecast line states ("≈ 12 kB written").
fn bytes(line: &str) -> f64 {
    let head = line.rsplit("≈ ").next().unwrap().trim_end_matches(" written");
    let (n, unit) = head.split_once(' ').unwrap();
    let scale = match unit {
        "bytes" => 1.0,
        "kB" => 1e3,
        "MB" => 1e6,
        "GB" => 1e9,
        _ => panic!("unit {unit} in {line}"),
    };
    n.parse::<f64>().unwrap() * scale
}

fn advise_args(extra: &[&str]) -> Vec<String> {
    let mut v: Vec<String> =
        ["advise", &scene("cornell-box.toml"), "--resolution", "20x16", "--rays", "1,2", "--replicates", "2"]
            .map(String::from)
            .to_vec();
    v.extend(
        ["--only", "sine-cosine/fibonacci/rotation", "--reference-dir", "ref", "--threads", "2"]
            .map(String::from),
    );
    v.extend(extra.iter().map(|s| s.to_string()));
    v
}

#[test]
fn advise_says_its_plan_first_and_refuses_one_over_the_limit() {
    let t = Tmp::new("advise-forecast");
    let o = t.hemilab(&advise_args(&["--max-minutes", "0.000001"]));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("advise plan: 1 reference to build, "), "{e}");
    assert!(e.contains("a sweep of 8 and about "), "2 configurations x 2 ray counts x 2 replicates: {e}");
    assert!(e.contains("--max-minutes 0.000001: this would take about"), "{e}");
    assert!(t.listing().is_empty(), "nothing written, not even the reference: {:?}", t.listing());

    // Within the limit it runs, having said its plan first.
    let o = t.hemilab(&advise_args(&["--pipeline", "atrous"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    let plan = e.lines().position(|l| l.starts_with("advise plan: 1 reference to build, ")).expect(&e);
    let first_progress = e.lines().position(|l| l.contains(" % after ")).unwrap_or(usize::MAX);
    assert!(plan < first_progress, "{e}");
    // Its own folder: the pipeline's name in it, so that the raw advice beside it is another.
    assert!(t.path("out/advise-cornell-box-atrous/advice.json").exists(), "{:?}", t.listing());
    let o = t.hemilab(&advise_args(&["--quiet"]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(t.path("out/advise-cornell-box/advice.json").exists(), "{:?}", t.listing());
    let a = |dir: &str| std::fs::read_to_string(t.path(dir).join("advice.json")).unwrap();
    assert!(a("out/advise-cornell-box-atrous").contains("\"pipeline\": \"atrous\""));
    assert!(a("out/advise-cornell-box").contains("\"pipeline\": \"raw\""));

    // Asked into the other's folder, it refuses (exit 2) and keeps that advice as it was.
    let before = a("out/advise-cornell-box-atrous");
    let o = t.hemilab(&advise_args(&["--quiet", "--out", "out/advise-cornell-box-atrous"]));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("holds advise's answer for pipeline atrous at frame 1"), "{e}");
    assert!(e.contains("its default is out/advise-cornell-box)"), "{e}");
    assert_eq!(a("out/advise-cornell-box-atrous"), before);
}

/// A table of one configuration over a moving camera's 4 frames: measured at frames 1, 2 and 4,
/// each compared with its reference and the frame before (flicker), so frames 0-3 (from 0) need one;
/// frame 0 is seen from the scene's own camera, so its reference is the scene's.
fn moving_spec() -> String {
    format!(
        r#"name = "moving"
scenes = ["{}"]
resolution = [32, 24]
replicates = 2
[reference]
rays = 64
replicates = 2
[timing]
repeats = 1
[cameras.orbit]
path = {{ orbit = {{ degrees = 10.0 }} }}
[[table]]
name = "t"
rays = [1]
distributions = ["sine-cosine"]
sequences = ["fibonacci"]
seed_modes = ["rotation"]
pipelines = ["ema0.1"]
cameras = ["orbit"]
frames = 4
"#,
        scene("cornell-box.toml")
    )
}

#[test]
fn plan_counts_a_moving_cameras_references_and_the_bytes_written() {
    let t = Tmp::new("plan-moving");
    t.spec("moving.toml", &moving_spec());
    let o = t.hemilab(&["plan", "moving.toml", "--reference-dir", "ref"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("reference 'cornell-box': must be built (2 x 64 rays)"), "{text}");
    assert!(
        text.contains("references of camera 'orbit' on 'cornell-box': 4 (")
            && text.contains("): 3 must be built (2 x 64 rays each), the other 1 stored or the scene's own"),
        "{text}"
    );
    assert!(text.contains("disk: ≈ ") && !text.contains("references none to build"), "{text}");
    // A real-time frame costs its render and its pipeline's own work, calibrated on the moving
    // camera's history (once left out: advise on the kitchen under SVGF was forecast at 84 s of
    // CPU time and took 178 s).
    let cal = text.lines().find(|l| l.starts_with("calibration on this machine")).unwrap();
    assert!(cal.contains(", ema0.1 (moving camera) + ") && cal.ends_with(" ms per frame"), "{cal}");

    t.run_ok(&t.path("moving.toml"), "out", "ref", &[]);
    // Every reference the plan counted was built, and the plan now finds them all.
    let manifests = std::fs::read_dir(t.path("ref"))
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension().is_some_and(|x| x == "json"))
        .count();
    assert_eq!(manifests, 4, "the scene's own, which is frame 0's too, and frames 1-3's");
    let o = t.hemilab(&["plan", "moving.toml", "--reference-dir", "ref"]);
    let text = stdout(&o);
    assert!(
        text.contains("references of camera 'orbit' on 'cornell-box': 4 (")
            && text.contains("): stored in ref, reused"),
        "{text}"
    );
    let line = text.lines().find(|l| l.starts_with("disk: ≈ ")).unwrap();
    assert!(line.contains("references none to build"), "{line}");
    // The job images and the records, within a factor of three of what the plan said.
    let mut written = 0u64;
    for e in std::fs::read_dir(t.path("out/images")).unwrap() {
        written += e.unwrap().metadata().unwrap().len();
    }
    for f in ["results.json", "results.csv"] {
        written += std::fs::metadata(t.path("out").join(f)).unwrap().len();
    }
    let said =
        bytes(&format!("≈ {} written", line.trim_start_matches("disk: ≈ ").split(" (").next().unwrap()));
    assert!((written as f64 / 3.0..=written as f64 * 3.0).contains(&said), "{said} vs {written}: {line}");
}

/// advise's progress lines (plain lines without a terminal) never run backwards under one label:
/// the timing protocol's second round once lengthened the sweep's bar, 80 % → 27 %.
#[test]
fn advise_progress_never_runs_backwards_under_one_label() {
    let t = Tmp::new("advise-progress");
    let args = [
        "advise",
        &scene("cornell-box.toml"),
        "--resolution",
        "32x24",
        "--rays",
        "16,256",
        "--only",
        "sine-cosine/fibonacci/rotation",
        "--reference-dir",
        "ref",
        "--threads",
        "1",
    ];
    let o = t.hemilab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut last: std::collections::HashMap<String, f64> = Default::default();
    for l in stderr(&o).lines() {
        let Some((label, rest)) = l.split_once(": ") else { continue };
        let Some(pct) = rest.split_once(" % after ").and_then(|(p, _)| p.parse::<f64>().ok()) else {
            continue;
        };
        let before = last.insert(label.to_string(), pct).unwrap_or(0.0);
        assert!(pct >= before, "'{label}' went from {before} % to {pct} %:\n{}", stderr(&o));
    }
}

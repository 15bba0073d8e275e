//! The extension point: `examples/external_sampler.rs` registers a sequence hemilab does not ship
//! (Hammersley) and runs the library's command line, so `run SPEC` measures it through `hemilab
//! run`'s own code path, named in the spec, in the results and on the report like a built-in one.
//! The plain binary refuses the same spec (the name is unknown to it), which shows it is the
//! registration that made the difference.

use crate::support::common::*;
use crate::support::examples::example;
use std::process::Command;

fn spec() -> String {
    format!(
        r#"name = "external"
scenes = ["{}"]
resolution = [24, 18]
replicates = 2
seed = 5

[reference]
rays = 64
replicates = 2

[[table]]
name = "t"
rays = [4, 16]
rows = [
  {{ distribution = "sine-cosine", sequence = "hammersley", seed_mode = "shift" }},
  {{ distribution = "sine-cosine", sequence = "fibonacci", seed_mode = "shift" }},
]
"#,
        scene("cornell-box.toml")
    )
}

#[test]
fn an_external_sampler_runs_through_hemilab_run_and_is_named_in_its_results() {
    let t = Tmp::new("external");
    let spec = t.spec("external.toml", &spec());

    let plain = t.run(&spec, "plain", "ref", &[]);
    let e = assert_error(&plain, &spec.display().to_string());
    assert!(e.contains("hammersley"), "the unknown sequence is named:\n{e}");
    assert!(!t.path("plain").exists(), "nothing written by the refused run");

    let o = Command::new(example("external_sampler"))
        .args(["run".as_ref(), spec.as_os_str()])
        .args(["--out", "out", "--reference-dir", "ref", "--quiet"])
        .current_dir(&*t)
        .output()
        .expect("run the example");
    assert!(o.status.success(), "external_sampler run failed:\n{}", stderr(&o));

    let out = t.path("out");
    let csv = std::fs::read_to_string(out.join("results.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "sequence").expect("a sequence column");
    let named = |s: &str| csv.lines().skip(1).filter(|l| l.split(',').nth(col) == Some(s)).count();
    assert_eq!(named("hammersley"), 4, "2 ray counts x 2 replicates of the new sequence:\n{csv}");
    assert_eq!(named("fibonacci"), 4, "{csv}");

    let records = records(&out);
    let ours: Vec<_> = records.iter().filter(|r| r.sequence == "hammersley").collect();
    assert_eq!(ours.len(), 4);
    for r in &ours {
        assert!(r.rmse.is_finite() && r.rmse > 0.0 && r.rmse < 0.5, "a measured error: {r:?}");
        let twin = records
            .iter()
            .find(|f| f.sequence == "fibonacci" && f.rays == r.rays && f.replicate == r.replicate)
            .expect("the lattice at the same rays and replicate");
        let (a, b) =
            (std::fs::read(out.join(&r.image)).unwrap(), std::fs::read(out.join(&twin.image)).unwrap());
        assert_ne!(a, b, "the new sequence renders its own image at {} rays", r.rays);
    }
    let report = std::fs::read_to_string(out.join("report.md")).expect("the run's report");
    assert!(report.contains("Hammersley"), "the report names the sequence by its label");
}

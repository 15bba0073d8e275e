//! `hemilab plan`: the summary first, the shard table, the references it would build, and an
//! estimate from a calibration on this machine that predicts the run's render CPU time within 2×
//! (checked against a real run: CPU time, which other work on a shared machine does not inflate;
//! the wall-time estimate multiplies it by the machine's measured load and is checked by hand).

use crate::support::common;

use common::*;

/// About a second of rendering on the Cornell box: 3 ray counts, 2 estimators, 2 replicates.
fn spec() -> String {
    format!(
        r#"name = "est"
scenes = ["{}"]
resolution = [64, 48]
replicates = 2
[reference]
rays = 256
replicates = 2
[[table]]
name = "t"
rays = [64, 256, 1024]
rows = [
  {{ distribution = "sine-cosine", sequence = "random" }},
  {{ distribution = "uniform", sequence = "fibonacci", seed_mode = "shift" }},
]
"#,
        scene("cornell-box.toml")
    )
}

/// The number after `key` in `text`, e.g. "renders 12 s CPU" → 12.
fn number_after(text: &str, key: &str) -> f64 {
    let at = text.find(key).unwrap_or_else(|| panic!("no '{key}' in:\n{text}")) + key.len();
    let num: String =
        text[at..].trim_start().chars().take_while(|c| c.is_ascii_digit() || *c == '.').collect();
    num.parse().unwrap_or_else(|_| panic!("no number after '{key}' in:\n{text}"))
}

#[test]
fn estimate_predicts_the_runs_render_time() {
    let t = Tmp::new("plan-estimate");
    t.spec("est.toml", &spec());
    let before = t.listing();
    let o = t.hemilab(&["plan", "est.toml", "--reference-dir", "ref"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(t.listing(), before, "plan renders into memory only and writes nothing");
    let text = stdout(&o);
    assert!(text.lines().next().unwrap().contains("12 jobs in 6 configurations"), "{text}");
    assert!(text.contains("reference 'cornell-box': must be built (2 x 256 rays)"), "{text}");
    assert!(text.contains("(--jobs lists the 12 jobs)"), "{text}");
    let calibration = number_after(&text, "calibration on this machine (");
    assert!(calibration > 0.0 && calibration < 1.0, "a fraction of a second of rendering: {text}");
    let predicted_cpu = number_after(&text, "(renders ");

    t.run_ok(&t.path("est.toml"), "out", "ref", &[]);
    let timing: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.path("out/timing.json")).unwrap()).unwrap();
    let measured_cpu = timing["session"]["timed_cpu_s"].as_f64().unwrap();
    let ratio = predicted_cpu / measured_cpu;
    assert!(
        (0.5..=2.0).contains(&ratio),
        "predicted {predicted_cpu} s, measured {measured_cpu} s of render CPU"
    );

    // With the reference in place it is reused, and the estimate drops the build.
    let o = t.hemilab(&["plan", "est.toml", "--reference-dir", "ref"]);
    assert!(stdout(&o).contains("reference 'cornell-box': stored in ref, reused"), "{}", stdout(&o));
    assert!(stdout(&o).contains("references none to build"), "{}", stdout(&o));
}

#[test]
fn shard_table_and_one_shards_jobs() {
    let t = Tmp::new("plan-shards");
    t.spec("est.toml", &spec());
    let o = t.hemilab(&["plan", "est.toml", "--shards", "3", "--reference-dir", "ref"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let rows: Vec<Vec<&str>> = text
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|f| f.first().is_some_and(|c| c.ends_with("/3")))
        .collect();
    assert_eq!(rows.len(), 3, "{text}");
    let jobs: usize = rows.iter().map(|r| r[1].parse::<usize>().unwrap()).sum();
    assert_eq!(jobs, 12, "{text}");
    assert!(rows.iter().all(|r| r[4] == "≈"), "every shard has an estimate: {text}");

    let o = t.hemilab(&["plan", "est.toml", "--shard", "1/3", "--jobs", "--reference-dir", "ref"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let first = text.lines().next().unwrap();
    assert!(first.contains("shard 1/3: ") && first.contains(&format!("{} jobs", rows[1][1])), "{text}");
    let listed = text.lines().skip_while(|l| !l.starts_with("jobs, in run order")).skip(2).count();
    assert_eq!(listed.to_string(), rows[1][1], "{text}");
    // A shard that does not exist is a usage error.
    let o = t.hemilab(&["plan", "est.toml", "--shard", "3/3"]);
    assert_eq!(o.status.code(), Some(2));
}

//! `hemilab advise` across runs, through the real binary on a tiny Cornell box: a rerun resumes
//! (renders nothing it has), a killed run's stage is resumed, `--from` re-analyses without
//! rendering, the output directory is replaced whole or refused, an impossible budget is refused in
//! seconds naming the minimum, and an independent `hemilab run` of what advise ships reproduces
//! the RMSE advise measured, within its stated σ.

use crate::advise::{advise, json, label, num};
use crate::support::common::{self, Tmp, scene};
use serde_json::Value;

fn from(t: &Tmp, dir: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["advise", "--from", dir, "--quiet", "--threads", "2"];
    args.extend(extra);
    t.hemilab(&args)
}

fn images(dir: &std::path::Path) -> usize {
    std::fs::read_dir(dir.join("images")).map_or(0, |d| d.count())
}

fn records(dir: &std::path::Path) -> usize {
    json(&dir.join("results.json")).as_array().unwrap().len()
}

fn answers(a: &Value) -> Vec<(String, u64, f64)> {
    a["recommendations"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| (label(&r["configuration"]), r["rays"].as_u64().unwrap(), num(&r["rmse"])))
        .collect()
}

#[test]
fn advise_resumes_and_reanalyses_without_rendering() {
    let t = Tmp::new("advise-resume");
    let o = advise(&t, &["--out", "out"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let out = t.path("out");
    let first = json(&out.join("advice.json"));
    let (n_images, n_records) = (images(&out), records(&out));
    assert!(n_images > 0 && first["jobs"]["rendered"].as_u64().unwrap() as usize == n_records);

    // The same again: every record is reused, the answers are the same numbers.
    let o = advise(&t, &["--out", "out"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    assert!(common::stdout(&o).contains("jobs: 0 rendered"), "{}", common::stdout(&o));
    assert_eq!(answers(&json(&out.join("advice.json"))), answers(&first));

    // A run killed before it replaced its output leaves its stage: the next run resumes from it.
    std::fs::rename(&out, t.path(".again.partial")).unwrap();
    let o = advise(&t, &["--out", "again"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    assert!(common::stdout(&o).contains("jobs: 0 rendered"), "{}", common::stdout(&o));
    assert!(!t.path(".again.partial").exists() && t.path("again/advice.json").is_file());
    let out = t.path("again");

    // --from at a new budget renders nothing; where the finalists were not measured it says so.
    let mid = num(&first["budgets_ms"][1]) * 1.07;
    let o = from(&t, "again", &["--budget-ms", &format!("{mid}")]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let a = json(&out.join("advice.json"));
    assert_eq!(a["jobs"]["rendered"], 0, "{}", common::stdout(&o));
    assert_eq!((images(&out), records(&out)), (n_images, n_records), "nothing new");
    let rec = &a["recommendations"][0];
    assert_eq!(rec["status"], "inside");
    if rec["measured"] == false {
        assert!(rec["note"].as_str().unwrap().contains("not measured"), "{}", rec["note"]);
        assert!(
            a["winner_map"]["budgets"].as_array().unwrap().is_empty() && !out.join("winner_map.png").exists()
        );
    }
    // … and at the first run's budgets it gives the first run's measured answers.
    let budgets: Vec<String> =
        first["budgets_ms"].as_array().unwrap().iter().map(|b| num(b).to_string()).collect();
    let o = from(&t, "again", &["--budget-ms", &budgets.join(","), "--out", "same"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let same = json(&t.path("same/advice.json"));
    assert_eq!(answers(&same), answers(&first));
    assert!(same["recommendations"].as_array().unwrap().iter().all(|r| r["measured"] == true));
    // Not quiet, --from says the resolution and why once (it rendered nothing to say it before).
    let o = t.hemilab(&["advise", "--from", "again", "--budget-ms", &budgets.join(","), "--out", "same"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let said = format!("{}{}", common::stdout(&o), common::stderr(&o));
    assert_eq!(said.lines().filter(|l| l.starts_with("resolution ")).count(), 1, "{said}");

    // Budgets outside every measured time: said so, not extrapolated; the earlier map is gone.
    let o = from(&t, "again", &["--budget-ms", "0.00001,100000"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let far = json(&out.join("advice.json"));
    let recs = far["recommendations"].as_array().unwrap();
    assert_eq!((recs[0]["status"].as_str(), recs[1]["status"].as_str()), (Some("below"), Some("above")));
    for rec in recs {
        assert!(rec["configuration"].is_null() && rec["gain_vs_paper_default"].is_null());
        assert!(rec["note"].as_str().unwrap().contains("measured range"), "{}", rec["note"]);
        assert_eq!(rec["outside"].as_array().unwrap().len(), 4);
    }
    assert!(!out.join("winner_map.png").exists(), "no budget to map, and the earlier map is gone");
    assert_eq!(images(&out), n_images, "the records and images stay: --from can answer again");
    assert!(far["setup"].as_str().unwrap().contains("stored reference"), "{}", far["setup"]);
}

#[test]
fn the_output_directory_is_replaced_whole_or_refused() {
    let t = Tmp::new("advise-outdir");
    std::fs::create_dir_all(t.path("mine")).unwrap();
    std::fs::write(t.path("mine/notes.txt"), "my own file").unwrap();
    let before = t.listing();
    let o = advise(&t, &["--out", "mine"]);
    assert_eq!(o.status.code(), Some(2), "{}", common::stderr(&o));
    assert!(common::stderr(&o).contains("sweep.json"), "{}", common::stderr(&o));
    assert_eq!(t.listing(), before, "nothing written, the user's file kept");
    // --from a directory that is not advise's.
    let o = from(&t, "mine", &[]);
    assert_eq!(o.status.code(), Some(2));
    assert!(common::stderr(&o).contains("sweep.json"), "{}", common::stderr(&o));
}

#[test]
fn an_impossible_budget_is_refused_in_seconds() {
    // Every default configuration, at the default resolution: the calibration, not the sweep.
    let t = Tmp::new("advise-impossible");
    let start = std::time::Instant::now();
    let o = t.hemilab(&[
        "advise",
        &scene("cornell-box.toml"),
        "--budget-ms",
        "0.001,5",
        "--reference-dir",
        "ref",
        "--out",
        "out",
        "--quiet",
    ]);
    let took = start.elapsed().as_secs_f64();
    let e = common::stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("--budget-ms 0.001") && e.contains("cheapest") && e.contains("from about"), "{e}");
    assert!(took <= 10.0, "refused after {took:.1} s");
    assert!(!t.path("out").exists() && !t.path("ref").exists() && !t.path(".out.partial").exists());
}

#[test]
fn an_independent_run_reproduces_what_advise_ships() {
    // What advise ships at each budget, rendered again by `hemilab run` with other seeds (seed 7:
    // neither the sweep's nor the finalists'), against the same reference: the mean MSE over 16
    // replicates agrees with advise's within 3 σ of the difference (both σ over replicates).
    let t = Tmp::new("advise-check");
    let o = advise(&t, &["--out", "out"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let a = json(&t.path("out/advice.json"));
    for (i, rec) in a["recommendations"].as_array().unwrap().iter().enumerate() {
        let c = &rec["configuration"];
        let spec = format!(
            "name = \"check{i}\"\nscenes = [\"{}\"]\nresolution = [20, 16]\nreplicates = 16\nseed = 7\n\n\
             [reference]\ndir = \"ref\"\n\n[[table]]\nname = \"shipped\"\nrays = [{}]\n\
             rows = [{{ distribution = \"{}\", sequence = \"{}\", seed_mode = \"{}\" }}]\n",
            scene("cornell-box.toml"),
            rec["rays"],
            c["distribution"].as_str().unwrap(),
            c["sequence"].as_str().unwrap(),
            c["seed_mode"].as_str().unwrap()
        );
        let path = t.spec(&format!("check{i}.toml"), &spec);
        t.run_ok(&path, &format!("check{i}"), "ref", &[]);
        let rs = common::records(&t.path(&format!("check{i}")));
        let mse: Vec<f64> = rs.iter().map(|r| r.rmse * r.rmse).collect();
        let n = mse.len() as f64;
        let m = mse.iter().sum::<f64>() / n;
        let sd = (mse.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let (rmse, se) = (m.sqrt(), sd / n.sqrt() / (2.0 * m.sqrt()));
        let (theirs, their_se) = (num(&rec["rmse"]), num(&rec["rmse_se"]));
        let z = (rmse - theirs) / se.hypot(their_se);
        assert!(
            z.abs() < 3.0,
            "budget {}: run {rmse} ± {se}, advise {theirs} ± {their_se}: {z:.1} σ",
            rec["budget_ms"]
        );
    }
}

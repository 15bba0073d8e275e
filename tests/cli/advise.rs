//! `hemilab advise` end to end on a tiny Cornell box: advice.json validates (its fields, and its
//! recommendations recomputed independently from the measured points it lists), the files it
//! names exist, budgets outside the measured times are said to be, and every bad input exits 2
//! with nothing written.

use crate::support::common;

use common::{Tmp, assert_error, scene};
use hemilab::metrics::STRUCTURED_RATIO;
use serde_json::Value;

const ONLY: &str = "sine-cosine/fibonacci/shift,sine-cosine/fibonacci/static,uniform/random/rotation";

fn advise(t: &Tmp, extra: &[&str]) -> std::process::Output {
    let mut args: Vec<String> =
        ["advise", &scene("cornell-box.toml"), "--resolution", "20x16", "--rays", "1,2,4,8"]
            .map(String::from)
            .to_vec();
    args.extend(
        ["--replicates", "3", "--only", ONLY, "--reference-dir", "ref", "--quiet", "--threads", "2"]
            .map(String::from),
    );
    args.extend(extra.iter().map(|s| s.to_string()));
    t.hemilab(&args)
}

fn json(path: &std::path::Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// Independently of `advice`: a configuration's mean MSE at `budget_ms`, from its listed points,
/// by log-log interpolation of each replicate's MSE between the two measured times around the
/// budget (times made non-decreasing by pooling, as documented); `None` outside its times.
fn interpolated_mse(points: &[Value], budget_ms: f64) -> Option<f64> {
    let mut lt: Vec<(f64, usize)> = Vec::new();
    for p in points {
        lt.push((num(&p["time_ms"]).ln(), 1));
        while lt.len() > 1 && lt[lt.len() - 2].0 > lt[lt.len() - 1].0 {
            let (b, nb) = lt.pop().unwrap();
            let (a, na) = lt.pop().unwrap();
            lt.push(((a * na as f64 + b * nb as f64) / (na + nb) as f64, na + nb));
        }
    }
    let t: Vec<f64> = lt.iter().flat_map(|&(m, n)| std::iter::repeat_n(m, n)).collect();
    let b = budget_ms.ln();
    if b < t[0] || b > *t.last().unwrap() {
        return None;
    }
    let i = t.iter().rposition(|&x| x <= b).unwrap().min(t.len() - 2);
    let w = if i + 1 == t.len() - 1 && b >= t[i + 1] { 1.0 } else { (b - t[i]) / (t[i + 1] - t[i]) };
    let (pa, pb) = (&points[i]["mse"], &points[i + 1]["mse"]);
    let reps = pa.as_array().unwrap().len();
    let geo = |x: f64, y: f64| {
        if w <= 0.0 {
            x
        } else if w >= 1.0 {
            y
        } else {
            (x.ln() * (1.0 - w) + y.ln() * w).exp()
        }
    };
    Some((0..reps).map(|r| geo(num(&pa[r]), num(&pb[r]))).sum::<f64>() / reps as f64)
}

#[test]
fn advice_json_validates_and_its_recommendations_recompute() {
    let t = Tmp::new("advise-ok");
    let o = advise(&t, &["--out", "out"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let out = t.path("out");
    for f in [
        "advice.json",
        "advice.md",
        "index.html",
        "error_time.png",
        "lowpass_time.png",
        "winner_map.png",
        "results.csv",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    for f in hemilab::report::referenced_files(&html) {
        assert!(out.join(&f).is_file(), "index.html links {f}, which is not there");
    }
    let stdout = common::stdout(&o);
    assert!(stdout.contains("ms per image: ship "), "{stdout}");

    let a = json(&out.join("advice.json"));
    assert_eq!(a["resolution"], serde_json::json!([20, 16]));
    assert_eq!(a["paper_default"]["sequence"], "random");
    assert!(a["time_per_image"].as_str().unwrap().contains("one thread"));
    assert_eq!(a["rays"], serde_json::json!([1, 2, 4, 8]));
    let configs = a["configurations"].as_array().unwrap();
    assert_eq!(configs.len(), 4, "three asked for and the paper default");
    assert!(a["budgets_chosen_by_advise"].as_bool().unwrap());
    let recs = a["recommendations"].as_array().unwrap();
    assert_eq!(recs.len(), a["budgets_ms"].as_array().unwrap().len());
    assert_eq!(recs.len(), 3);
    let label = |c: &Value| {
        format!(
            "{}/{}/{}",
            c["distribution"].as_str().unwrap(),
            c["sequence"].as_str().unwrap(),
            c["seed_mode"].as_str().unwrap()
        )
    };
    for rec in recs {
        let budget = num(&rec["budget_ms"]);
        assert_eq!(rec["status"], "inside", "the chosen budgets lie in the default's measured range");
        let best = label(&rec["configuration"]);
        for part in best.split('/') {
            assert!(!part.is_empty());
        }
        assert!(rec["rays"].as_u64().unwrap() >= 1);
        let rays = num(&rec["rays_interpolated"]);
        assert!((1.0..=8.0).contains(&rays) && rec["rays"].as_u64().unwrap() == rays.floor().max(1.0) as u64);
        // Recompute every configuration at this budget from the listed points.
        let mut at: Vec<(String, f64)> = configs
            .iter()
            .filter_map(|c| {
                Some((label(&c["configuration"]), interpolated_mse(c["points"].as_array().unwrap(), budget)?))
            })
            .collect();
        at.sort_by(|x, y| x.1.total_cmp(&y.1));
        // The ranking recomputes; the recommendation is its best configuration whose error is not
        // structured (low-frequency ratio ≤ STRUCTURED_RATIO), or its best when every one is.
        let ranking = rec["ranking"].as_array().unwrap();
        assert_eq!(label(&ranking[0]["configuration"]), at[0].0, "ranking at {budget} ms: {at:?}");
        let structured = |e: &Value| num(&e["lowfreq_ratio"]) > STRUCTURED_RATIO;
        let shipped = ranking.iter().find(|e| !structured(e)).unwrap_or(&ranking[0]);
        assert_eq!(label(&shipped["configuration"]), best, "the recommendation at {budget} ms: {at:?}");
        assert_eq!(rec["structured"].as_bool().unwrap(), structured(shipped));
        assert!(rec["structured_rule"].as_str().unwrap().contains("lowfreq_ratio"));
        assert!(ranking.iter().all(|e| num(&e["whiteness_z"]).is_finite()), "z is still reported");
        let mse = at.iter().find(|x| x.0 == best).unwrap().1;
        let rmse = num(&rec["rmse"]);
        assert!((rmse - mse.sqrt()).abs() < 1e-9 * rmse, "{rmse} vs {}", mse.sqrt());
        assert!(num(&rec["rmse_se"]) >= 0.0 && num(&rec["lowpass_rmse"]) > 0.0);
        if best != at[0].0 {
            assert_eq!(label(&rec["least_rmse_structured"]["configuration"]), at[0].0);
            assert!(structured(&ranking[0]));
        }
        let default =
            at.iter().find(|x| x.0 == "sine-cosine/random/rotation").expect("the default is inside");
        let gain = num(&rec["gain_vs_paper_default"]);
        assert!((gain - default.1 / mse).abs() < 1e-9 * gain, "gain = MSE ratio at equal time: {gain}");
        assert!(num(&rec["gain_vs_paper_default_se"]) >= 0.0);
        // The ranking is sorted, lists every configuration inside, and the default against itself is 1 ± 0.
        assert_eq!(ranking.len(), at.len());
        let rmses: Vec<f64> = ranking.iter().map(|e| num(&e["rmse"])).collect();
        assert!(rmses.windows(2).all(|w| w[0] <= w[1]), "{rmses:?}");
        let own =
            ranking.iter().find(|e| label(&e["configuration"]) == "sine-cosine/random/rotation").unwrap();
        assert_eq!((num(&own["gain_vs_paper_default"]), num(&own["gain_vs_paper_default_se"])), (1.0, 0.0));
        assert_eq!(rec["paper_default"]["gain_vs_paper_default"], 1.0);
        assert!(rec["best_lowpass"]["lowpass_rmse"].as_f64().unwrap() <= num(&rec["lowpass_rmse"]));
    }
    let maps = a["winner_map"]["budgets"].as_array().unwrap();
    assert_eq!(a["winner_map"]["file"], "winner_map.png");
    assert!(a["winner_map"]["significance"].as_str().unwrap().contains("paired"));
    for m in maps {
        let won: u64 = m["wins"].as_array().unwrap().iter().map(|w| w["pixels"].as_u64().unwrap()).sum();
        assert_eq!(won + m["unresolved_pixels"].as_u64().unwrap(), m["covered_pixels"].as_u64().unwrap());
    }
    // A reference was built in the reference directory (none is stored at 20x16).
    assert!(std::fs::read_dir(t.path("ref")).unwrap().count() >= 2);

    // Budgets outside every measured time: said so, not extrapolated; the reference is reused.
    std::fs::create_dir_all(t.path("far")).unwrap();
    std::fs::write(t.path("far/winner_map.png"), "an earlier map").unwrap();
    let o = advise(&t, &["--out", "far", "--budget-ms", "0.00001,100000"]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let far = json(&t.path("far/advice.json"));
    let recs = far["recommendations"].as_array().unwrap();
    assert_eq!((recs[0]["status"].as_str(), recs[1]["status"].as_str()), (Some("below"), Some("above")));
    for rec in recs {
        assert!(rec["configuration"].is_null() && rec["gain_vs_paper_default"].is_null());
        assert!(rec["note"].as_str().unwrap().contains("measured range"), "{}", rec["note"]);
        assert_eq!(rec["outside"].as_array().unwrap().len(), 4);
    }
    assert!(!t.path("far/winner_map.png").exists(), "no budget to map, and the earlier map is gone");
    assert!(far["setup"].as_str().unwrap().contains("stored reference"), "{}", far["setup"]);
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let t = Tmp::new("advise-bad");
    std::fs::write(t.path("bad.toml"), "mesh = \"none.obj\"\nresolution = [8, 8]\n").unwrap();
    std::fs::write(t.path("file"), "not a directory").unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["--rays".into(), "8".into()], "--rays"),
        (vec!["--rays".into(), "0,4".into()], "--rays"),
        (vec!["--budget-ms".into(), "0".into()], "--budget-ms"),
        (vec!["--budget-ms".into(), "fast".into()], "--budget-ms"),
        (vec!["--only".into(), "sine-cosine/halton/*".into()], "--only"),
        (vec!["--only".into(), "*/random/static".into()], "--only"),
        (vec!["--resolution".into(), "0x16".into()], "--resolution"),
        (vec!["--replicates".into(), "1".into()], "--replicates"),
        (vec!["--out".into(), "file/sub".into()], "file/sub"),
    ];
    let before = t.listing();
    for (extra, what) in cases {
        let mut args: Vec<String> =
            ["advise", &scene("cornell-box.toml"), "--reference-dir", "ref", "--quiet"]
                .map(String::from)
                .to_vec();
        if !extra.contains(&"--out".to_string()) {
            args.extend(["--out".to_string(), "out".to_string()]);
        }
        args.extend(extra.iter().cloned());
        let o = t.hemilab(&args);
        let e = common::stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {e}");
        assert!(e.contains(what), "{extra:?}: the message names {what}: {e}");
        assert!(!e.contains("panicked"), "{e}");
        assert_eq!(t.listing(), before, "{extra:?} wrote something");
    }
    for (scene, what) in [("missing.toml", "missing.toml"), ("bad.toml", "bad.toml")] {
        let o = t.hemilab(&["advise", scene, "--out", "out", "--reference-dir", "ref", "--quiet"]);
        assert_error(&o, what);
        assert_eq!(t.listing(), before, "{scene} wrote something");
    }
}

#[test]
fn the_committed_kitchen_reference_is_reused_by_default() {
    // Without --resolution: the largest stored reference of the kitchen with at most 64x48 pixels,
    // i.e. the committed one of experiments/claims.toml, found by its manifest (read only here).
    let t = Tmp::new("advise-kitchen");
    let reference = format!("{}/reference", env!("CARGO_MANIFEST_DIR"));
    // Lock files (`<stem>.lock`, git-ignored) are `reference::obtain`'s; anything else would be new.
    let files = || {
        let mut v: Vec<String> = std::fs::read_dir(&reference)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| !n.ends_with(".lock"))
            .collect();
        v.sort();
        v
    };
    let before = files();
    let o = t.hemilab(&[
        "advise",
        &scene("kitchen.toml"),
        "--rays",
        "2,4",
        "--replicates",
        "2",
        "--only",
        "sine-cosine/fibonacci/shift",
        "--budget-ms",
        "1000",
        "--reference-dir",
        &reference,
        "--out",
        "out",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let a = json(&t.path("out/advice.json"));
    assert_eq!(a["resolution"], serde_json::json!([64, 48]));
    let setup = a["setup"].as_str().unwrap();
    assert!(setup.contains("stored reference") && setup.contains("kitchen-64x48-fb00a993.exr"), "{setup}");
    assert_eq!(a["recommendations"][0]["status"], "above", "1 s is beyond 4 rays at 64x48");
    assert_eq!(files(), before, "nothing added to reference/");
}

/// Without --reference-dir, from another directory, the shipped kitchen's committed reference is
/// found (the repository's reference/ beside scenes/), and nothing is written beside the scene.
#[test]
fn committed_reference_is_found_from_anywhere() {
    let t = Tmp::new("advise-anywhere");
    let o = t.hemilab(&[
        "advise",
        &scene("kitchen.toml"),
        "--only",
        "sine-cosine/fibonacci/shift",
        "--rays",
        "1,2",
        "--replicates",
        "2",
        "--out",
        "x",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let a = json(&t.path("x/advice.json"));
    let file = a["reference"]["file"].as_str().unwrap();
    assert!(file.contains("reference/kitchen-64x48-"), "{file}");
    assert!(a["setup"].as_str().unwrap().contains("stored reference"), "{}", a["setup"]);
    let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/reference");
    assert!(!scenes.exists(), "advise wrote {}", scenes.display());
    assert!(!t.path("reference").exists(), "advise wrote into the current directory");
}

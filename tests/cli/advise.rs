//! `hemilab advise` end to end on a tiny Cornell box: advice.json validates (its fields; each
//! answer, its gain and every σ recomputed independently from the per-replicate values it lists,
//! under the error model it states; the sweep's rankings from its points), the files it names
//! exist, and every bad input exits 2 with nothing written. Resuming, `--from`, refusals and an
//! independent check of what is shipped: `advise_runs.rs`.

use crate::support::common;

use common::{Tmp, assert_error, scene};
use serde_json::Value;

const ONLY: &str = "sine-cosine/fibonacci/shift,sine-cosine/fibonacci/static,uniform/random/rotation";

pub fn advise(t: &Tmp, extra: &[&str]) -> std::process::Output {
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

pub fn json(path: &std::path::Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

pub fn num(v: &Value) -> f64 {
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

fn nums(v: &Value) -> Vec<f64> {
    v.as_array().unwrap_or_else(|| panic!("not a list: {v}")).iter().map(num).collect()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

pub fn label(c: &Value) -> String {
    format!(
        "{}/{}/{}",
        c["distribution"].as_str().unwrap(),
        c["sequence"].as_str().unwrap(),
        c["seed_mode"].as_str().unwrap()
    )
}

/// Independently of `compare::model`: the gain of `better` over `base` (two finalist entries) and
/// its σ as advice.json's `error_model` states it — paired replicate part plus (k₁ − k₂)² σ_u² +
/// k₁² σ_e₁² + k₂² σ_e₂²; 1 ± 0 for a configuration against itself.
fn gain_and_sigma(base: &Value, better: &Value, run_factor: f64) -> (f64, f64) {
    if label(&base["configuration"]) == label(&better["configuration"]) {
        return (1.0, 0.0); // the same measurement
    }
    let (a, b) = (nums(&base["mse"]), nums(&better["mse"]));
    assert_eq!(base["replicates"], better["replicates"], "paired over the same replicates");
    let n = a.len() as f64;
    let (ma, mb) = (mean(&a), mean(&b));
    let cov = |x: &[f64], mx: f64, y: &[f64], my: f64| {
        x.iter().zip(y).map(|(p, q)| (p - mx) * (q - my)).sum::<f64>() / (n - 1.0)
    };
    let rep = (cov(&a, ma, &a, ma) / (ma * ma) + cov(&b, mb, &b, mb) / (mb * mb)
        - 2.0 * cov(&a, ma, &b, mb) / (ma * mb))
        .max(0.0)
        / n;
    let (ka, kb) = (num(&base["slope"]), num(&better["slope"]));
    let (ea, eb) = (num(&base["time_sigma_ln"]), num(&better["time_sigma_ln"]));
    let timing = ((ka - kb) * run_factor).powi(2) + (ka * ea).powi(2) + (kb * eb).powi(2);
    let g = ma / mb;
    (g, g * (rep + timing).sqrt())
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-12)
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
        "results.json",
        "sweep.json",
        "timing.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    for f in hemilab::report::referenced_files(&html) {
        assert!(out.join(&f).is_file(), "index.html links {f}, which is not there");
    }
    let stdout = common::stdout(&o);
    assert!(stdout.contains("ms per image: ship ") && stdout.contains(" 0 reused"), "{stdout}");
    assert!(!t.path(".out.partial").exists(), "the stage became the output");

    let a = json(&out.join("advice.json"));
    assert_eq!(a["resolution"], serde_json::json!([20, 16]));
    assert_eq!(a["paper_default"]["sequence"], "random");
    assert!(a["time_per_image"].as_str().unwrap().contains("one thread"));
    assert_eq!(a["rays"], serde_json::json!([1, 2, 4, 8]));
    let configs = a["configurations"].as_array().unwrap();
    assert_eq!(configs.len(), 4, "three asked for and the paper default");
    assert!(a["budgets_chosen_by_advise"].as_bool().unwrap());
    let run_factor = num(&a["error_model"]["run_factor_sigma_ln"]);
    assert!(run_factor > 0.0 && a["error_model"]["text"].as_str().unwrap().contains("1 σ"));
    let threshold = num(&a["structure"]["threshold"]);
    assert_eq!(a["structure"]["measure"], "lowfreq_ratio");
    let replicates = a["finalists"]["replicates"].as_u64().unwrap() as usize;
    assert_eq!(replicates, 24, "the finalists' replicates: the sweep's 3, 24 at least");
    // Every point lists each replicate's structure value beside its MSE.
    for c in configs {
        for p in c["points"].as_array().unwrap() {
            assert_eq!(nums(&p["structure"]).len(), nums(&p["mse"]).len());
            assert!(num(&p["time_sigma_ms"]) > 0.0);
        }
    }
    let recs = a["recommendations"].as_array().unwrap();
    assert_eq!(recs.len(), a["budgets_ms"].as_array().unwrap().len());
    assert_eq!(recs.len(), 3);
    for rec in recs {
        let budget = num(&rec["budget_ms"]);
        assert_eq!(rec["status"], "inside", "the chosen budgets lie in the default's measured range");
        assert_eq!(rec["measured"], true, "{budget} ms: measured at the count it names");
        // Every finalist was measured at an integer count the budget fits, with its own replicates.
        let finalists = rec["finalists"].as_array().unwrap();
        // The paper default is always a finalist (the budgets lie inside its measured times); how
        // many of the other three are depends on whether the budget lies inside their measured
        // times, which a loaded machine moves: at least one of them.
        assert!(
            finalists.len() >= 2
                && finalists.iter().any(|f| label(&f["configuration"]) == "sine-cosine/random/rotation"),
            "{budget} ms: {} finalists",
            finalists.len()
        );
        for f in finalists {
            assert_eq!(f["measured"], true);
            let rays = f["rays"].as_u64().unwrap() as f64;
            assert!(rays >= 1.0 && rays <= num(&f["rays_interpolated"]).floor().max(1.0), "{f}");
            assert_eq!(nums(&f["mse"]).len(), replicates);
            assert!(
                num(&f["time_ms"]) > 0.0
                    && num(&f["time_sigma_ms"]) > 0.0
                    && f["timings"].as_u64().unwrap() >= replicates as u64
            );
            assert!(f["fits_budget"].is_boolean());
            let mse = nums(&f["mse"]);
            let rmse = mean(&mse).sqrt();
            assert!(close(num(&f["rmse"]), rmse), "{f}");
            // At the ray count it was measured at, an RMSE's σ is the replicates' (delta method).
            let sd =
                (mse.iter().map(|x| (x - mean(&mse)).powi(2)).sum::<f64>() / (mse.len() - 1) as f64).sqrt();
            assert!(close(num(&f["rmse_se"]), sd / (mse.len() as f64).sqrt() / (2.0 * rmse)), "{f}");
            let z = mean(&nums(&f["structure"]));
            assert!(close(num(&f["structure_mean"]), z) && f["structured"] == (z > threshold));
        }
        // The answer recomputed: the least mean MSE among the finalists whose error is not
        // structured (their per-replicate structure values), else the least of all.
        let by_mse = |f: &&Value| mean(&nums(&f["mse"]));
        let mut sorted: Vec<&Value> = finalists.iter().collect();
        sorted.sort_by(|x, y| by_mse(x).total_cmp(&by_mse(y)));
        let unstructured = |f: &&&Value| mean(&nums(&f["structure"])) <= threshold;
        let best = *sorted.iter().find(unstructured).unwrap_or(&sorted[0]);
        assert_eq!(label(&rec["configuration"]), label(&best["configuration"]), "at {budget} ms");
        assert_eq!(rec["rays"], best["rays"]);
        assert!(close(num(&rec["rmse"]), by_mse(&best).sqrt()));
        assert_eq!(rec["structured"].as_bool().unwrap(), mean(&nums(&best["structure"])) > threshold);
        if label(&sorted[0]["configuration"]) != label(&best["configuration"]) {
            assert_eq!(
                label(&rec["least_rmse_structured"]["configuration"]),
                label(&sorted[0]["configuration"])
            );
        }
        // The gain and its σ under the stated model, and the runner-up's margin in the same σ.
        let default =
            finalists.iter().find(|f| label(&f["configuration"]) == "sine-cosine/random/rotation").unwrap();
        let (g, sigma) = gain_and_sigma(default, best, run_factor);
        assert!(close(num(&rec["gain_vs_paper_default"]), g), "{g} vs {}", rec["gain_vs_paper_default"]);
        assert!(
            close(num(&rec["gain_vs_paper_default_se"]), sigma),
            "{sigma} vs {}",
            rec["gain_vs_paper_default_se"]
        );
        let parts = num(&rec["gain_se_replicates"]).hypot(num(&rec["gain_se_timing"]));
        assert!(close(parts, sigma));
        if let Some(second) = sorted
            .iter()
            .filter(unstructured)
            .find(|f| label(&f["configuration"]) != label(&best["configuration"]))
        {
            assert_eq!(label(&rec["runner_up"]["configuration"]), label(&second["configuration"]));
            let (g2, s2) = gain_and_sigma(second, best, run_factor);
            let z = num(&rec["runner_up"]["sigma_behind_recommended"]);
            assert!(close(z, g2.ln() / (s2 / g2)), "margin {z} vs {}", g2.ln() / (s2 / g2));
        }
        let own = recs
            .iter()
            .flat_map(|r| r["finalists"].as_array().unwrap())
            .find(|f| label(&f["configuration"]) == "sine-cosine/random/rotation")
            .unwrap();
        assert_eq!((num(&own["gain_vs_paper_default"]), num(&own["gain_vs_paper_default_se"])), (1.0, 0.0));

        // The sweep's ranking recomputes from the listed points (interpolation), sorted.
        let mut at: Vec<(String, f64)> = configs
            .iter()
            .filter_map(|c| {
                Some((label(&c["configuration"]), interpolated_mse(c["points"].as_array().unwrap(), budget)?))
            })
            .collect();
        at.sort_by(|x, y| x.1.total_cmp(&y.1));
        let ranking = rec["ranking"].as_array().unwrap();
        assert_eq!(ranking.len(), at.len());
        for (e, (name, mse)) in ranking.iter().zip(&at) {
            assert_eq!(&label(&e["configuration"]), name, "ranking at {budget} ms: {at:?}");
            assert!(close(num(&e["rmse"]), mse.sqrt()));
            assert_eq!(e["rays"].as_u64().unwrap() as f64, num(&e["rays_interpolated"]).floor().max(1.0));
        }
    }
    let maps = a["winner_map"]["budgets"].as_array().unwrap();
    assert_eq!(a["winner_map"]["file"], "winner_map.png");
    assert!(a["winner_map"]["significance"].as_str().unwrap().contains("Benjamini-Hochberg"));
    assert_eq!(maps.len(), 3, "every measured budget has a map");
    for m in maps {
        let won: u64 = m["wins"].as_array().unwrap().iter().map(|w| w["pixels"].as_u64().unwrap()).sum();
        assert_eq!(won + m["unresolved_pixels"].as_u64().unwrap(), m["covered_pixels"].as_u64().unwrap());
    }
    // A reference was built in the reference directory (none is stored at 20x16).
    assert!(std::fs::read_dir(t.path("ref")).unwrap().count() >= 2);
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
        (vec!["--only".into(), "sine-cosine/hammersley/*".into()], "--only"),
        (vec!["--only".into(), "*/random/static".into()], "--only"),
        (vec!["--resolution".into(), "0x16".into()], "--resolution"),
        (vec!["--replicates".into(), "1".into()], "--replicates"),
        (vec!["--out".into(), "file/sub".into()], "file/sub"),
        (vec!["--pipeline".into(), "ema2+atrous".into()], "--pipeline"),
        (vec!["--pipeline".into(), "atrous".into(), "--frames".into(), "4".into()], "--frames"),
        (vec!["--frames".into(), "0".into()], "--frames"),
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

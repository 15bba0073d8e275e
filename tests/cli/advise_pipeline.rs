//! `hemilab advise --pipeline P --frames K`: advice for the image after a real-time pipeline. The
//! sweep's records are real-time records at frame K alone (results.csv says which pipeline and
//! frame), advice.json names the pipeline, and the times advise ranks by are one frame's: the
//! record's time over its K frames.

use crate::support::common;

use super::advise::{json, num};
use common::{Tmp, scene};

const ONLY: &str =
    "sine-cosine/fibonacci/rotation,sine-cosine/random/blue-noise,sine-cosine/fibonacci/static";

fn advise(t: &Tmp, pipeline: &str, frames: &str) -> std::process::Output {
    let mut args: Vec<String> =
        ["advise", &scene("cornell-box.toml"), "--resolution", "20x16", "--rays", "1,2"]
            .map(String::from)
            .to_vec();
    args.extend(
        ["--replicates", "2", "--only", ONLY, "--reference-dir", "ref", "--quiet", "--threads", "2"]
            .map(String::from),
    );
    args.extend(["--pipeline", pipeline, "--frames", frames, "--out", "out"].map(String::from));
    t.hemilab(&args)
}

#[test]
fn advise_ranks_the_image_after_the_pipeline_at_one_frames_time() {
    let t = Tmp::new("advise-pipeline");
    let o = advise(&t, "ema0.1+atrous", "4");
    assert!(o.status.success(), "{}", common::stderr(&o));
    let out = t.path("out");
    let a = json(&out.join("advice.json"));
    assert_eq!(a["pipeline"], "ema0.1+atrous");
    assert_eq!(a["frames"], 4);
    assert!(a["setup"].as_str().unwrap().contains("after ema0.1+atrous at frame 4"), "{}", a["setup"]);
    let records =
        hemilab::results::from_json(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert!(!records.is_empty());
    for r in &records {
        assert_eq!(
            (r.pipeline.as_str(), r.frame, r.schedule.as_str()),
            ("ema0.1+atrous", 4, "independent"),
            "{r:?}"
        );
        assert!(r.rmse.is_finite() && r.rmse > 0.0);
    }
    // Each stored record renders 4 frames; what advise ranks is the time of one.
    let ranked = hemilab::advice::pipeline::as_ranked(&records).unwrap();
    for (r, k) in records.iter().zip(&ranked) {
        assert!(k.is_single_frame());
        assert_eq!((k.rmse, k.rays), (r.rmse, r.rays));
        assert!((k.time_s * 4.0 - r.time_s).abs() <= 1e-12 * r.time_s, "{} vs {}", k.time_s, r.time_s);
        assert_eq!(k.rays_cast * 4, r.rays_cast);
        assert!(k.lowfreq_ratio.is_nan(), "after a spatial filter the structure measure is not read");
    }
    // An accumulating pipeline sweeps no static seed (its error repeats every frame), and says why.
    assert!(records.iter().all(|r| r.seed_mode != "static"), "{records:?}");
    let page = std::fs::read_to_string(out.join("advice.md")).unwrap();
    assert!(page.contains(hemilab::advice::REPEATING_ERROR), "{page}");
    assert!(page.contains(
        "hemilab advise: cornell-box at 20x16 after ema0.1+atrous at frame 4 (budgets in ms per frame)"
    ));
    // The budgets an engine has: rays per pixel per frame, no ms budget unless asked for.
    assert!(a["budgets_ms"].as_array().unwrap().is_empty(), "{}", a["budgets_ms"]);
    let per_ray = a["ray_budgets"].as_array().unwrap();
    assert_eq!(
        per_ray.iter().map(|x| x["rays_per_pixel_per_frame"].as_u64().unwrap()).collect::<Vec<_>>(),
        [1, 2]
    );
    for x in per_ray {
        let ranking = x["ranking"].as_array().unwrap();
        // The paper's default and the two --only rows not static (the static one is not swept).
        assert_eq!(ranking.len(), 3, "{x}");
        assert_eq!(x["recommended"], ranking[0]["configuration"]);
        assert!(num(&ranking[0]["rmse"]) <= num(&ranking[1]["rmse"]));
        assert!(x["near_ties"].as_array().unwrap().contains(&ranking[0]["configuration"]));
        let rays = x["rays_per_pixel_per_frame"].as_u64().unwrap() as u32;
        for e in ranking {
            // The RMSE is √ of the mean of the replicates' MSE; the time one frame's, per record.
            let mse: Vec<f64> = e["mse"].as_array().unwrap().iter().map(|m| num(&m["mse"])).collect();
            assert_eq!(mse.len(), 2);
            let rmse = (mse.iter().sum::<f64>() / 2.0).sqrt();
            assert!((num(&e["rmse"]) - rmse).abs() <= 1e-12 * rmse, "{e}");
            assert!(num(&e["sampler_ns_per_point"]) > 0.0, "{e}");
            let mine: Vec<&hemilab::results::JobResult> = ranked
                .iter()
                .filter(|r| {
                    r.rays == rays
                        && format!("{}/{}/{}", r.distribution, r.sequence, r.seed_mode)
                            == super::advise::label(&e["configuration"])
                })
                .collect();
            assert_eq!(mine.len(), 2, "{e}");
            let mut t: Vec<f64> = mine.iter().map(|r| r.time_s * 1e3).collect();
            t.sort_by(f64::total_cmp);
            assert!((num(&e["time_per_frame_ms"]) - (t[0] + t[1]) / 2.0).abs() <= 1e-9, "{e} vs {t:?}");
        }
    }
    let text = common::stdout(&o);
    assert!(
        text.lines()
            .any(|l| l.starts_with("At 1 ray per pixel per frame after ema0.1+atrous at frame 4: ship ")),
        "{text}"
    );

    // Asked for ms budgets, it answers them too, per frame.
    let o = t.hemilab(&{
        let mut v: Vec<String> =
            ["advise", &scene("cornell-box.toml"), "--resolution", "20x16", "--rays", "1,2"]
                .map(String::from)
                .to_vec();
        v.extend(
            ["--replicates", "2", "--only", ONLY, "--reference-dir", "ref", "--quiet", "--threads", "2"]
                .map(String::from),
        );
        v.extend(["--pipeline", "ema0.1+atrous", "--frames", "4", "--out", "out"].map(String::from));
        let b = ranked.iter().map(|r| r.time_s).fold(0.0, f64::max) * 1e3 * 0.9;
        v.extend(["--budget-ms".to_string(), format!("{b}")]);
        v
    });
    assert!(o.status.success(), "{}", common::stderr(&o));
    let a = json(&out.join("advice.json"));
    assert_eq!(a["budgets_ms"].as_array().unwrap().len(), 1, "{}", a["budgets_ms"]);
    assert!(common::stdout(&o).contains(" ms per frame: "), "{}", common::stdout(&o));
}

#[test]
fn a_spatial_pipeline_alone_ranks_frame_one() {
    let t = Tmp::new("advise-atrous");
    let o = advise(&t, "atrous", "1");
    assert!(o.status.success(), "{}", common::stderr(&o));
    let records =
        hemilab::results::from_json(&std::fs::read_to_string(t.path("out/results.json")).unwrap()).unwrap();
    assert!(records.iter().all(|r| r.pipeline == "atrous" && r.frame == 1), "{records:?}");
    // A spatial filter alone accumulates nothing: the static seed is swept.
    assert!(records.iter().any(|r| r.seed_mode == "static"), "{records:?}");
    let a = json(&t.path("out/advice.json"));
    assert_eq!((a["pipeline"].as_str(), a["frames"].as_u64()), (Some("atrous"), Some(1)));
}

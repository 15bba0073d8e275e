//! `hemilab advise --pipeline P --frames K`: advice for the image after a real-time pipeline. The
//! sweep's records are real-time records at frame K alone (results.csv says which pipeline and
//! frame), advice.json names the pipeline, and the times advise ranks by are one frame's: the
//! record's time over its K frames.

use crate::support::common;

use super::advise::{json, num};
use common::{Tmp, scene};

const ONLY: &str = "sine-cosine/fibonacci/rotation,sine-cosine/random/blue-noise";

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
    // The answers' times are on that per-frame scale: below the slowest stored record's.
    let slowest = records.iter().map(|r| r.time_s).fold(0.0, f64::max);
    for b in a["budgets_ms"].as_array().unwrap() {
        assert!(num(b) * 1e-3 < slowest, "budget {b} ms against the slowest record's {slowest} s");
    }
}

#[test]
fn a_spatial_pipeline_alone_ranks_frame_one() {
    let t = Tmp::new("advise-atrous");
    let o = advise(&t, "atrous", "1");
    assert!(o.status.success(), "{}", common::stderr(&o));
    let records =
        hemilab::results::from_json(&std::fs::read_to_string(t.path("out/results.json")).unwrap()).unwrap();
    assert!(records.iter().all(|r| r.pipeline == "atrous" && r.frame == 1), "{records:?}");
    let a = json(&t.path("out/advice.json"));
    assert_eq!((a["pipeline"].as_str(), a["frames"].as_u64()), (Some("atrous"), Some(1)));
}

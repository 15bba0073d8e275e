//! `hemilab advise --pipeline P --frames K`: advice for the image after a real-time pipeline, per
//! ray budget and camera. The sweep's records are real-time records at frame K alone (results.csv
//! says which pipeline, frame, schedule and camera), each configuration seen by the scene's still
//! camera and a moving, jittered one, under both schedules where the schedule changes its points
//! (STBN within its 32-frame cycle is swept once), the answer names the RMSE and FLIP winners with
//! the winner's flicker and bias/noise split, the times advise ranks by are one frame's, and the
//! page shows the final frames and the comparison viewer. The user's denoiser runs in the loop.

use crate::support::common;
use crate::support::examples::example;

use super::advise::{json, label, num};
use common::{Tmp, scene};
use serde_json::Value;

const ONLY: &str = "sine-cosine/fibonacci/rotation,sine-cosine/random/blue-noise,sine-cosine/fibonacci/static,\
                    sine-cosine/random/stbn";

fn args(pipeline: &str, frames: &str, only: &str, extra: &[&str]) -> Vec<String> {
    let mut args: Vec<String> =
        ["advise", &scene("cornell-box.toml"), "--resolution", "20x16", "--rays", "1,2"]
            .map(String::from)
            .to_vec();
    args.extend(
        ["--replicates", "2", "--only", only, "--reference-dir", "ref", "--quiet", "--threads", "2"]
            .map(String::from),
    );
    args.extend(["--pipeline", pipeline, "--frames", frames, "--out", "out"].map(String::from));
    args.extend(extra.iter().map(|s| s.to_string()));
    args
}

fn advise(t: &Tmp, pipeline: &str, frames: &str) -> std::process::Output {
    t.hemilab(&args(pipeline, frames, ONLY, &[]))
}

/// "d/s/m@schedule" of a ranking entry or a near-tie.
fn candidate(e: &Value) -> String {
    format!("{}@{}", label(&e["configuration"]), e["schedule"].as_str().unwrap())
}

#[test]
fn advise_ranks_each_camera_and_schedule_after_the_pipeline_at_one_frames_time() {
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
        assert_eq!((r.pipeline.as_str(), r.frame), ("ema0.1+atrous", 4), "{r:?}");
        assert!(r.rmse.is_finite() && r.rmse > 0.0);
    }
    // Every configuration by both cameras; under both schedules, but STBN, whose two schedules
    // draw the same points over its 32-frame cycle, once.
    let views = |mode: &str| {
        let mut v: Vec<(String, String)> = records
            .iter()
            .filter(|r| r.seed_mode == mode)
            .map(|r| (r.camera.clone(), r.schedule.clone()))
            .collect();
        v.sort();
        v.dedup();
        v
    };
    let pair = |c: &str, s: &str| (c.to_string(), s.to_string());
    for mode in ["rotation", "blue-noise"] {
        assert_eq!(
            views(mode),
            [
                pair("orbit", "independent"),
                pair("orbit", "r1"),
                pair("static", "independent"),
                pair("static", "r1")
            ],
            "{mode}"
        );
    }
    assert_eq!(views("stbn"), [pair("orbit", "independent"), pair("static", "independent")]);
    // Each stored record renders 4 frames; what advise ranks is the time of one. (Reading the
    // records back needs their camera known here, as advise knew it.)
    hemilab::plan::CameraId::intern(hemilab::plan::CameraRun {
        name: "orbit".into(),
        path: hemilab::advice::setup::default_path(),
        jitter: true,
        frames: 4,
    });
    let ranked = hemilab::advice::pipeline::as_ranked(&records).unwrap();
    for (r, k) in records.iter().zip(&ranked) {
        assert_eq!((k.pipeline.as_str(), k.frame), ("raw", 1));
        assert_eq!((k.rmse, k.rays, &k.camera, &k.schedule), (r.rmse, r.rays, &r.camera, &r.schedule));
        assert!((k.time_s * 4.0 - r.time_s).abs() <= 1e-12 * r.time_s, "{} vs {}", k.time_s, r.time_s);
        assert!(
            (k.rays_cast * 4).abs_diff(r.rays_cast) <= 2,
            "rounded to the ray: {} vs {}",
            k.rays_cast,
            r.rays_cast
        );
        assert!(k.lowfreq_ratio.is_nan(), "after a spatial filter the structure measure is not read");
    }
    // An accumulating pipeline sweeps no static seed (its error repeats every frame), and says why.
    assert!(records.iter().all(|r| r.seed_mode != "static"), "{records:?}");
    let md = std::fs::read_to_string(out.join("advice.md")).unwrap();
    assert!(md.contains(hemilab::advice::REPEATING_ERROR), "{md}");
    assert!(md.contains(
        "hemilab advise: cornell-box at 20x16 after ema0.1+atrous at frame 4 (budgets in ms per frame)"
    ));
    // The budgets an engine has: rays per pixel per frame, for each camera; no ms budget unless
    // asked for.
    assert!(a["budgets_ms"].as_array().unwrap().is_empty(), "{}", a["budgets_ms"]);
    let per_ray = a["ray_budgets"].as_array().unwrap();
    let at: Vec<(u64, &str)> = per_ray
        .iter()
        .map(|x| (x["rays_per_pixel_per_frame"].as_u64().unwrap(), x["camera"].as_str().unwrap()))
        .collect();
    assert_eq!(at, [(1, "static"), (1, "orbit"), (2, "static"), (2, "orbit")]);
    for x in per_ray {
        let ranking = x["ranking"].as_array().unwrap();
        // The paper's default, rotation and blue-noise under two schedules, STBN under one.
        assert_eq!(ranking.len(), 7, "{x}");
        let stbn: Vec<&Value> =
            ranking.iter().filter(|e| e["configuration"]["seed_mode"] == "stbn").collect();
        assert_eq!(stbn.len(), 1);
        assert_eq!(stbn[0]["schedule"], "any");
        assert_eq!(x["recommended"], ranking[0]["configuration"]);
        assert_eq!(x["recommended_schedule"], ranking[0]["schedule"]);
        for w in ranking.windows(2) {
            assert!(num(&w[0]["rmse"]) <= num(&w[1]["rmse"]));
        }
        let ties: Vec<String> = x["near_ties"].as_array().unwrap().iter().map(candidate).collect();
        assert_eq!(ties[0], candidate(&ranking[0]));
        // By FLIP: the least mean FLIP, named, and whether it differs from the RMSE winner.
        let least_flip = ranking.iter().min_by(|p, q| num(&p["flip"]).total_cmp(&num(&q["flip"]))).unwrap();
        assert_eq!(candidate(&x["recommended_by_flip"]), candidate(least_flip));
        assert_eq!(x["flip_differs"].as_bool().unwrap(), candidate(least_flip) != candidate(&ranking[0]));
        let rays = x["rays_per_pixel_per_frame"].as_u64().unwrap() as u32;
        let camera = x["camera"].as_str().unwrap();
        for e in ranking {
            // The RMSE is √ of the mean of the replicates' MSE; FLIP the mean of theirs.
            let mse: Vec<f64> = e["mse"].as_array().unwrap().iter().map(|m| num(&m["mse"])).collect();
            assert_eq!(mse.len(), 2);
            let rmse = (mse.iter().sum::<f64>() / 2.0).sqrt();
            assert!((num(&e["rmse"]) - rmse).abs() <= 1e-12 * rmse, "{e}");
            let flips: Vec<f64> = e["flips"].as_array().unwrap().iter().map(|m| num(&m["flip"])).collect();
            assert!(flips.iter().all(|f| *f > 0.0 && *f < 1.0), "{e}");
            assert!((num(&e["flip"]) - (flips[0] + flips[1]) / 2.0).abs() <= 1e-12, "{e}");
            assert!(num(&e["flicker"]) > 0.0, "frame 4 has a frame before it: {e}");
            // The bias/noise split from the kept images: bias² + noise² is the mean MSE.
            let (b, n) = (num(&e["bias_rmse"]), num(&e["noise_rmse"]));
            assert!(n > 0.0, "{e}");
            let mean_mse = mse.iter().sum::<f64>() / 2.0;
            // (bias² is clipped at 0 where the replicates' spread exceeds the error.)
            let split = b * b + n * n;
            assert!(
                (split - mean_mse).abs() <= 1e-4 * mean_mse || (b == 0.0 && split >= mean_mse),
                "{e}: {b}² + {n}² vs {mean_mse}"
            );
            assert!(num(&e["sampler_ns_per_point"]) > 0.0, "{e}");
            let schedule = e["schedule"].as_str().unwrap();
            let mine: Vec<&hemilab::results::JobResult> = ranked
                .iter()
                .filter(|r| {
                    r.rays == rays
                        && r.camera == camera
                        && (schedule == "any" || r.schedule == schedule)
                        && format!("{}/{}/{}", r.distribution, r.sequence, r.seed_mode)
                            == label(&e["configuration"])
                })
                .collect();
            assert_eq!(mine.len(), 2, "{e}");
            let mut t: Vec<f64> = mine.iter().map(|r| r.time_s * 1e3).collect();
            t.sort_by(f64::total_cmp);
            assert!((num(&e["time_per_frame_ms"]) - (t[0] + t[1]) / 2.0).abs() <= 1e-9, "{e} vs {t:?}");
        }
    }
    let text = common::stdout(&o);
    for camera in ["the scene's still camera", "the moving camera 'orbit'"] {
        let start = format!("At 1 ray per pixel per frame, {camera}, after ema0.1+atrous at frame 4: ship ");
        assert!(text.lines().any(|l| l.starts_with(&start)), "{text}");
    }
    // The page: the answer first, then the final frames beside the reference for each camera
    // (image, signed error, FLIP), then the tables and the comparison viewer (the run page's).
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    let ship = html.find("ship ").expect("the answer");
    let finals = html.find("advise_final.png").expect("the still camera's final frames");
    assert!(ship < finals && finals < html.find("<table").unwrap(), "answer, frames, then tables");
    for f in ["advise_final", "advise_final_orbit"] {
        for part in ["", "_error", "_flip"] {
            let name = format!("{f}{part}.png");
            assert!(out.join(&name).is_file(), "{name}");
            assert!(html.contains(&name), "{name}");
        }
    }
    assert!(html.contains("id=\"viewer\""));
    let manifest = std::fs::read_to_string(out.join("viewer/manifest.js")).unwrap();
    assert!(manifest.contains("orbit") && manifest.contains("static"), "a view per camera");
    assert!(out.join("viewer/viewer.js").is_file());

    // Asked for ms budgets, it answers them too, per frame (the still camera, independent schedule).
    let b = ranked.iter().map(|r| r.time_s).fold(0.0, f64::max) * 1e3 * 0.9;
    let o = t.hemilab(&args("ema0.1+atrous", "4", ONLY, &["--budget-ms", &format!("{b}")]));
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
    // A spatial filter alone accumulates nothing: the static seed is swept, by the still camera
    // under the independent schedule alone (frame 1 is the same under both).
    assert!(records.iter().any(|r| r.seed_mode == "static"), "{records:?}");
    assert!(records.iter().all(|r| r.camera == "static" && r.schedule == "independent"), "{records:?}");
    let a = json(&t.path("out/advice.json"));
    assert_eq!((a["pipeline"].as_str(), a["frames"].as_u64()), (Some("atrous"), Some(1)));
}

/// `--denoiser NAME=COMMAND` runs the user's denoiser on every ranked frame (as a spec's
/// `[denoisers.NAME]` does for `run`), `--camera-path` adds a camera; a denoiser that cannot run
/// and a path that looks away from the scene are refused before any work (exit 2, nothing
/// written).
#[test]
fn the_users_denoiser_and_camera_path_run_through_advise() {
    let t = Tmp::new("advise-denoiser");
    let exe = example("denoise_box");
    let box_ = format!("box={} {{input}} {{output}}", exe.display());
    let only = "sine-cosine/random/blue-noise";
    let o = t.hemilab(&args("ema0.1", "2", only, &["--denoiser", &box_, "--camera-path", "pan:4"]));
    assert!(o.status.success(), "{}", common::stderr(&o));
    let out = t.path("out");
    let records =
        hemilab::results::from_json(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert!(!records.is_empty());
    for r in &records {
        assert_eq!(r.denoiser, "box", "{r:?}");
        assert!(r.denoise_s > 0.0, "the denoiser's own time: {r:?}");
    }
    let mut cameras: Vec<&str> = records.iter().map(|r| r.camera.as_str()).collect();
    cameras.sort();
    cameras.dedup();
    assert_eq!(cameras, ["orbit", "pan-4", "static"]);
    let a = json(&out.join("advice.json"));
    assert!(a["setup"].as_str().unwrap().contains("denoiser 'box'"), "{}", a["setup"]);
    assert_eq!(a["ray_budgets"].as_array().unwrap().len(), 2 * 3, "2 ray counts × 3 cameras");
    assert!(std::fs::read_to_string(out.join("advice.md")).unwrap().contains("and the denoiser box"));

    // Refused before any work: the same folder is left as it was, another one never made.
    for (extra, says) in [
        (vec!["--denoiser", "bad=/nonexistent/denoiser {input} {output}"], "denoisers.bad"),
        (vec!["--camera-path", "pan:180"], "sees no triangle"),
        (vec!["--denoiser", "box=denoise {input}"], "--denoiser"),
    ] {
        let mut a = args("ema0.1", "2", only, &extra);
        let at = a.iter().position(|x| x == "out").unwrap();
        a[at] = "refused".into();
        let o = t.hemilab(&a);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", common::stderr(&o));
        assert!(common::stderr(&o).contains(says), "{extra:?}: {}", common::stderr(&o));
        assert!(!t.path("refused").exists(), "{extra:?}");
    }
}

/// `advise --help` names every pipeline the parser's error names (it once listed six of them), and
/// the camera path and denoiser options.
#[test]
fn advise_help_lists_every_pipeline_the_error_lists() {
    let t = Tmp::new("advise-help");
    let o = t.hemilab(&["advise", "--help"]);
    assert!(o.status.success());
    let flat = |s: &str| s.split_whitespace().collect::<Vec<_>>().join(" ");
    let help = flat(&common::stdout(&o));
    assert!(help.contains(&flat(hemilab::denoise::pipeline::ALLOWED)), "{help}");
    for option in ["--camera-path", "--denoiser", "orbit:DEG", "NAME=PROGRAM"] {
        assert!(help.contains(option), "{option}: {help}");
    }
    let o = t.hemilab(&["advise", &scene("cornell-box.toml"), "--pipeline", "blur"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        flat(&common::stderr(&o)).contains(&flat(hemilab::denoise::pipeline::ALLOWED)),
        "{}",
        common::stderr(&o)
    );
}

#[test]
fn a_steady_state_frame_is_rendered_from_the_frames_its_pipeline_remembers() {
    // SVGF remembers 21 frames (all but 1 % of its history's weight): frame 32 is rendered from
    // frame 12, each record says so, and what advise ranks is the time of one of those frames.
    let t = Tmp::new("advise-steady");
    let o = t.hemilab(&args("svgf", "32", "sine-cosine/fibonacci/rotation", &[]));
    assert!(o.status.success(), "{}", common::stderr(&o));
    let out = t.path("out");
    let records =
        hemilab::results::from_json(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    assert!(!records.is_empty());
    hemilab::plan::CameraId::intern(hemilab::plan::CameraRun {
        name: "orbit".into(),
        path: hemilab::advice::setup::default_path(),
        jitter: true,
        frames: 32,
    });
    let ranked = hemilab::advice::pipeline::as_ranked(&records).unwrap();
    for (r, k) in records.iter().zip(&ranked) {
        assert_eq!((r.frame, r.first_frame), (32, 12), "{r:?}");
        assert!((k.time_s * 21.0 - r.time_s).abs() <= 1e-12 * r.time_s, "{} vs {}", k.time_s, r.time_s);
    }
    // Its reference has 4 x 1024 rays (a filtered image's error is a tenth of a raw frame's).
    let manifests: Vec<_> = std::fs::read_dir(t.path("ref"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    assert!(!manifests.is_empty());
    for m in manifests {
        let v = json(&m);
        assert_eq!((v["rays"].as_u64(), v["replicates"].as_u64()), (Some(1024), Some(4)), "{}", m.display());
    }
}

/// The Cornell box's scene file in `t`, its mesh by absolute path, with `extra` appended.
fn room(t: &Tmp, extra: &str) -> String {
    let text = std::fs::read_to_string(scene("cornell-box.toml")).unwrap();
    let mesh = std::path::Path::new(&scene("cornell-box.obj")).canonicalize().unwrap();
    let text = text.replace("\"cornell-box.obj\"", &format!("{:?}", mesh.display().to_string()));
    let path = t.path("room.toml");
    std::fs::write(&path, format!("{text}\n{extra}")).unwrap();
    path.display().to_string()
}

#[test]
fn a_scenes_own_cameras_are_ranked_beside_the_default_orbit() {
    let t = Tmp::new("advise-scene-cameras");
    let file = room(&t, "[cameras.walk]\npath = { pan = { degrees = 4.0 } }\njitter = true\n");
    let mut a = args("ema0.1", "4", "sine-cosine/fibonacci/rotation", &[]);
    a[1] = file;
    let o = t.hemilab(&a);
    assert!(o.status.success(), "{}", common::stderr(&o));
    let records =
        hemilab::results::from_json(&std::fs::read_to_string(t.path("out/results.json")).unwrap()).unwrap();
    let mut cams: Vec<&str> = records.iter().map(|r| r.camera.as_str()).collect();
    cams.sort_unstable();
    cams.dedup();
    assert_eq!(cams, ["orbit", "static", "walk"]);
    // A name advise gives its own cameras is refused, naming the key (exit 2, nothing written).
    let bad = room(&t, "[cameras.orbit]\npath = { pan = { degrees = 4.0 } }\n");
    let mut a = args("ema0.1", "4", "sine-cosine/fibonacci/rotation", &[]);
    a[1] = bad;
    let out = a.iter().position(|x| x == "out").unwrap();
    a[out] = "out-bad".into();
    let o = t.hemilab(&a);
    assert_eq!(o.status.code(), Some(2), "{}", common::stderr(&o));
    assert!(common::stderr(&o).contains("cameras.orbit"), "{}", common::stderr(&o));
    assert!(!t.path("out-bad").exists());
}

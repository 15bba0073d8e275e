//! `hemilab run` of the real-time axes through the real binary: a moving, jittered camera and the
//! user's own denoiser command (`examples/denoise_box.rs`) end to end — results.csv names the
//! camera and the denoiser and reports flicker, the floor and the denoiser's own time — and a
//! missing or failing command refused before any rendering (exit 2, nothing written).

use crate::support::common::*;
use crate::support::examples::example;
use hemilab::results::JobResult;

/// Kitchen at 32x24, 1 ray per frame over 4 frames, through SVGF and EMA, with the scene's camera
/// and an orbit of 6 degrees with jitter; `extra` goes into the table.
fn spec(extra_top: &str, extra_table: &str) -> String {
    format!(
        r#"name = "rt"
scenes = ["{}"]
resolution = [32, 24]
replicates = 2
seed = 5

[reference]
rays = 64
replicates = 2

[cameras.orbit]
path = {{ orbit = {{ degrees = 6.0 }} }}
jitter = true
{extra_top}

[[table]]
name = "t"
rays = [1]
distributions = ["sine-cosine"]
sequences = ["fibonacci"]
seed_modes = ["rotation"]
pipelines = ["svgf", "ema0.1"]
cameras = ["static", "orbit"]
frames = 4
{extra_table}
"#,
        scene("kitchen.toml")
    )
}

#[test]
fn a_moving_camera_and_a_users_denoiser_run_end_to_end() {
    let t = Tmp::new("rt-denoise");
    let exe = example("denoise_box");
    let denoiser = format!(
        "[denoisers.box]\nprogram = \"{}\"\nargs = [\"{{input}}\", \"{{output}}\"]",
        exe.display().to_string().replace('\\', "/")
    );
    let s = t.spec("rt.toml", &spec(&denoiser, "denoisers = [\"box\"]"));
    t.run_ok(&s, "out", "refs", &[]);
    let rs = records(&t.path("out"));
    // 2 pipelines x 3 reported frames (1, 2, 4) x 2 cameras x 2 replicates.
    assert_eq!(rs.len(), 24, "{}", rs.len());
    for r in &rs {
        assert_eq!(r.denoiser, "box");
        assert!(r.camera == "static" || r.camera == "orbit", "{}", r.camera);
        assert!(r.rmse.is_finite() && r.rmse > 0.0);
        assert!(r.denoise_s > 0.0, "the denoiser's own time is reported: {}", r.denoise_s);
        // Fibonacci × rotation alone: no input unbiased per pixel, so no floor.
        assert!(r.floor.is_none(), "no floor of {} at frame {}", r.pipeline, r.frame);
        assert_eq!(r.flicker.is_some(), r.frame > 1, "flicker from frame 2: {:?} at {}", r.flicker, r.frame);
        // The denoiser's output is split from its two replicates like any other (no jackknife below 3).
        assert!(r.noise_rmse.is_finite() && r.bias_rmse.is_finite() && r.bias_se.is_nan(), "{r:?}");
    }
    let csv = std::fs::read_to_string(t.path("out/results.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for c in ["camera", "denoiser", "flicker", "floor", "denoise_s", "bias_rmse", "bias_se", "noise_rmse"] {
        assert!(header.split(',').any(|h| h == c), "{c} in {header}");
    }
    // The orbit's measured frames (and the one before each) have references of their own.
    let refs = std::fs::read_dir(t.path("refs"))
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension().is_some_and(|x| x == "exr"));
    assert_eq!(refs.count(), 1 + 4, "the scene's view and orbit frames 0, 1, 2, 3");
    assert!(!t.path("out/.denoise").exists(), "the denoiser's working files are removed");
}

#[test]
fn every_camera_is_split_from_its_replicates_and_the_parts_add_up_to_the_mean_mse() {
    let t = Tmp::new("rt-split");
    let s = t.spec("rt.toml", &spec("", ""));
    let o = t.run_ok(&s, "out", "refs", &[]);
    let rs = records(&t.path("out"));
    assert_eq!(rs.len(), 24);
    // Every row is denoised: the smallest RMSE the reference must resolve is still a number (it
    // read "inf", so the noise-floor warning could never fire), the least of the static camera's.
    let out = String::from_utf8_lossy(&o.stdout);
    let line = out.lines().find(|l| l.starts_with("reference 'kitchen': ")).expect("the reference line");
    let smallest: f64 = line.rsplit(' ').next().unwrap().parse().unwrap();
    let least = rs.iter().filter(|r| r.camera == "static").map(|r| r.rmse).fold(f64::INFINITY, f64::min);
    assert!(smallest.is_finite() && smallest >= least * 0.999, "{line} (least record {least})");
    for r in &rs {
        assert!(r.noise_rmse.is_finite() && r.bias_rmse.is_finite(), "{} {r:?}", r.camera);
        assert!(r.denoise_s == 0.0 && r.denoiser.is_empty());
        // bias² + noise² is the mean MSE over the configuration's replicates.
        let same: Vec<&JobResult> = rs
            .iter()
            .filter(|o| (&o.camera, &o.pipeline, o.frame) == (&r.camera, &r.pipeline, r.frame))
            .collect();
        assert_eq!(same.len(), 2);
        let mse = same.iter().map(|o| o.rmse * o.rmse).sum::<f64>() / 2.0;
        let parts = r.bias_rmse.powi(2) + r.noise_rmse.powi(2);
        // RMSE's errors are f32 differences, the split's f64: equal to 1e-6.
        assert!(parts >= mse * (1.0 - 1e-6), "{parts} against {mse}: bias² is clipped at 0 only upwards");
        if r.bias_rmse > 0.0 {
            assert!((parts - mse).abs() < 1e-6 * mse, "{parts} against {mse}");
        }
    }
    // A resumed run reads the same split back from the kept images.
    t.run_ok(&s, "out", "refs", &[]);
    let again = records(&t.path("out"));
    for (a, b) in rs.iter().zip(&again) {
        assert_eq!((a.bias_rmse, a.noise_rmse, a.floor), (b.bias_rmse, b.noise_rmse, b.floor));
    }
}

#[test]
fn a_missing_or_failing_denoiser_is_refused_before_any_rendering() {
    let t = Tmp::new("rt-bad-denoiser");
    let cases = [
        ("\"/nonexistent/denoiser\"", "[\"{input}\", \"{output}\"]", "cannot start"),
        // `false` runs and fails.
        ("\"false\"", "[\"{input}\", \"{output}\"]", "denoise_command"),
    ];
    for (i, (program, args, says)) in cases.iter().enumerate() {
        let d = format!("[denoisers.box]\nprogram = {program}\nargs = {args}");
        let s = t.spec(&format!("bad{i}.toml"), &spec(&d, "denoisers = [\"box\"]"));
        let before = t.listing();
        let o = t.run(&s, &format!("out{i}"), "refs", &[]);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains("key `denoisers.box`") && e.contains(says), "{e}");
        assert!(!e.contains("reference for"), "refused before any reference: {e}");
        assert_eq!(t.listing(), before, "nothing written");
    }
}

/// A valid spec whose table has a user's denoiser and the `raw` pipeline (no `pipelines` key), or
/// only a moving camera, renders and reports: once it rendered every job, then stopped with exit 2,
/// "no result for …", and no report, looking for a raw frame of the scene's camera no job made.
#[test]
fn a_table_of_denoised_or_moving_frames_alone_renders_and_reports() {
    let t = Tmp::new("rt-no-raw");
    let exe = example("denoise_box");
    let text = format!(
        r#"name = "rt"
scenes = ["{}"]
resolution = [24, 18]
replicates = 2

[reference]
rays = 32
replicates = 2

[denoisers.box]
program = "{}"
args = ["{{input}}", "{{output}}"]

[cameras.orbit]
path = {{ orbit = {{ degrees = 4.0 }} }}

[[table]]
name = "denoised"
rays = [1]
rows = [{{ distribution = "sine-cosine", sequence = "fibonacci" }}]
denoisers = ["box"]

[[table]]
name = "moving"
rays = [1]
rows = [{{ distribution = "sine-cosine", sequence = "fibonacci" }}]
cameras = ["orbit"]
frames = 2
"#,
        scene("cornell-box.toml"),
        exe.display().to_string().replace('\\', "/")
    );
    let s = t.spec("rt.toml", &text);
    let o = t.run_ok(&s, "out", "refs", &[]);
    assert!(t.path("out/index.html").exists(), "{}", String::from_utf8_lossy(&o.stdout));
    let rs = records(&t.path("out"));
    assert!(rs.iter().any(|r| r.denoiser == "box") && rs.iter().any(|r| r.camera == "orbit"));
    assert!(rs.iter().all(|r| !r.is_single_frame()), "no paper-table record was asked for");
}

/// A camera path whose frames see nothing — a 180° pan, a dolly through the back wall, keyframes
/// looking away — is refused at load (`plan` and `run`, exit 2, nothing written), naming
/// `cameras.NAME` and the frame: once `plan` passed it and `run` built an all-background reference,
/// then failed naming a job.
#[test]
fn a_camera_path_whose_frames_see_nothing_is_refused_naming_the_camera_and_frame() {
    let t = Tmp::new("rt-blind-path");
    let cases = [
        ("pan", "{ pan = { degrees = 180.0 } }", "frame 1 (of 0 to 1)"),
        ("dolly", "{ dolly = { distance = 2000.0 } }", "frame 1 (of 0 to 1)"),
        (
            "keys",
            "{ keyframes = [{ frame = 0, eye = [278.0, 273.0, -800.0], target = [278.0, 273.0, -1600.0] }] }",
            "frame 0 (of 0 to 1)",
        ),
    ];
    for (name, path, frame) in cases {
        let text = format!(
            r#"name = "blind"
scenes = ["{}"]
resolution = [24, 18]
replicates = 2
[reference]
rays = 32
replicates = 2
[cameras.{name}]
path = {path}
[[table]]
name = "t"
rays = [1]
rows = [{{ distribution = "sine-cosine", sequence = "fibonacci" }}]
cameras = ["{name}"]
frames = 2
"#,
            scene("cornell-box.toml")
        );
        let s = t.spec("blind.toml", &text);
        for command in ["plan", "run"] {
            let mut args = vec![command, s.to_str().unwrap(), "--reference-dir", "refs"];
            if command == "run" {
                args.push("--quiet");
            }
            let o = t.hemilab(&args);
            let e = assert_error(&o, &s.display().to_string());
            assert!(e.contains(&format!("key `cameras.{name}.path`")) && e.contains(frame), "{name}: {e}");
            assert!(e.contains("sees no triangle"), "{e}");
            assert!(!t.path("refs").exists() && !t.path("out").exists(), "{command} {name}: nothing written");
        }
    }
}

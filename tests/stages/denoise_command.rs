//! The user's own denoiser: `DenoiseCommand` runs a program on a frame's EXR and
//! reads one back. Here the program is the package's example `denoise_box` (a normal-aware 5 × 5
//! box, as a user would write), built by `support::examples`; and commands that fail in each way
//! are each one clear error (exit status 2) from `probe`, before any rendering.

use crate::support::common::Tmp;
use crate::support::examples::example;
use hemilab::denoise_command::DenoiseCommand;
use hemilab::image::{Channel, Image};
use hemilab::load::load_scene;
use hemilab::render::{gbuffer, render};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use std::path::Path;

fn command(program: &str, args: &[&str], timeout_s: f64) -> DenoiseCommand {
    DenoiseCommand { program: program.into(), args: args.iter().map(|a| a.to_string()).collect(), timeout_s }
}

fn box_denoiser() -> DenoiseCommand {
    command(example("denoise_box").to_str().unwrap(), &["{input}", "{output}"], 60.0)
}

#[test]
fn the_example_box_denoiser_is_probed_run_and_timed_and_lowers_the_error() {
    let dir = Tmp::new("denoise-box");
    let cmd = box_denoiser();
    cmd.validate().unwrap();
    cmd.probe(&dir).unwrap();
    let scene = load_scene(&Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml")).unwrap();
    let (w, h) = (48, 36);
    let job = |rays, seed| {
        crate::support::jobs::render_job(
            Distribution::SineCosine,
            SamplerConfig::new(Sequence::Random, SeedMode::Shift, rays, seed).unwrap(),
            (w, h),
            scene.ao_distance,
        )
    };
    let noisy = render(&scene, &job(1, 3), &|_| {});
    let reference = render(&scene, &job(1024, 4), &|_| {});
    let g = gbuffer(&scene, w, h);
    let (denoised, took) = cmd.run(&dir, &noisy.ao, &g).unwrap();
    assert!(took.as_nanos() > 0);
    assert_eq!((denoised.width, denoised.height), (w, h));
    let rmse = |img: &Image| hemilab::metrics::measure(img, &reference.ao, &g.coverage).unwrap().rmse;
    let (before, after) = (rmse(&noisy.ao), rmse(&denoised));
    eprintln!("1-ray frame RMSE {before:.4} -> {after:.4} after denoise_box ({took:?})");
    assert!(
        after < 0.5 * before,
        "the box filter more than halves a 1-ray frame's error: {before} -> {after}"
    );
    // What came back is the example's filter of what was sent: at each pixel, the mean over its
    // 5 × 5 neighbours that are covered and face the same way (n · n' ≥ 0.9); background as sent.
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let i = (y * w as i64 + x) as usize;
            if !g.is_covered(i) {
                assert_eq!(denoised.data[i], noisy.ao.data[i]);
                continue;
            }
            let (mut sum, mut n) = (0.0f64, 0);
            for qy in (y - 2).max(0)..=(y + 2).min(h as i64 - 1) {
                for qx in (x - 2).max(0)..=(x + 2).min(w as i64 - 1) {
                    let q = (qy * w as i64 + qx) as usize;
                    if g.is_covered(q) && g.normal[i].dot(g.normal[q]) >= 0.9 {
                        sum += noisy.ao.data[q] as f64;
                        n += 1;
                    }
                }
            }
            assert_eq!(denoised.data[i], (sum / n as f64) as f32, "pixel ({x}, {y})");
        }
    }
    let left: Vec<_> = std::fs::read_dir(&*dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert!(left.is_empty(), "a run cleans up after itself: {left:?}");
}

/// Writes an EXR of the given channels (each `side` × `side`, filled with `value`) for a fake
/// denoiser to copy into place.
fn fixture(dir: &Tmp, name: &str, side: u32, channels: &[&str], value: f32) -> String {
    let img = Image::from_vec(side, side, vec![value; (side * side) as usize]);
    let list: Vec<Channel> = channels.iter().map(|&name| Channel { name, image: &img }).collect();
    let path = dir.path(name);
    hemilab::io::write_exr(&path, &list).unwrap();
    path.to_string_lossy().into_owned()
}

#[test]
fn a_command_that_fails_writes_nothing_or_writes_the_wrong_image_is_one_clear_error() {
    let dir = Tmp::new("denoise-fail");
    let work = dir.path("work");
    let small = fixture(&dir, "small.exr", 4, &["Y"], 0.5);
    let no_value = fixture(&dir, "z.exr", 8, &["Z"], 0.5);
    let nan = fixture(&dir, "nan.exr", 8, &["R", "G", "B"], f32::NAN);
    let good = fixture(&dir, "good.exr", 8, &["Y"], 0.5);
    let sh =
        |script: &str, timeout: f64| command("sh", &["-c", script, "sh", "{input}", "{output}"], timeout);
    let copy = |from: &str| sh(&format!("cp '{from}' \"$2\""), 60.0);
    let cases = [
        (
            sh("echo 'model file missing' >&2; exit 3", 60.0),
            vec!["failed (exit status: 3)", "model file missing"],
        ),
        (sh("true", 60.0), vec!["exited successfully but wrote nothing at", "denoise-output.exr"]),
        (sh("echo hello > \"$2\"", 60.0), vec!["not a readable EXR"]),
        (copy(&small), vec!["its output is 4x4, the frame 8x8"]),
        (copy(&no_value), vec!["has channels [Z]; hemilab reads Y, or R, G and B"]),
        (copy(&nan), vec!["not finite at pixel (0, 0)"]),
        (sh("exec sleep 10", 0.2), vec!["did not finish within timeout_s = 0.2 s"]),
        (
            command("/no/such/denoiser", &["{input}", "{output}"], 60.0),
            vec!["cannot start /no/such/denoiser"],
        ),
    ];
    for (cmd, wanted) in cases {
        cmd.validate().unwrap();
        let e = cmd.probe(&work).unwrap_err();
        assert_eq!(e.exit_code(), 2);
        let msg = e.to_string();
        assert!(
            msg.starts_with("denoise_command `")
                && msg.contains("on a tiny test image, before any rendering"),
            "{msg}"
        );
        for w in wanted {
            assert!(msg.contains(w), "{w:?} not in: {msg}");
        }
        // A probe's files are removed, failed or not (once a failed probe left 20 MB of stderr
        // behind); the message keeps the end of the stderr.
        assert!(!msg.contains("input kept at"), "{msg}");
        let left: Vec<_> = std::fs::read_dir(&work).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert!(left.is_empty(), "a failed probe leaves nothing: {left:?} after {msg}");
    }
    // A command that copies a good image into place passes, whatever it was sent.
    copy(&good).probe(&work).unwrap();
}

#[test]
fn the_input_exr_has_the_documented_channels() {
    let dir = Tmp::new("denoise-channels");
    let keep = dir.path("seen.exr");
    let cmd = command(
        "sh",
        &["-c", &format!("cp \"$1\" '{}' && cp \"$1\" \"$2\"", keep.display()), "sh", "{input}", "{output}"],
        60.0,
    );
    cmd.probe(&dir.path("work")).unwrap();
    let channels = hemilab::io::read_exr(&keep).unwrap();
    let mut names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
    names.sort();
    assert_eq!(names, ["A", "B", "G", "N.X", "N.Y", "N.Z", "R", "Z", "albedo.B", "albedo.G", "albedo.R"]);
    let get = |n: &str| &channels.iter().find(|(c, _)| c == n).unwrap().1;
    assert_eq!(get("R"), get("G"));
    assert!(get("albedo.R").data.iter().all(|&v| v == 1.0));
    assert_eq!(get("A").data[0], 0.0, "the probe has a background pixel");
    assert_eq!((get("N.X").data[0], get("Z").data[0]), (0.0, 0.0), "zero on background");
    let len = |i: usize| {
        (get("N.X").data[i].powi(2) + get("N.Y").data[i].powi(2) + get("N.Z").data[i].powi(2)).sqrt()
    };
    assert!((1..64).all(|i| (len(i) - 1.0).abs() < 1e-6), "unit normals on covered pixels");
}

/// A command past its `timeout_s` is stopped with everything it started: once only the command was
/// killed, and its own children (here two `sleep`s a shell started) kept running.
#[test]
fn a_command_past_its_timeout_is_stopped_with_its_children() {
    let dir = Tmp::new("denoise-group");
    let pids = dir.path("pids");
    let script = format!("sleep 30 & echo $! >> '{0}'; sleep 30 & echo $! >> '{0}'; wait", pids.display());
    let cmd = command("sh", &["-c", &script, "sh", "{input}", "{output}"], 0.5);
    let e = cmd.probe(&dir.path("work")).unwrap_err().to_string();
    assert!(e.contains("did not finish within timeout_s = 0.5 s"), "{e}");
    let started: Vec<i32> =
        std::fs::read_to_string(&pids).unwrap().lines().map(|l| l.trim().parse().unwrap()).collect();
    assert_eq!(started.len(), 2, "{started:?}");
    // Gone (or a zombie waiting for init to reap it) within a few seconds.
    let alive = |pid: i32| {
        std::fs::read_to_string(format!("/proc/{pid}/stat"))
            .is_ok_and(|s| s.rsplit(')').next().is_some_and(|rest| !rest.trim_start().starts_with('Z')))
    };
    let start = std::time::Instant::now();
    while started.iter().any(|&p| alive(p)) && start.elapsed().as_secs() < 5 {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    assert!(started.iter().all(|&p| !alive(p)), "still running: {started:?}");
}

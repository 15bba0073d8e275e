//! The real binary: `render` writes the EXR (Y = AO, A = coverage) and a PNG beside it; bad arguments
//! exit with 2 and create nothing; `bench --json` reports rays per second.

use crate::support::common::{Tmp, entries, hemilab_in_root as hemilab, render, render_args};

#[test]
fn render_writes_exr_and_png_preview() {
    let dir = Tmp::new("render");
    let exr = dir.join("sub/box.exr");
    let estimator = ["--distribution", "sine-cosine", "--sequence", "fibonacci", "--seed-mode", "rotation"];
    let out = render(
        "cornell-box.toml",
        4,
        &exr,
        &[&estimator[..], &["--resolution", "24x16", "--threads", "2"]].concat(),
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // No progress (a render this small takes under the 2 s before a first line), and the one thing
    // done beyond what was asked: the directory `sub` did not exist.
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        format!(
            "note: created the directory {} for --output (it did not exist)\n",
            dir.join("sub").display()
        )
    );
    let channels = hemilab::io::read_exr(&exr).unwrap();
    let get = |n: &str| &channels.iter().find(|(name, _)| name == n).expect(n).1;
    let (y, a) = (get("Y"), get("A"));
    assert_eq!((y.width, y.height, a.width, a.height), (24, 16, 24, 16));
    assert!(a.data.iter().all(|&c| c == 0.0 || c == 1.0));
    assert!(a.data.contains(&1.0));
    assert!(y.data.iter().zip(&a.data).any(|(&v, &c)| c == 1.0 && v > 0.0 && v < 1.0));
    let png = std::fs::read(dir.join("sub/box.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    // Where the image came from, in its header (OpenImageIO's `iinfo -v` shows it).
    let p = hemilab::image::decode_exr_provenance(&std::fs::read(&exr).unwrap()).unwrap().unwrap();
    let want = serde_json::json!({
        "image": "render",
        "hemilab_version": env!("CARGO_PKG_VERSION"),
        "scene": "scenes/cornell-box.toml",
        "scene_name": "cornell-box",
        "scene_hash": p.json["scene_hash"],
        "distribution": "sine-cosine",
        "sequence": "fibonacci",
        "seed_mode": "rotation",
        "rays": 4,
        "seed": 1,
        "resolution": [24, 16],
        "ao_distance": "150.0",
    });
    assert_eq!(p.json, want);
    assert_eq!(p.json["scene_hash"].as_str().map(str::len), Some(32));
    assert!(
        p.summary.contains("render of scenes/cornell-box.toml") && p.summary.contains("4 rays per pixel")
    );
    let mut listing = entries(&dir.join("sub"));
    listing.sort();
    assert_eq!(listing, ["box.exr", "box.png"], "no temporary files left behind");
}

#[test]
fn bad_arguments_exit_2_and_create_nothing() {
    let dir = Tmp::new("bad");
    let exr = dir.join("out/x.exr");
    let png = dir.join("x.png");
    let good = |distribution: &'static str| {
        vec!["--distribution", distribution, "--sequence", "random", "--seed-mode", "shift"]
    };
    let with = |mut v: Vec<&'static str>, extra: &[&'static str]| {
        v.extend_from_slice(extra);
        v
    };
    let box_ = "scenes/cornell-box.toml";
    let cases: Vec<(&str, u32, Vec<&str>, &str)> = vec![
        (box_, 4, good("cosine"), "cosine"),
        (box_, 0, good("sine"), "--rays"),
        (box_, 4, with(good("sine"), &["--resolution", "0x8"]), "resolution"),
        (box_, 4, with(good("sine"), &["--resolution", "16384x16384"]), "at most 67108864 pixels"),
        ("scenes/no-such-scene.toml", 4, good("sine"), "no-such-scene.toml"),
    ];
    for (scene, rays, args, want) in cases {
        let out = hemilab(&render_args(scene, rays, &exr, &args));
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: want '{want}' in {err}");
        assert!(entries(&dir).is_empty(), "{args:?} created {:?}", entries(&dir));
    }
    let out = hemilab(&render_args(box_, 4, &png, &good("sine")));
    assert_eq!(out.status.code(), Some(2), "an output that is not .exr");
    assert!(String::from_utf8_lossy(&out.stderr).contains(".exr"));
    assert!(entries(&dir).is_empty());
}

/// `render SCENE --rays N --output F` alone renders the recommended estimator: the same bytes as
/// sine-cosine, Fibonacci, per-pixel seed (rotation) given explicitly.
#[test]
fn render_defaults_to_the_recommended_estimator() {
    let dir = Tmp::new("render-default");
    let (a, b) = (dir.join("a.exr"), dir.join("b.exr"));
    let base = ["--resolution", "16x12", "--quiet"];
    let out = render("cornell-box.toml", 4, &a, &base);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let explicit = ["--distribution", "sine-cosine", "--sequence", "fibonacci", "--seed-mode", "rotation"];
    let out = render("cornell-box.toml", 4, &b, &[&base[..], &explicit].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

#[test]
fn bench_reports_json() {
    let out = hemilab(&[
        "bench",
        "scenes/cornell-box.toml",
        "--rays",
        "2",
        "--resolution",
        "8x8",
        "--json",
        "--repeats",
        "2",
        "--distances",
        "100,inf",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["scene"], "cornell-box");
    assert_eq!(v["triangles"], 30);
    assert_eq!(v["single_thread"]["threads"], 1);
    assert!(v["single_thread"]["rays_per_s"].as_f64().unwrap() > 0.0);
    assert!(v["all_threads"]["rays_per_s"].as_f64().unwrap() > 0.0);
    assert!(v["bvh_build_s"].as_f64().unwrap() >= 0.0);
    // Rays counted are AO rays only: 8 x 8 pixels, all covered, 2 rays each, per render.
    assert_eq!(v["single_thread"]["ao_rays"].as_u64().unwrap() % 128, 0);
    // The baseline comparison: one entry per distance, both thread counts, rays/s and ratio.
    let cmp = v["comparison"].as_array().unwrap();
    assert_eq!(cmp.len(), 2);
    assert_eq!(cmp[0]["ao_distance"], 100.0);
    assert_eq!(cmp[1]["ao_distance"], "infinite");
    for c in cmp {
        assert_eq!(c["rays"], 128);
        assert_eq!(c["mismatches"]["hemilab_wrong"], 0);
        assert_eq!(c["mismatches"]["hemilab_vs_single_ray"], 0);
        let runs = c["runs"].as_array().unwrap();
        assert_eq!(runs[0]["threads"], 1);
        for r in runs {
            // Each sample traces the set at least once (more for a set this small: ~0.2 s of obvhs).
            assert!(r["traces_per_sample"].as_u64().unwrap() >= 1);
            for key in ["obvhs_rays_per_s", "hemilab_rays_per_s", "ratio"] {
                let s = &r[key];
                assert!(s["min"].as_f64().unwrap() > 0.0, "{key}");
                assert!(
                    s["min"].as_f64() <= s["median"].as_f64() && s["median"].as_f64() <= s["max"].as_f64()
                );
            }
        }
    }
}

/// Without `--distances` the table compares at the scene's own d (the Cornell box's 150 mm), 0.3 d
/// and ∞, prints ∞ as ∞ and the disagreements as counts, not as JSON; "infinite" = "inf".
#[test]
fn bench_table_defaults_to_the_scene_distance_and_reads_plainly() {
    let args = ["bench", "scenes/cornell-box.toml", "--rays", "2", "--resolution", "8x8", "--repeats", "1"];
    let out = hemilab(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    let ds: Vec<&str> = text
        .lines()
        .filter(|l| l.split_whitespace().nth(1) == Some("1"))
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    assert_eq!(ds, ["45", "150", "∞"], "{text}");
    assert!(text.contains("whole render, d = 150,"), "{text}");
    assert!(!text.contains('"') && !text.contains('{'), "{text}");
    assert_eq!(text.matches("mismatching rays: ").count(), 3, "{text}");
    let mut json = args.to_vec();
    json.extend(["--json", "--distances", "infinite,inf"]);
    let v: serde_json::Value = serde_json::from_slice(&hemilab(&json).stdout).unwrap();
    let cmp = v["comparison"].as_array().unwrap();
    assert!(cmp.len() == 2 && cmp.iter().all(|c| c["ao_distance"] == "infinite"), "{v}");
}

#[test]
fn bench_rejects_a_bad_distance() {
    let out = hemilab(&["bench", "scenes/cornell-box.toml", "--distances", "1,-2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("distance"));
}

/// Regression: a directory where the PNG preview goes used to fail only after the EXR was written,
/// leaving half the output. Both targets are now checked before rendering.
#[test]
fn an_output_that_is_a_directory_writes_nothing() {
    let dir = Tmp::new("outdir");
    std::fs::create_dir_all(dir.join("x.png")).unwrap();
    let exr = dir.join("x.exr");
    let estimator = ["--distribution", "sine", "--sequence", "random", "--seed-mode", "shift"];
    let out = render("cornell-box.toml", 1, &exr, &[&estimator[..], &["--resolution", "8x8"]].concat());
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("x.png") && err.contains("directory"), "{err}");
    assert_eq!(entries(&dir), ["x.png"], "nothing written beside the directory");
}

/// Every seed mode, blue-noise included, is listed where a user looks: --help of the commands that
/// take one, and the error for an unknown name.
#[test]
fn help_and_errors_list_every_seed_mode() {
    use hemilab::sampling::SeedMode;
    for cmd in ["render", "points"] {
        let out = hemilab(&[cmd, "--help"]);
        assert!(out.status.success());
        let help = String::from_utf8_lossy(&out.stdout);
        for name in SeedMode::NAMES {
            assert!(help.contains(name), "{cmd} --help lacks '{name}':\n{help}");
        }
    }
    let dir = Tmp::new("seedmode");
    let exr = dir.join("x.exr");
    let out = render(
        "cornell-box.toml",
        1,
        &exr,
        &["--distribution", "sine", "--sequence", "random", "--seed-mode", "blue"],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("'blue'") && err.contains("static, rotation, shift, blue-noise"), "{err}");
    assert!(entries(&dir).is_empty());
}

/// `render --seed-mode blue-noise` works end to end and is deterministic (same seed, same bits).
#[test]
fn render_blue_noise_is_deterministic() {
    let dir = Tmp::new("bluenoise");
    let render = |name: &str| {
        let exr = dir.join(name);
        let estimator =
            ["--distribution", "sine-cosine", "--sequence", "fibonacci", "--seed-mode", "blue-noise"];
        let out = render("cornell-box.toml", 2, &exr, &[&estimator[..], &["--resolution", "70x66"]].concat());
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        std::fs::read(&exr).unwrap()
    };
    assert_eq!(render("a.exr"), render("b.exr"));
}

/// `render --seed-mode stbn --frame F --schedule S` works end to end: deterministic, a different
/// image per frame; `points` takes the same options; both --help list the schedules.
#[test]
fn render_and_points_take_stbn_frames_and_schedules() {
    use hemilab::sampling::Schedule;
    for cmd in ["render", "points"] {
        let out = hemilab(&[cmd, "--help"]);
        let help = String::from_utf8_lossy(&out.stdout);
        for name in Schedule::NAMES {
            assert!(help.contains(name) && help.contains("--frame"), "{cmd} --help lacks '{name}':\n{help}");
        }
    }
    let dir = Tmp::new("stbn");
    let render = |name: &str, frame: &str| {
        let exr = dir.join(name);
        let frames = ["--seed-mode", "stbn", "--frame", frame, "--schedule", "r1", "--resolution", "40x30"];
        let out = render("cornell-box.toml", 2, &exr, &frames);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        std::fs::read(&exr).unwrap()
    };
    let a = render("a.exr", "3");
    assert_eq!(a, render("b.exr", "3"));
    assert_ne!(a, render("c.exr", "4"));
    let png = dir.join("p.png");
    let out = hemilab(&[
        "points",
        "--distribution",
        "sine-cosine",
        "--sequence",
        "fibonacci",
        "--seed-mode",
        "stbn",
        "--count",
        "16",
        "--frame",
        "40",
        "--schedule",
        "independent",
        "--output",
        png.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stdout).contains("frame 40 (independent)"));
    let out = hemilab(&[
        "points",
        "--distribution",
        "sine",
        "--sequence",
        "random",
        "--count",
        "4",
        "--schedule",
        "r3",
        "--output",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("valid: independent, r1"));
}

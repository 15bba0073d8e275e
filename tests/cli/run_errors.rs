//! `hemilab run` refusing bad input through the real binary: exit status 2, one `error: <path>: …`
//! message naming what to fix, and nothing written — no output directory, no reference, no
//! overwritten results.

use crate::support::common;

use common::*;

#[test]
fn bad_specs_exit_2_name_file_line_and_key_and_create_nothing() {
    let t = Tmp::new("bad-spec");
    let good = tiny_spec(16, "");
    let cases: [(String, &[&str]); 4] = [
        (
            good.replace("rays = [2, 4]", "rays = [0]"),
            &["line 14", "key `table.rays` (table 't')", "1..=65536"],
        ),
        (
            good.replace("\"uniform\"", "\"unifrm\""),
            &["line 16", "key `table.rows.distribution` (table 't')", "valid: uniform, sine, sine-cosine"],
        ),
        (
            good.replace("seed = 3", "seed = 3\nraplicates = 2"),
            &["line 6", "key `raplicates`", "`replicates`"],
        ),
        (good.replace("rays = 16", "rays = \"many\""), &["line 8", "key `reference.rays`", "\"auto\""]),
    ];
    for (i, (text, parts)) in cases.iter().enumerate() {
        let spec = t.spec(&format!("bad{i}.toml"), text);
        let before = t.listing();
        let o = t.run(&spec, "out", "ref", &[]);
        let e = assert_error(&o, &spec.display().to_string());
        for p in *parts {
            assert!(e.contains(p), "case {i}: expected {p:?} in:\n{e}");
        }
        assert_eq!(t.listing(), before, "case {i}: nothing is created");
        assert!(o.stdout.is_empty());
    }

    // Several problems: each line names the file.
    let text = good.replace("rays = [2, 4]", "rays = [0]").replace("\"uniform\"", "\"unifrm\"");
    let spec = t.spec("many.toml", &text);
    let e = assert_error(&t.run(&spec, "out", "ref", &[]), &spec.display().to_string());
    assert_eq!(e.lines().count(), 2, "{e}");
    assert!(e.lines().all(|l| l.contains(&format!("{}: line ", spec.display()))), "{e}");
}

#[test]
fn missing_spec_or_scene_file_is_named() {
    let t = Tmp::new("missing");
    let o = t.hemilab(&["run", "nope.toml", "--out", "out", "--reference-dir", "ref", "--quiet"]);
    assert_error(&o, "nope.toml");
    let spec = t.spec("s.toml", &tiny_spec(16, "").replace("cornell-box.toml", "no-such-scene.toml"));
    let e = assert_error(&t.run(&spec, "out", "ref", &[]), &spec.display().to_string());
    assert!(e.contains("key `scenes`") && e.contains("no-such-scene.toml"), "{e}");
    assert_eq!(t.listing(), ["s.toml"]);
}

#[test]
fn a_camera_that_sees_nothing_stops_every_command_before_any_work() {
    // Once: `render` exited 0 with "0 AO rays", and `run` built and wrote a reference, then failed
    // with a job's key ("no pixel is covered").
    let t = Tmp::new("blind");
    let box_scene = std::fs::read_to_string(scene("cornell-box.toml")).unwrap();
    let blind = box_scene
        .replace("target = [278.0, 273.0, 0.0]", "target = [278.0, 273.0, -1600.0]")
        .replace("cornell-box.obj", &scene("cornell-box.obj"));
    let scene_file = t.spec("blind.toml", &blind);
    let spec = t.spec("s.toml", &tiny_spec(16, "").replace(&scene("cornell-box.toml"), "blind.toml"));
    let before = t.listing();
    let name = scene_file.display().to_string();
    let runs: [&[&str]; 5] = [
        &["run", "s.toml", "--out", "out", "--reference-dir", "ref", "--quiet"],
        &["plan", "s.toml"],
        &["reference", "s.toml", "--reference-dir", "ref"],
        &["advise", &name, "--out", "out", "--reference-dir", "ref"],
        &["render", &name, "--rays", "4", "--output", "out/x.exr"],
    ];
    for args in runs {
        let e = assert_error(
            &t.hemilab(args),
            if args[0] == "advise" || args[0] == "render" { &name } else { "blind.toml" },
        );
        assert!(
            e.contains("camera: sees no triangle of the mesh") && e.contains("aim `target`"),
            "{args:?}: {e}"
        );
        assert_eq!(t.listing(), before, "{args:?}: nothing is written");
    }
    assert!(spec.exists());
}

/// A camera behind the box's back wall, looking at its outside: it sees triangles, but every one
/// open all round, so every image would be all white (AO 1) and every error zero. Said at load, as
/// a warning naming the scene file and its camera key (the camera under the floor is one too); the
/// committed scenes never say it.
#[test]
fn a_camera_outside_the_room_is_told_its_images_would_be_all_white() {
    let t = Tmp::new("all-white");
    let box_scene = std::fs::read_to_string(scene("cornell-box.toml")).unwrap();
    let outside = box_scene
        .replace("eye = [278.0, 273.0, -800.0]", "eye = [278.0, 273.0, 1800.0]")
        .replace("cornell-box.obj", &scene("cornell-box.obj"));
    let scene_file = t.spec("outside.toml", &outside);
    let name = scene_file.display().to_string();
    let o =
        t.hemilab(&["render", &name, "--rays", "4", "--resolution", "32x32", "--output", "x.exr", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains(&format!(
            "warning: {name}: key `camera.perspective.eye`: every surface the camera sees is open"
        )) && e.contains("all white"),
        "{e}"
    );
    let o = t.hemilab(&[
        "render",
        &scene("cornell-box.toml"),
        "--rays",
        "4",
        "--resolution",
        "32x32",
        "--output",
        "y.exr",
        "--quiet",
    ]);
    assert!(o.status.success() && !stderr(&o).contains("all white"), "{}", stderr(&o));
}

#[test]
fn advise_checks_the_view_at_the_resolution_it_renders() {
    // A small triangle off the image centre: seen by the scene's own 64x48 pixel centres, missed by
    // every centre of a 2x2 image (at ±1/2 of the half-extent). advise once checked the view at the
    // scene's size only, then failed mid-run at --resolution's.
    let t = Tmp::new("advise-view");
    std::fs::write(t.path("tri.obj"), "v 0.05 0.05 -1\nv 0.2 0.05 -1\nv 0.05 0.2 -1\nf 1 2 3\n").unwrap();
    let scene_file = t.spec(
        "tri.toml",
        "mesh = \"tri.obj\"\nresolution = [64, 48]\nao_distance = 1.0\n[camera.perspective]\n\
         eye = [0.0, 0.0, 0.0]\ntarget = [0.0, 0.0, -1.0]\nup = [0.0, 1.0, 0.0]\nfov_y_deg = 60.0\n",
    );
    let name = scene_file.display().to_string();
    let ok = t.hemilab(&["render", &name, "--rays", "1", "--output", "seen.exr", "--quiet"]);
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let before = t.listing();
    let args = ["advise", &name, "--resolution", "2x2", "--out", "out", "--reference-dir", "ref"];
    let e = assert_error(&t.hemilab(&args), &name);
    assert!(e.contains("camera: sees no triangle of the mesh") && e.contains("2x2"), "{e}");
    assert_eq!(t.listing(), before, "nothing is written");
}

#[test]
fn unwritable_output_directory_fails_before_rendering() {
    let t = Tmp::new("unwritable");
    let spec = t.spec("tiny.toml", &tiny_spec(16, ""));
    std::fs::write(t.path("blocker"), "a file, not a directory").unwrap();
    for out in ["blocker/out", "blocker"] {
        let e = assert_error(&t.run(&spec, out, "ref", &[]), out);
        assert!(e.contains("not a directory"), "{e}");
    }
    assert_eq!(t.listing(), ["blocker", "tiny.toml"], "no reference rendered, no output");
    // The reference directory is checked before a reference is rendered, too.
    let e = assert_error(&t.run(&spec, "out", "blocker/ref", &[]), "blocker/ref");
    assert!(e.contains("not a directory"), "{e}");
    assert!(!t.path("out/results.json").exists());
}

#[test]
fn manifest_mismatch_is_refused_with_no_build_reference() {
    let t = Tmp::new("manifest");
    // A clean run with a 64-ray reference: the numbers any correct run must reproduce.
    let spec = t.spec("tiny.toml", &tiny_spec(64, ""));
    t.run_ok(&spec, "clean", "clean-ref", &[]);
    let clean = records(&t.path("clean"));

    // A stale reference in `ref`: same scene view, but 16 rays (same file name, different image).
    let stale = t.spec("stale.toml", &tiny_spec(16, ""));
    let o = t.hemilab(&["reference".as_ref(), stale.as_os_str(), "--reference-dir".as_ref(), "ref".as_ref()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let manifests: Vec<_> = std::fs::read_dir(t.path("ref"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    assert_eq!(manifests.len(), 1);
    let manifest = &manifests[0];
    let stale_exr = std::fs::read(manifest.with_extension("exr")).unwrap();

    let o = t.run(&spec, "out", "ref", &["--no-build-reference"]);
    let e = assert_error(
        &o,
        &std::path::Path::new("ref").join(manifest.file_name().unwrap()).display().to_string(),
    );
    assert!(e.contains("rays: stored 16, wanted 64"), "names what differs: {e}");
    assert!(e.contains("--no-build-reference"), "{e}");
    assert!(!t.path("out").exists(), "nothing compared, nothing written");

    // Edited by hand: a changed seed is caught just the same.
    let text = std::fs::read_to_string(manifest).unwrap();
    std::fs::write(
        manifest,
        text.replace("\"rays\": 16", "\"rays\": 64").replace("\"seed\": 3", "\"seed\": 4"),
    )
    .unwrap();
    let e = stderr(&t.run(&spec, "out", "ref", &["--no-build-reference"]));
    assert!(e.contains("seed: stored 4, wanted 3"), "{e}");
    assert!(!t.path("out").exists());

    // Without the flag a reference of the spec's settings is built under a name of its own beside
    // the stale one, which is kept as it is (a reference is never overwritten by a different one),
    // and the numbers are those of the clean run: the stale image was never compared.
    t.run_ok(&spec, "out", "ref", &[]);
    assert_eq!(std::fs::read(manifest.with_extension("exr")).unwrap(), stale_exr, "the stale one is kept");
    let built: Vec<_> = std::fs::read_dir(t.path("ref"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json") && p != manifest)
        .collect();
    assert_eq!(built.len(), 1, "{built:?}");
    let text = std::fs::read_to_string(&built[0]).unwrap();
    assert!(text.contains("\"rays\": 64") && text.contains("\"seed\": 3"), "{text}");
    let rebuilt = records(&t.path("out"));
    assert_eq!(
        rebuilt.iter().map(timeless).collect::<Vec<_>>(),
        clean.iter().map(timeless).collect::<Vec<_>>()
    );
    // And now it matches: reused without complaint.
    t.run_ok(&spec, "out2", "ref", &["--no-build-reference"]);
}

#[test]
fn corrupt_results_file_is_refused_and_left_untouched() {
    let t = Tmp::new("corrupt");
    let spec = t.spec("tiny.toml", &tiny_spec(16, ""));
    std::fs::create_dir_all(t.path("out")).unwrap();
    let junk = "[{ \"scene\": \"cornell-box\", \"rmse\": 0.1 ";
    std::fs::write(t.path("out/results.json"), junk).unwrap();
    let path = std::path::Path::new("out").join("results.json");
    let e = assert_error(&t.run(&spec, "out", "ref", &[]), &path.display().to_string());
    assert!(e.contains("--force"), "suggests --force: {e}");
    assert_eq!(std::fs::read_to_string(t.path("out/results.json")).unwrap(), junk, "left untouched");
    assert_eq!(t.listing(), ["out", "out/results.json", "tiny.toml"], "nothing rendered");

    t.run_ok(&spec, "out", "ref", &["--force"]);
    assert_eq!(records(&t.path("out")).len(), 16);
}

#[test]
fn auto_reference_is_reused_only_with_enough_rays() {
    let t = Tmp::new("auto-ref");
    let auto = tiny_spec(16, "").replace("rays = 16", "rays = \"auto\"");
    let spec = t.spec("tiny.toml", &auto);
    t.run_ok(&spec, "out", "ref", &[]);
    t.run_ok(&spec, "out", "ref", &["--no-build-reference"]);
    // The spec now measures 16 rays: the stored reference is too coarse for it.
    let more = t.spec("more.toml", &auto.replace("rays = [2, 4]", "rays = [2, 16]"));
    let o = t.run(&more, "out2", "ref", &["--no-build-reference"]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("rays: stored 2 x 256, wanted at least 2 x 1024"), "{e}");
    t.run_ok(&more, "out2", "ref", &[]);
    t.run_ok(&spec, "out", "ref", &["--no-build-reference"]);
}

/// A run that would take hours says so before it starts (here it then stops: no reference and
/// `--no-build-reference`); a small one does not.
#[test]
fn long_run_is_announced_before_it_starts() {
    let t = Tmp::new("long-run");
    let big = tiny_spec(16, "").replace("resolution = [24, 18]", "resolution = [8192, 8192]");
    let spec = t.spec("big.toml", &big.replace("rays = [2, 4]", "rays = [16384]"));
    let o = t.run(&spec, "out", "ref", &["--no-build-reference"]);
    let e = stderr(&o);
    assert!(e.starts_with("warning: this run will take about "), "{e}");
    assert!(e.contains("hemilab plan") && e.contains("resumes"), "{e}");
    let spec = t.spec("small.toml", &tiny_spec(16, ""));
    let o = t.run(&spec, "out", "ref", &["--no-build-reference"]);
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
}

//! Scene files and meshes: the shipped scenes load; every bad input is one error naming the file and
//! the line or key; bad triangles are dropped and counted, never a panic.

use hemilab::load::dropped_warning;
use hemilab::load::load_scene;
use std::path::Path;

/// A fresh directory for one test, removed when it passes.
fn temp_dir(name: &str) -> crate::support::common::Tmp {
    crate::support::common::Tmp::new(name)
}

const TOML: &str = "mesh = \"m.obj\"\nresolution = [8, 8]\nao_distance = 1.0\n\n[camera.perspective]\n\
    eye = [0.0, 0.0, 5.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 1.0, 0.0]\nfov_y_deg = 45.0\n";
const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

/// Writes the scene TOML and (if given) its mesh, and returns the load error text.
fn load_error(name: &str, toml: &str, obj: Option<&str>) -> (crate::support::common::Tmp, String) {
    let dir = temp_dir(name);
    let scene = dir.join("s.toml");
    std::fs::write(&scene, toml).unwrap();
    if let Some(obj) = obj {
        std::fs::write(dir.join("m.obj"), obj).unwrap();
    }
    let err = match load_scene(&scene) {
        Ok(_) => panic!("{name}: loaded a bad scene"),
        Err(e) => e.to_string(),
    };
    assert_eq!(hemilab::error::Error::Usage(String::new()).exit_code(), 2);
    (dir, err)
}

#[test]
fn shipped_scenes_load() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let cornell = load_scene(&root.join("scenes/cornell-box.toml")).unwrap();
    assert_eq!(
        (cornell.name.as_str(), cornell.triangle_count, cornell.dropped_triangles),
        ("cornell-box", 30, 0)
    );
    let kitchen = load_scene(&root.join("scenes/kitchen.toml")).unwrap();
    // 56,939 triangles in the file, of which 26 have zero area as written (read in f32, rounding
    // gave one of them a sliver of area).
    assert_eq!(kitchen.triangle_count + kitchen.dropped_triangles, 56_939);
    assert_eq!(kitchen.ao_distance, 1.0);
    assert!(dropped_warning(&kitchen).unwrap().contains("dropped 26 triangles"));
    assert_eq!(kitchen.content_hash.len(), 32);
    assert_ne!(kitchen.content_hash, cornell.content_hash);
}

#[test]
fn good_scene_with_degenerate_triangles_drops_and_counts_them() {
    let dir = temp_dir("degenerate");
    std::fs::write(dir.join("s.toml"), TOML.replace("ao_distance = 1.0", "ao_distance = \"infinite\""))
        .unwrap();
    std::fs::write(dir.join("m.obj"), format!("{QUAD}v 2 2 2\nv 4 4 4\nf 1 2 2\nf 5 6 1\n")).unwrap();
    let scene = load_scene(&dir.join("s.toml")).unwrap();
    assert_eq!((scene.triangle_count, scene.dropped_triangles), (2, 2));
    assert_eq!(scene.ao_distance, f32::INFINITY);
    assert!(dropped_warning(&scene).unwrap().contains("dropped 2 triangles"));
    // "inf" is the same as "infinite", as on the command line (`bench --distances inf`).
    std::fs::write(dir.join("s.toml"), TOML.replace("ao_distance = 1.0", "ao_distance = \"inf\"")).unwrap();
    assert_eq!(load_scene(&dir.join("s.toml")).unwrap().ao_distance, f32::INFINITY);
}

#[test]
fn missing_scene_and_missing_mesh_name_the_files() {
    let e = load_scene(Path::new("/nonexistent/hemilab/s.toml")).err().unwrap().to_string();
    assert!(e.contains("/nonexistent/hemilab/s.toml"), "{e}");
    let (dir, e) = load_error("missing-mesh", TOML, None);
    assert!(e.contains(&dir.join("s.toml").display().to_string()) && e.contains("`mesh`"), "{e}");
    assert!(e.contains(&dir.join("m.obj").display().to_string()), "{e}");
    assert!(e.contains("'m.obj' not found") && e.contains("relative to the scene file"), "{e}");
}

#[test]
fn bad_meshes_name_the_mesh_file_and_line() {
    for (name, obj, want) in [
        ("empty", "# no geometry\n", "empty mesh"),
        ("out-of-range", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 9\n", "line 4"),
        ("negative-out-of-range", "v 0 0 0\nf -1 -2 -3\n", "line 2"),
        ("zero-index", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 0 1 2\n", "line 4"),
        ("two-vertex-face", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2\n", "line 4"),
        ("bad-vertex", "v 0 0 0\nv 1 zero 0\n", "line 2"),
        ("all-degenerate", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "its one triangle has zero area"),
        ("binary", "\u{0}\u{1}\u{2}", "empty mesh"),
        // Once read as f64, then collapsed in f32: "empty mesh: no usable triangles", blamed on the
        // scene file, with no reason.
        (
            "huge-coordinate",
            "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n",
            "line 2: vertex coordinate 1e30 is beyond",
        ),
        (
            "infinite-coordinate",
            "v 0 0 0\nv 1 0 0\nv 0 1e999 0\nf 1 2 3\n",
            "line 3: vertex coordinate '1e999'",
        ),
        ("nan-coordinate", "v nan 0 0\n", "line 1: vertex coordinate 'nan' is not a finite number"),
        (
            "only-polylines",
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nl 1 2 3\n",
            "no faces (AO needs at least one triangle); skipped 1 `l`",
        ),
    ] {
        let (dir, e) = load_error(name, TOML, Some(obj));
        assert!(e.contains(&dir.join("m.obj").display().to_string()), "{name}: {e}");
        assert!(e.contains(want), "{name}: want '{want}' in: {e}");
    }
}

#[test]
fn bad_scene_files_name_the_line_and_key() {
    for (name, toml, want) in [
        ("unknown-key", TOML.replace("ao_distance", "ao_dist"), vec!["line 3", "ao_dist"]),
        ("unknown-camera-key", TOML.replace("fov_y_deg", "fov"), vec!["line 9", "fov"]),
        ("bad-fov", TOML.replace("45.0", "180.0"), vec!["line 9", "fov_y_deg", "(0, 180)"]),
        ("bad-distance", TOML.replace("1.0\n", "\"far\"\n"), vec!["line 3", "infinite"]),
        ("bad-resolution", TOML.replace("[8, 8]", "[8, 0]"), vec!["line 2", "resolution"]),
        (
            "bad-projection",
            TOML.replace("perspective", "fisheye"),
            vec!["line 5", "perspective", "orthographic"],
        ),
        ("missing-key", TOML.replace("resolution = [8, 8]\n", ""), vec!["resolution"]),
        ("eye-is-target", TOML.replace("[0.0, 0.0, 5.0]", "[0.0, 0.0, 0.0]"), vec!["camera", "eye"]),
        // `up` along the view once rendered an image rolled by rounding error.
        (
            "up-along-the-view",
            TOML.replace("up = [0.0, 1.0, 0.0]", "up = [0.0, 0.0, -2.0]"),
            vec!["line 8, key `camera.perspective.up`: [0, 0, -2]: up is parallel", "at least 0.057°"],
        ),
        (
            "up-nearly-along-the-view",
            TOML.replace("up = [0.0, 1.0, 0.0]", "up = [0.0, 0.0001, 1.0]"),
            vec!["line 8, key `camera.perspective.up`", "from parallel"],
        ),
        // A camera that sees nothing once rendered "0 AO rays" and exited 0 (and `run` failed only
        // after building a reference).
        (
            "camera-sees-nothing",
            TOML.replace("target = [0.0, 0.0, 0.0]", "target = [0.0, 0.0, 10.0]"),
            vec!["camera: sees no triangle of the mesh (none of the 8x8 primary rays", "aim `target`"],
        ),
        ("not-obj", TOML.replace("m.obj", "m.ply"), vec!["`mesh`", ".obj"]),
        (
            "a-spec",
            "# my spec\nscenes = [\"s.toml\"]\n[[table]]\nname = \"t\"\n".to_string(),
            vec!["line 2, key `scenes`", "this is an experiment spec, not a scene file"],
        ),
        // `[camera]` with the keys under it: the fix, not serde's "wanted exactly 1 element".
        (
            "camera-without-projection",
            TOML.replace("[camera.perspective]", "[camera]"),
            vec!["line 5, key `camera`: ", "[camera.perspective]", "[camera.orthographic]"],
        ),
        // No camera at all: the missing key and the fix, and no line (toml points at the first
        // character of the file, here a comment).
        (
            "missing-camera",
            format!("# my scene\n{}", &TOML[..TOML.find("[camera").unwrap()]),
            vec!["s.toml: key `camera`: missing; add a camera: write `[camera.perspective]`", "orthographic"],
        ),
        (
            "missing-camera-key",
            TOML.replace("fov_y_deg = 45.0\n", ""),
            vec!["line 5, key `camera.perspective.fov_y_deg`: missing; add `fov_y_deg"],
        ),
        (
            "too-many-pixels",
            TOML.replace("[8, 8]", "[16384, 16384]"),
            vec!["line 2", "at most 67108864 pixels"],
        ),
        (
            "three-sides",
            TOML.replace("[8, 8]", "[8, 8, 8]"),
            vec!["line 2, key `resolution`", "[width, height]"],
        ),
        (
            "four-coordinates",
            TOML.replace("[0.0, 0.0, 5.0]", "[0.0, 0.0, 5.0, 1.0]"),
            vec!["line 6", "[x, y, z]"],
        ),
    ] {
        let (dir, e) = load_error(name, &toml, Some(QUAD));
        assert!(e.contains(&dir.join("s.toml").display().to_string()), "{name}: {e}");
        assert_eq!(e.lines().count(), 1, "{name}: one line, as a spec's errors: {e}");
        assert!(!e.contains("line 1,"), "{name}: {e}");
        for w in want {
            assert!(e.contains(w), "{name}: want '{w}' in: {e}");
        }
    }
}

#[test]
fn polylines_points_and_comments_in_a_mesh() {
    // Once an `l` of three corners became a triangle (changing the image by up to 0.75), and a
    // comment after a vertex was a "color parse error" with no line.
    use hemilab::render::render;
    use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
    let dir = temp_dir("polylines");
    std::fs::write(dir.join("s.toml"), TOML).unwrap();
    let obj = "v 0 0 0 # corner\nv 1 0 0\nv 1 1 0\nv 0 1 0\n# the quad\nf 1 2 3 4 # two triangles\n\
               l 1 3 4\nl 1 2\np 2\nl -1 -2 -3\n";
    std::fs::write(dir.join("m.obj"), obj).unwrap();
    let with = load_scene(&dir.join("s.toml")).unwrap();
    assert_eq!((with.triangle_count, with.dropped_triangles), (2, 0));
    let w = dropped_warning(&with).unwrap();
    assert_eq!(
        w,
        "warning: scene 's': skipped mesh elements that are not faces: 3 `l` (polylines; first on line 7), \
         1 `p` (points; line 9); AO renders faces only"
    );
    std::fs::write(dir.join("m.obj"), QUAD).unwrap();
    let plain = load_scene(&dir.join("s.toml")).unwrap();
    assert!(dropped_warning(&plain).is_none());
    let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Shift, 8, 1).unwrap();
    let job = crate::support::jobs::render_job(Distribution::Sine, sampler, (8, 8), 1.0);
    let (a, b) = (render(&with, &job, &|_| {}), render(&plain, &job, &|_| {}));
    assert_eq!((a.ao, a.coverage), (b.ao, b.coverage), "skipped elements change nothing");
}

#[test]
fn committed_references_record_the_cameras_the_scenes_have() {
    // A manifest written before the camera was JSON holds it as a debug string; the JSON form
    // reproduces that string, so each committed reference keeps its file name and is reused.
    use hemilab::reference::{CameraRecord, Manifest};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut scenes = std::collections::HashMap::new();
    let mut checked = 0;
    for e in std::fs::read_dir(root.join("reference")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "json") {
            continue;
        }
        let m = Manifest::from_json(&std::fs::read_to_string(&p).unwrap()).unwrap();
        assert_eq!(m.file_stem(), p.file_stem().unwrap().to_string_lossy(), "{}", p.display());
        // A camera path's frame (the jittered orbit of experiments/realtime.toml) records the
        // frame's camera, not the scene's: its name is checked above, its camera by the run.
        if m.jitter_average {
            continue;
        }
        let view = *scenes.entry(m.scene.clone()).or_insert_with(|| {
            load_scene(&root.join("experiments").join(&m.scene)).unwrap_or_else(|e| panic!("{e}")).view
        });
        assert_eq!(CameraRecord::of(&view).legacy(), m.camera.legacy(), "{}", p.display());
        checked += 1;
    }
    assert!(checked >= 7, "{checked} manifests");
}

#[test]
fn shipped_validation_scene_matches_the_one_built_in_code() {
    use hemilab::render::render;
    use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let file = load_scene(&root.join("scenes/floating-rectangle.toml")).unwrap();
    let code = hemilab::scene::procedural::floating_rectangle(file.resolution);
    assert_eq!((file.triangle_count, file.camera, file.ao_distance), (4, code.camera, code.ao_distance));
    let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Shift, 8, 1).unwrap();
    let job = |s: &hemilab::scene::Scene| {
        crate::support::jobs::render_job(Distribution::Sine, sampler, (16, 16), s.ao_distance)
    };
    let (a, b) = (render(&file, &job(&file), &|_| {}), render(&code, &job(&code), &|_| {}));
    assert_eq!((a.ao, a.coverage), (b.ao, b.coverage));
}

#[test]
fn every_scene_file_loads_with_a_view_of_its_mesh() {
    // The seven shipped scenes: each loads without dropped triangles (the kitchen's 25 aside) and its
    // camera sees a surface in most of the image (a scene whose camera misses its mesh is useless).
    use hemilab::render::render;
    use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut names: Vec<String> = std::fs::read_dir(root.join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    assert!(names.len() >= 7, "{names:?}");
    let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Shift, 1, 1).unwrap();
    for name in names {
        let scene = load_scene(&root.join("scenes").join(&name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        if name != "kitchen.toml" {
            assert_eq!(scene.dropped_triangles, 0, "{name}");
        }
        let job =
            crate::support::jobs::render_job(Distribution::SineCosine, sampler, (32, 24), scene.ao_distance);
        let out = render(&scene, &job, &|_| {});
        let covered = out.coverage.data.iter().filter(|&&c| c > 0.5).count();
        assert!(covered * 2 > out.coverage.data.len(), "{name}: only {covered} of 768 pixels see the mesh");
    }
}

#[test]
fn committed_procedural_meshes_are_what_the_code_generates() {
    use hemilab::scene::{generate, mesh};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (name, text) in
        [("atrium", generate::atrium()), ("slats", generate::slats()), ("terrain", generate::terrain())]
    {
        let path = root.join(format!("scenes/{name}.obj.zst"));
        let stored = mesh::decompress(&std::fs::read(&path).unwrap()).unwrap();
        let stored = String::from_utf8(stored).unwrap();
        if let Some((no, (a, b))) = stored.lines().zip(text.lines()).enumerate().find(|(_, (a, b))| a != b) {
            panic!(
                "{}: line {} is '{a}' but the generator writes '{b}'; regenerate with \
                 `cargo run --release --example write_scenes` (see scenes/README.md)",
                path.display(),
                no + 1
            );
        }
        assert_eq!(stored.lines().count(), text.lines().count(), "{}", path.display());
    }
}

#[test]
fn rendering_a_small_scene_after_a_large_one_on_the_same_thread() {
    // The renderer keeps each thread's last occluders (triangle indices) across images; a spec with
    // several scenes renders a 30-triangle box right after the 57,000-triangle kitchen on the same
    // threads. That once indexed past the box's triangles and panicked.
    use hemilab::render::render;
    use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Shift, 16, 1).unwrap();
    let job = |s: &hemilab::scene::Scene| {
        crate::support::jobs::render_job(Distribution::SineCosine, sampler, (24, 16), s.ao_distance)
    };
    let big = load_scene(&root.join("scenes/kitchen.toml")).unwrap();
    let small = load_scene(&root.join("scenes/cornell-box.toml")).unwrap();
    let alone = pool.install(|| render(&small, &job(&small), &|_| {}));
    let after = pool.install(|| {
        render(&big, &job(&big), &|_| {});
        render(&small, &job(&small), &|_| {})
    });
    assert_eq!((after.ao, after.coverage), (alone.ao, alone.coverage), "the cache changed the answer");
}

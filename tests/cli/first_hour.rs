//! What a newcomer met in a first hour, each fixed and kept fixed: a missing scene file was the
//! operating system's bare "No such file or directory"; a spec with two typos named one; `--output`
//! into a missing directory made `a` for `a/../b` and anything under `/` without a word; `.lock`
//! files stayed beside the references after a run.

use crate::support::common::*;

#[test]
fn a_missing_scene_file_names_the_path_it_was_looked_for_at() {
    let t = Tmp::new("missing-scene");
    let o = t.hemilab(&["render", "nope.toml", "--rays", "1", "--output", "x.exr"]);
    let e = assert_error(&o, "nope.toml");
    assert!(e.contains("scene file not found (looked for "), "{e}");
    assert!(e.contains(&format!("{}/nope.toml", t.0.display())), "the absolute path: {e}");
    assert!(!e.contains("os error"), "{e}");
    let o = t.hemilab(&["advise", "nope.toml", "--quiet"]);
    let e = assert_error(&o, "nope.toml");
    assert!(e.contains("scene file not found"), "{e}");
    let o = t.hemilab(&["plan", "nospec.toml"]);
    let e = assert_error(&o, "nospec.toml");
    assert!(e.contains("spec file not found (looked for "), "{e}");
    assert!(t.listing().is_empty(), "nothing written: {:?}", t.listing());
}

#[test]
fn a_spec_with_two_typos_and_a_bad_value_reports_all_three() {
    let t = Tmp::new("typos");
    let text = tiny_spec(16, "")
        .replace("replicates = 2\nseed = 3", "replicate = 2\nseed = -3")
        .replace("[reference]\nrays = 16", "[reference]\nray = 16");
    let spec = t.spec("typos.toml", &text);
    let before = t.listing();
    let e = assert_error(&t.run(&spec, "out", "ref", &[]), &spec.display().to_string());
    let lines: Vec<&str> = e.lines().collect();
    assert_eq!(lines.len(), 3, "{e}");
    assert!(
        lines[0].contains("line 4, key `replicate`: unknown field `replicate` (did you mean `replicates`?)")
    );
    assert!(lines[1].contains("line 5, key `seed`: -3 is out of range"), "{e}");
    assert!(
        lines[2].contains("line 8, key `reference.ray`: unknown field `ray` (did you mean `rays`?)"),
        "{e}"
    );
    assert!(lines.iter().all(|l| l.contains(&format!("{}: line ", spec.display()))), "{e}");
    assert_eq!(t.listing(), before, "nothing written");
}

fn render_to(t: &Tmp, output: &str) -> std::process::Output {
    let scene = scene("cornell-box.toml");
    t.hemilab(&["render", &scene, "--rays", "1", "--resolution", "8x6", "--quiet", "--output", output])
}

#[test]
fn output_into_a_missing_directory_is_made_where_the_path_says() {
    let t = Tmp::new("output-dir");
    let o = render_to(&t, "a/../b/c/x.exr");
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(t.listing(), ["b", "b/c", "b/c/x.exr", "b/c/x.png"], "no `a` made for `a/..`");
    assert_eq!(
        stderr(&o),
        format!("note: created the directory {}/b/c for --output (it did not exist)\n", t.0.display()),
        "the note names the absolute directory"
    );

    // A directory that would be made right under `/` is refused: one error, exit 2, nothing made.
    let top = format!("/hemilab-test-no-such-dir-{}", std::process::id());
    let o = render_to(&t, &format!("{top}/x.exr"));
    let e = assert_error(&o, &top);
    assert!(e.contains("directly under the filesystem root") && e.contains("create it first"), "{e}");
    assert!(!std::path::Path::new(&top).exists(), "{top} was made");
    let o = t.hemilab(&[
        "points",
        "--distribution",
        "sine",
        "--sequence",
        "random",
        "--count",
        "4",
        "--output",
        &format!("{top}/p.png"),
    ]);
    assert_error(&o, &top);
    assert!(!std::path::Path::new(&top).exists(), "{top} was made");
}

#[test]
fn no_lock_file_stays_after_a_run() {
    let t = Tmp::new("locks");
    let spec = t.spec("tiny.toml", &tiny_spec(16, ""));
    t.run_ok(&spec, "out", "ref", &[]);
    let stray: Vec<String> = t.listing().into_iter().filter(|f| f.ends_with(".lock")).collect();
    assert!(stray.is_empty(), "{stray:?}");
    assert!(
        t.listing().iter().any(|f| f.starts_with("ref/") && f.ends_with(".exr")),
        "a reference was built"
    );
}

/// A camera under the Cornell box's floor sees its underside and, below the horizon, nothing: it
/// passes the "sees a triangle" check, so it is warned about (file and key), and the preview draws
/// "no surface" as a blue checkerboard, never as the black of full occlusion.
#[test]
fn a_camera_under_the_floor_is_warned_about_and_no_surface_is_not_black() {
    let t = Tmp::new("under-floor");
    let mesh = scene("cornell-box.obj");
    let under = format!(
        "mesh = \"{mesh}\"\nresolution = [32, 24]\nao_distance = 150.0\n[camera.perspective]\n\
         eye = [278.0, -60.0, 280.0]\ntarget = [278.0, -60.0, 600.0]\nup = [0.0, 1.0, 0.0]\nfov_y_deg = 60.0\n"
    );
    t.spec("under.toml", &under);
    let o = t.hemilab(&["render", "under.toml", "--rays", "2", "--quiet", "--output", "x.exr"]);
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    assert!(
        e.starts_with(
            "warning: under.toml: key `camera.perspective.eye`: the eye looks to be under the floor"
        ),
        "{e}"
    );
    assert!(e.contains("blue checkerboard"), "{e}");
    let channels = hemilab::io::read_exr(&t.path("x.exr")).unwrap();
    let a = &channels.iter().find(|(n, _)| n == "A").unwrap().1;
    let png = image::load_from_memory(&std::fs::read(t.path("x.png")).unwrap()).unwrap().to_rgb8();
    let (mut background, mut surface) = (0, 0);
    for (i, &c) in a.data.iter().enumerate() {
        let p = png.get_pixel(i as u32 % 32, i as u32 / 32).0;
        if c == 0.0 {
            background += 1;
            assert!(p[2] > p[0] + 40, "no surface at pixel {i} is drawn blue, not {p:?}");
        } else {
            surface += 1;
            assert!(p[0] == p[1] && p[1] == p[2], "a surface is drawn gray, not {p:?}");
        }
    }
    assert!(background > 0 && surface > 0, "{background} background, {surface} surface pixels");

    // The committed scene itself, seen from its own camera, is no such view.
    let o = t.hemilab(&[
        "render",
        &scene("cornell-box.toml"),
        "--rays",
        "1",
        "--resolution",
        "8x6",
        "--quiet",
        "--output",
        "y.exr",
    ]);
    assert!(o.status.success() && !stderr(&o).contains("warning"), "{}", stderr(&o));
}

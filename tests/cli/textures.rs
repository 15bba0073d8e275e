//! Noise textures and point files on the command line: `render`, `points`, `run` and
//! `advise` take the engines' seed modes, a texture (`texture:PATH[:use]`, a spec's
//! `{ texture = .., use = .. }`) and a point file (`points:PATH`, `{ points = .. }`); a texture of
//! hemilab's own mask renders the built-in mode's image; results name the file and its content, so
//! an edited file is measured anew; a skewed texture loads with one warning; every bad file is one
//! error naming the file and the reason, exit status 2, nothing written.

use crate::support::common::{Tmp, assert_error, scene, stderr, stdout};
use hemilab::load::texture::{Own, own_masks};

/// A directory holding hemilab's own masks (PNG and EXR), a point file and bad files.
fn setup(name: &str) -> Tmp {
    let t = Tmp::new(name);
    std::fs::create_dir_all(t.path("masks")).unwrap();
    for which in [Own::BlueNoise, Own::Stbn] {
        for png in [true, false] {
            for (file, bytes) in own_masks(which, png).unwrap() {
                std::fs::write(t.path(&format!("masks/{file}")), bytes).unwrap();
            }
        }
    }
    std::fs::write(t.path("pts.txt"), "0.1 0.1\n0.6 0.3\n0.35 0.85\n0.8 0.7\n").unwrap();
    std::fs::write(t.path("junk.png"), "not an image").unwrap();
    std::fs::write(t.path("out.txt"), "0.1 0.2\n0.3 1.5\n").unwrap();
    image::GrayImage::from_fn(8, 8, |x, y| image::Luma([(x * 8 + y) as u8]))
        .save(t.path("grey.png"))
        .unwrap();
    image::GrayImage::from_fn(8, 8, |x, _| image::Luma([x as u8])).save(t.path("dark.png")).unwrap();
    image::RgbImage::from_fn(8, 8, |_, _| image::Rgb([128, 128, 255])).save(t.path("up.png")).unwrap();
    t
}

fn render(t: &Tmp, mode: &str, out: &str, extra: &[&str]) -> std::process::Output {
    let scene = scene_path();
    let mut args = vec!["render", &scene, "--rays", "4", "--resolution", "24x18", "--seed-mode", mode];
    args.extend(["--output", out, "--quiet"]);
    args.extend(extra);
    t.hemilab(&args)
}

fn scene_path() -> String {
    scene("cornell-box.toml")
}

fn ao_bits(t: &Tmp, file: &str) -> Vec<u32> {
    let channels = hemilab::io::read_exr(&t.path(file)).unwrap();
    let y = &channels.iter().find(|(n, _)| n == "Y").unwrap().1;
    y.data.iter().map(|v| v.to_bits()).collect()
}

#[test]
fn render_reads_textures_and_points_and_own_masks_give_the_built_in_images() {
    let t = setup("cli-textures-render");
    for (mode, built_in, frame) in [
        ("texture:masks/blue_noise.png", "blue-noise", "0"),
        ("texture:masks/blue_noise.exr:offset", "blue-noise", "3"),
        ("texture:masks/stbn_%d.png", "stbn", "37"),
    ] {
        let a = render(&t, mode, "a.exr", &["--frame", frame]);
        assert!(a.status.success(), "{mode}: {}", stderr(&a));
        let b = render(&t, built_in, "b.exr", &["--frame", frame]);
        assert!(b.status.success(), "{}", stderr(&b));
        assert_eq!(ao_bits(&t, "a.exr"), ao_bits(&t, "b.exr"), "{mode} vs {built_in} at frame {frame}");
    }
    for (mode, extra) in [
        ("ign", vec!["--schedule", "r1", "--frame", "5"]),
        ("bayer", vec![]),
        ("magic-square", vec![]),
        ("r2-dither", vec!["--sequence", "points:pts.txt"]),
        ("texture:masks/stbn_%d.exr:rotation", vec!["--sequence", "sobol"]),
    ] {
        let o = render(&t, mode, "c.exr", &extra);
        assert!(o.status.success(), "{mode}: {}", stderr(&o));
    }
    // The EXR's provenance names the texture by path, use and content hash.
    let p = hemilab::image::decode_exr_provenance(&std::fs::read(t.path("c.exr")).unwrap()).unwrap().unwrap();
    let m = p.json["seed_mode"].as_str().unwrap();
    assert!(
        m.starts_with("texture:masks/stbn_%d.exr:rotation#")
            && m.len() == "texture:masks/stbn_%d.exr:rotation#".len() + 8,
        "{m}"
    );
}

#[test]
fn points_draws_a_texture_and_a_point_file_panel() {
    let t = setup("cli-textures-points");
    let o = t.hemilab(&[
        "points",
        "--distribution",
        "sine-cosine",
        "--sequence",
        "points:pts.txt",
        "--seed-mode",
        "shift",
        "--count",
        "4",
        "--output",
        "p.png",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("points pts.txt"), "{}", stdout(&o));
    let o = t.hemilab(&[
        "points",
        "--distribution",
        "sine-cosine",
        "--sequence",
        "fibonacci",
        "--seed-mode",
        "texture:masks/stbn_%d.png",
        "--count",
        "64",
        "--frame",
        "3",
        "--output",
        "q.svg",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("texture masks/stbn_%d.png (offset)"), "{}", stdout(&o));
    for f in ["p.png", "q.svg"] {
        assert!(std::fs::metadata(t.path(f)).unwrap().len() > 100, "{f}");
    }
}

#[test]
fn run_names_files_by_path_and_content_and_remeasures_an_edited_one() {
    let t = setup("cli-textures-run");
    let spec = t.spec(
        "s.toml",
        &format!(
            r#"scenes = ["{}"]
resolution = [16, 12]
replicates = 2
[reference]
rays = 32
replicates = 2
[[table]]
name = "t"
rays = [2]
distributions = ["sine-cosine"]
sequences = ["fibonacci", {{ points = "pts.txt" }}]
seed_modes = ["ign", {{ texture = "masks/stbn_%d.png", use = "offset" }}]
"#,
            scene_path()
        ),
    );
    let first = t.run_ok(&spec, "out", "ref", &[]);
    let csv = std::fs::read_to_string(t.path("out/results.csv")).unwrap();
    assert!(csv.contains(",texture:masks/stbn_%d.png:offset#"), "{csv}");
    assert!(csv.contains(",points:pts.txt#"), "{csv}");
    assert!(stdout(&first).contains("8 rendered"), "{}", stdout(&first));
    let again = t.run_ok(&spec, "out", "ref", &[]);
    assert!(stdout(&again).contains("0 rendered, 8 reused"), "{}", stdout(&again));
    // An edited point file is another sequence: its jobs are measured anew, the others reused.
    std::fs::write(t.path("pts.txt"), "0.15 0.1\n0.6 0.3\n0.35 0.85\n0.8 0.7\n").unwrap();
    let edited = t.run_ok(&spec, "out", "ref", &[]);
    assert!(stdout(&edited).contains("4 rendered, 4 reused"), "{}", stdout(&edited));
}

#[test]
fn advise_measures_a_texture_and_a_point_file() {
    let t = setup("cli-textures-advise");
    let o = t.hemilab(&[
        "advise",
        &scene_path(),
        "--resolution",
        "12x8",
        "--rays",
        "1,2",
        "--replicates",
        "2",
        "--only",
        "sine-cosine/fibonacci/*",
        "--texture",
        "masks/blue_noise.png",
        "--points",
        "pts.txt",
        "--reference-dir",
        "ref",
        "--out",
        "adv",
        "--quiet",
        "--threads",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let advice = std::fs::read_to_string(t.path("adv/advice.json")).unwrap();
    assert!(advice.contains("texture:masks/blue_noise.png:offset#"), "the texture was measured");
    assert!(!advice.contains("points:pts.txt"), "--only sine-cosine/fibonacci/* leaves the point file out");
}

#[test]
fn a_skewed_texture_loads_with_one_warning() {
    let t = setup("cli-textures-warn");
    let o = render(&t, "texture:dark.png", "d.exr", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert_eq!(e.matches("warning:").count(), 1, "{e}");
    assert!(e.contains("texture 'dark.png' (offset)") && e.contains("Kuiper distance"), "{e}");
}

#[test]
fn bad_texture_and_point_files_exit_2_name_the_file_and_write_nothing() {
    let t = setup("cli-textures-bad");
    let before = t.listing();
    let scene = scene_path();
    for (mode, seq, dist, what, reason) in [
        ("texture:missing.png", "fibonacci", "sine-cosine", "--seed-mode texture:missing.png", "not found"),
        (
            "texture:junk.png",
            "fibonacci",
            "sine-cosine",
            "--seed-mode texture:junk.png",
            "junk.png is not a readable PNG",
        ),
        (
            "texture:grey.png:vector",
            "fibonacci",
            "sine-cosine",
            "--seed-mode texture:grey.png:vector",
            "needs 3",
        ),
        (
            "texture:masks/stbn_%d.png:vector",
            "random",
            "sine-cosine",
            "--seed-mode texture:masks/stbn_%d.png:vector",
            "needs 3",
        ),
        (
            "shift",
            "points:out.txt",
            "sine-cosine",
            "--sequence points:out.txt",
            "line 2: point (0.3, 1.5) is outside",
        ),
        ("shift", "points:none.npy", "sine-cosine", "--sequence points:none.npy", "not found"),
        ("shift", "points:pts.txt", "sine-cosine", "--rays 8", "holds 4 points per pixel"),
    ] {
        for cmd in ["render", "points"] {
            let mut args = vec![cmd, "--distribution", dist, "--sequence", seq, "--seed-mode", mode];
            if cmd == "render" {
                args.insert(1, &scene);
                args.extend(["--rays", "8", "--resolution", "8x6", "--output", "x.exr"]);
            } else {
                args.extend(["--count", "8", "--output", "x.png"]);
            }
            let o = t.hemilab(&args);
            let what = if cmd == "points" { what.replace("--rays 8", "--count 8") } else { what.to_string() };
            let e = assert_error(&o, &what);
            assert!(e.contains(reason), "{cmd} {mode} {seq}: {e}");
            assert_eq!(t.listing(), before, "{cmd} {mode} {seq} wrote something");
        }
    }
    // In a spec: one error per bad entry, each with its line and key.
    let spec = t.spec(
        "bad.toml",
        &format!(
            r#"scenes = ["{}"]
[[table]]
name = "t"
rays = [2]
distributions = ["sine-cosine"]
sequences = [{{ points = "out.txt" }}]
seed_modes = [{{ texture = "junk.png" }}, {{ texture = "masks/blue_noise.png", use = "sideways" }}, {{ textur = "x.png" }}]
"#,
            scene_path()
        ),
    );
    let before = t.listing();
    let o = t.hemilab(&["run", spec.to_str().unwrap(), "--out", "o", "--reference-dir", "ref"]);
    let e = assert_error(&o, spec.to_str().unwrap());
    for want in [
        "line 6, key `table.sequences` (table 't'): point file",
        "out.txt: line 2: point (0.3, 1.5) is outside [0, 1)²",
        "line 7, key `table.seed_modes` (table 't'): texture",
        "junk.png is not a readable PNG",
        "unknown texture use 'sideways'",
        "unknown key `textur`",
    ] {
        assert!(e.contains(want), "{want}: {e}");
    }
    assert_eq!(t.listing(), before, "a bad spec wrote something");
    // A vector texture with another warp: refused at its row.
    let spec = t.spec(
        "vec.toml",
        &format!(
            r#"scenes = ["{}"]
[[table]]
name = "t"
rays = [2]
rows = [{{ distribution = "uniform", sequence = "random", seed_mode = {{ texture = "masks/stbn_%d.png", use = "rotation" }} }},
        {{ distribution = "uniform", sequence = "random", seed_mode = {{ texture = "up.png", use = "vector" }} }}]
"#,
            scene_path()
        ),
    );
    let o = t.hemilab(&["plan", spec.to_str().unwrap()]);
    // (The one-direction texture also gets its warning: its azimuths are anything but uniform.)
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert_eq!(e.matches("error:").count(), 1, "{e}");
    assert!(e.contains("line 6, key `table.rows` (table 't'): seed mode 'texture:up.png:vector#"), "{e}");
    assert!(e.contains("its distribution must be sine-cosine, not uniform"), "{e}");
}

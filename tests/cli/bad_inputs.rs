//! The reproducers of the inputs' readers, through the real binary: each bad file is one
//! message naming it, exit status 2, within seconds (the binary is run under a limit that only a
//! hang reaches), where each once panicked (exit 101), aborted (134) or read forever.

use crate::support::common::{Tmp, scene, stderr};
use crate::support::gltf_ext::masked_square;
use hemilab::scene::gltf_write::glb;
use serde_json::json;
use std::process::{Command, Output, Stdio};
use std::time::Duration;
use wait_timeout::ChildExt;

/// Far above the milliseconds a refusal takes; only a hang reaches it.
const LIMIT: Duration = Duration::from_secs(120);

/// `hemilab ARGS` in `t`, killed (and the test failed) if it runs past `LIMIT`.
fn bounded(t: &Tmp, args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_hemilab"))
        .args(args)
        .current_dir(&**t)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    if child.wait_timeout(LIMIT).unwrap().is_none() {
        child.kill().unwrap();
        panic!("hemilab {args:?} still ran after {LIMIT:?}: a hang");
    }
    child.wait_with_output().unwrap()
}

/// Exit 2 and one line naming `names` and saying `phrase`.
fn refused(o: &Output, names: &str, phrase: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "expected exit 2, got {:?}:\n{e}", o.status);
    assert_eq!(e.trim_end().lines().count(), 1, "one message:\n{e}");
    assert!(e.contains(names) && e.contains(phrase), "'{e}' lacks '{names}' or '{phrase}'");
}

fn render(t: &Tmp, scene: &str, extra: &[&str]) -> Output {
    let mut args =
        vec!["render", scene, "--rays", "2", "--resolution", "8x6", "--output", "o.exr", "--quiet"];
    args.extend(extra);
    bounded(t, &args)
}

#[test]
fn bad_textures_and_point_sets_are_one_message() {
    let t = Tmp::new("bad-textures");
    let cornell = scene("cornell-box.toml");
    image::GrayImage::from_fn(4, 4, |x, y| image::Luma([(x * 64 + y * 16) as u8]))
        .save(t.path("t.png"))
        .unwrap();
    let o = render(&t, &cornell, &["--seed-mode", "texture:s_%099999999999d.png"]);
    refused(&o, "s_%099999999999d.png", "N up to 9");
    let o = render(&t, &cornell, &["--seed-mode", "texture:/dev/zero"]);
    refused(&o, "/dev/zero", "not a regular file");
    let o = render(&t, &cornell, &["--seed-mode", "texture:t.png:diagonal"]);
    refused(&o, "t.png:diagonal", "valid: offset, rotation, vector");
    for shape in ["(4611686018427387904, 2)", "(2, 4611686018427387904, 2)"] {
        let header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}\n");
        let mut npy = b"\x93NUMPY\x01\x00".to_vec();
        npy.extend((header.len() as u16).to_le_bytes());
        npy.extend(header.as_bytes());
        npy.extend([0u8; 64]);
        std::fs::write(t.path("p.npy"), npy).unwrap();
        let o = render(&t, &cornell, &["--sequence", "points:p.npy"]);
        refused(&o, "p.npy", "needs more than 2^64");
    }
    assert!(!t.path("o.exr").exists(), "nothing written");
}

/// A change to a glTF file's JSON.
type Edit = dyn Fn(&mut serde_json::Value);

#[test]
fn bad_gltf_files_are_one_message_naming_the_file_and_the_object() {
    let t = Tmp::new("bad-gltf");
    std::fs::write(
        t.path("s.toml"),
        "mesh = \"m.glb\"\nresolution = [32, 24]\nao_distance = 1.0\n[camera.perspective]\n\
         eye = [0.5, 0.5, 3.0]\ntarget = [0.5, 0.5, 0.0]\nup = [0.0, 1.0, 0.0]\nfov_y_deg = 45.0\n",
    )
    .unwrap();
    let cases: Vec<(Box<Edit>, &str)> = vec![
        (
            Box::new(|d| {
                let a = d["meshes"][1]["primitives"][0]["indices"].as_u64().unwrap() as usize;
                d["accessors"][a]["componentType"] = json!(5126);
            }),
            "indices are SCALAR of UNSIGNED_BYTE",
        ),
        (Box::new(|d| d["nodes"][0]["children"] = json!([0])), "a cycle among `children` (0 → 0)"),
        (Box::new(|d| d["materials"][0]["alphaCutoff"] = json!(2.0)), "materials[0]: alphaCutoff 2.0"),
        (Box::new(|d| d["materials"][0]["alphaCutoff"] = json!(-1)), "materials[0]: alphaCutoff -1"),
        (Box::new(|d| d["images"][0] = json!({})), "images[0]: has neither a `uri` nor a `bufferView`"),
    ];
    for (edit, phrase) in cases {
        let (mut doc, bin) = masked_square().encode(None);
        edit(&mut doc);
        std::fs::write(t.path("m.glb"), glb(&doc, &bin)).unwrap();
        let o = render(&t, "s.toml", &[]);
        refused(&o, "m.glb", phrase);
    }
    // A buffer that names a device.
    let (json, _) = masked_square().to_gltf("/dev/zero");
    std::fs::write(t.path("m.gltf"), json).unwrap();
    std::fs::write(
        t.path("d.toml"),
        std::fs::read_to_string(t.path("s.toml")).unwrap().replace("m.glb", "m.gltf"),
    )
    .unwrap();
    let o = render(&t, "d.toml", &[]);
    refused(&o, "/dev/zero", "not a regular file");
    assert!(!t.path("o.exr").exists(), "nothing written");
}

//! glTF 2.0 meshes: an OBJ scene written as .glb or .gltf + .bin renders the same bits; node
//! transforms, instancing, strips, fans and unindexed primitives give the triangles they should;
//! the file's first camera stands in for a missing TOML camera; every bad file is one error naming
//! the file and the reason.

use super::support::common::Tmp;
use hemilab::load::load_scene;
use hemilab::render::render;
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::gltf_write::{Doc, Material, Node, Prim, soup};
use hemilab::scene::{Camera, Scene};
use std::path::Path;

const CAMERA: &str = "[camera.perspective]\neye = [278.0, 273.0, -800.0]\ntarget = [278.0, 273.0, 0.0]\n\
    up = [0.0, 1.0, 0.0]\nfov_y_deg = 39.3077\n";

fn toml(mesh: &str, camera: &str) -> String {
    format!("mesh = \"{mesh}\"\nresolution = [32, 24]\nao_distance = 150.0\n{camera}")
}

/// The Cornell box's triangles rounded to f32 (glTF stores f32), as written in both files.
fn cornell_f32() -> Vec<[[f32; 3]; 3]> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let bytes = std::fs::read(root.join("scenes/cornell-box.obj")).unwrap();
    let mesh = hemilab::scene::mesh::parse_obj(&bytes).unwrap();
    mesh.triangles().map(|t| t.map(|v| v.as_vec3().to_array())).collect()
}

/// An OBJ of the triangles, every coordinate printed exactly (f32 → f64 is exact; `{}` round-trips).
fn obj_text(tris: &[[[f64; 3]; 3]]) -> String {
    let mut s = String::new();
    for (i, t) in tris.iter().enumerate() {
        for v in t {
            s += &format!("v {} {} {}\n", v[0], v[1], v[2]);
        }
        s += &format!("f {} {} {}\n", 3 * i + 1, 3 * i + 2, 3 * i + 3);
    }
    s
}

fn widen(tris: &[[[f32; 3]; 3]]) -> Vec<[[f64; 3]; 3]> {
    tris.iter().map(|t| t.map(|v| v.map(f64::from))).collect()
}

fn image_bits(scene: &Scene) -> Vec<u32> {
    let job = crate::support::jobs::render_job(
        Distribution::SineCosine,
        SamplerConfig::new(Sequence::Random, SeedMode::Rotation, 8, 1).unwrap(),
        (32, 24),
        scene.ao_distance,
    );
    let out = render(scene, &job, &|_| {});
    out.ao.data.iter().chain(&out.coverage.data).map(|v| v.to_bits()).collect()
}

/// Writes `obj` as m.obj and `doc` as m.glb (and m.gltf + m.bin), and loads the three scenes.
fn three_ways(name: &str, obj: &str, doc: &Doc, camera: &str) -> [Scene; 3] {
    let t = Tmp::new(name);
    std::fs::write(t.path("m.obj"), obj).unwrap();
    std::fs::write(t.path("m.glb"), doc.to_glb()).unwrap();
    let (json, bin) = doc.to_gltf("m data.bin");
    std::fs::write(t.path("m.gltf"), json.replace("m data.bin", "m%20data.bin")).unwrap();
    std::fs::write(t.path("m data.bin"), bin).unwrap();
    ["m.obj", "m.glb", "m.gltf"].map(|m| {
        let p = t.path(&format!("{m}.toml"));
        std::fs::write(&p, toml(m, camera)).unwrap();
        load_scene(&p).unwrap_or_else(|e| panic!("{name} {m}: {e}"))
    })
}

#[test]
fn an_obj_scene_written_as_gltf_renders_the_same_image() {
    let tris = cornell_f32();
    let doc = Doc {
        meshes: vec![soup(&tris)],
        nodes: vec![Node { mesh: Some(0), ..Node::default() }],
        roots: vec![0],
        ..Doc::default()
    };
    let [obj, glb, gltf] = three_ways("cornell", &obj_text(&widen(&tris)), &doc, CAMERA);
    assert_eq!((obj.triangle_count, glb.triangle_count, gltf.triangle_count), (30, 30, 30));
    let want = image_bits(&obj);
    assert!(want.iter().any(|&b| b != 0));
    assert_eq!(image_bits(&glb), want, ".glb");
    assert_eq!(image_bits(&gltf), want, ".gltf + .bin");
}

#[test]
fn node_transforms_and_instances_place_every_copy() {
    let tris = cornell_f32();
    // The box drawn twice: once as is (under a parent scaled by 1), once moved by 600 along x
    // and scaled by 0.5 around the origin through a parent and a child matrix. Powers of two keep
    // every product exact, so the OBJ of the same copies has the same coordinates.
    let mut m = [0.0; 16];
    (m[0], m[5], m[10], m[15]) = (0.5, 0.5, 0.5, 1.0);
    let doc = Doc {
        meshes: vec![soup(&tris)],
        nodes: vec![
            Node { scale: Some([1.0; 3]), children: vec![1], ..Node::default() },
            Node { mesh: Some(0), ..Node::default() },
            Node { translation: Some([600.0, 0.0, 0.0]), children: vec![3], ..Node::default() },
            Node { mesh: Some(0), matrix: Some(m), ..Node::default() },
        ],
        roots: vec![0, 2],
        ..Doc::default()
    };
    let mut both = widen(&tris);
    both.extend(widen(&tris).iter().map(|t| t.map(|v| [v[0] * 0.5 + 600.0, v[1] * 0.5, v[2] * 0.5])));
    let camera = CAMERA
        .replace("[278.0, 273.0, -800.0]", "[450.0, 273.0, -1400.0]")
        .replace("[278.0, 273.0, 0.0]", "[450.0, 273.0, 0.0]");
    let [obj, glb, gltf] = three_ways("instances", &obj_text(&both), &doc, &camera);
    assert_eq!((obj.triangle_count, glb.triangle_count), (60, 60));
    let want = image_bits(&obj);
    assert_eq!(image_bits(&glb), want);
    assert_eq!(image_bits(&gltf), want);
}

#[test]
fn strips_fans_and_unindexed_lists_give_the_triangles_of_a_list() {
    // A unit square facing the camera and a triangle beside it.
    let (a, b, c, d) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]);
    let tri = [[1.5, 0.0, 0.0], [2.5, 0.0, 0.0], [2.0, 1.0, 0.0]];
    let list = [[a, b, c], [a, c, d], tri];
    let prim = |positions: Vec<[f32; 3]>, indices: Option<Vec<u32>>, mode| Prim {
        positions,
        indices,
        mode,
        ..Prim::default()
    };
    let doc = Doc {
        meshes: vec![vec![
            // strip a b d c: (a b d), (b c d): the square cut along b–d, winding kept.
            prim(vec![a, b, c, d], Some(vec![0, 1, 3, 2]), 5),
            // fan around a, unindexed: (b c a), (c d a).
            prim(vec![a, b, c, d], None, 6),
            // an unindexed list.
            prim(tri.to_vec(), None, 4),
        ]],
        nodes: vec![Node { mesh: Some(0), ..Node::default() }],
        roots: vec![0],
        ..Doc::default()
    };
    let mut obj_tris = widen(&[[a, b, d], [b, c, d]]);
    obj_tris.extend(widen(&list));
    let camera = "[camera.perspective]\neye = [1.25, 0.5, 3.0]\ntarget = [1.25, 0.5, 0.0]\n\
        up = [0.0, 1.0, 0.0]\nfov_y_deg = 60.0\n";
    let [obj, glb, _] = three_ways("strips", &obj_text(&obj_tris), &doc, camera);
    assert_eq!((obj.triangle_count, glb.triangle_count), (5, 5));
    let corners = |s: &Scene| {
        let mut v: Vec<_> = (0..s.triangle_count as u32)
            .map(|p| {
                let t = s.accel.triangle(p).map(|v| v.to_array().map(f32::to_bits));
                // Rotated so the least corner leads: the same triangle with the same winding.
                let k = (0..3).min_by_key(|&i| t[i]).unwrap();
                [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
            })
            .collect();
        v.sort();
        v
    };
    assert_eq!(corners(&glb), corners(&obj), "same triangles, same winding");
}

#[test]
fn the_files_first_camera_stands_in_for_a_missing_one() {
    // Camera 0 on a node 5 in front of the square along +z, looking down its −z; rotated about z
    // by 90° through the matrix, so its up is −x.
    let mut m = [0.0; 16];
    (m[1], m[4], m[10], m[15]) = (1.0, -1.0, 1.0, 1.0);
    (m[12], m[13], m[14]) = (0.5, 0.5, 5.0);
    let doc = Doc {
        meshes: vec![soup(&[
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]],
            [[0.0; 3], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
        ])],
        nodes: vec![
            Node { mesh: Some(0), ..Node::default() },
            Node { camera: Some(0), matrix: Some(m), ..Node::default() },
        ],
        roots: vec![0, 1],
        cameras: vec![0.5],
        ..Doc::default()
    };
    let t = Tmp::new("gltf-camera");
    std::fs::write(t.path("m.glb"), doc.to_glb()).unwrap();
    std::fs::write(t.path("s.toml"), toml("m.glb", "")).unwrap();
    let s = load_scene(&t.path("s.toml")).unwrap();
    let Camera::Perspective { eye, target, up, fov_y_deg } = s.view else { panic!("{:?}", s.view) };
    assert_eq!(eye.to_array(), [0.5, 0.5, 5.0]);
    assert_eq!(target.to_array(), [0.5, 0.5, 4.0]);
    assert_eq!(up.to_array(), [-1.0, 0.0, 0.0]);
    assert_eq!(fov_y_deg, 0.5f32.to_degrees());
    // The TOML's camera wins when it gives one.
    let own = "[camera.perspective]\neye = [0.5, 0.5, 3.0]\ntarget = [0.5, 0.5, 0.0]\nup = [0.0, 1.0, 0.0]\n\
        fov_y_deg = 39.3077\n";
    std::fs::write(t.path("s.toml"), toml("m.glb", own)).unwrap();
    let view = load_scene(&t.path("s.toml")).unwrap().view;
    assert!(matches!(view, Camera::Perspective { fov_y_deg, .. } if fov_y_deg == 39.3077), "{view:?}");
}

/// One error, naming `file`, containing each of `want`.
fn assert_load_error(dir: &Tmp, file: &str, want: &[&str]) {
    let e = match load_scene(&dir.path("s.toml")) {
        Ok(_) => panic!("loaded a bad file ({want:?})"),
        Err(e) => e.to_string(),
    };
    assert!(e.starts_with(&format!("{}: ", dir.path(file).display())), "{e}");
    assert_eq!(e.lines().count(), 1, "{e}");
    for w in want {
        assert!(e.contains(w), "want '{w}' in: {e}");
    }
}

#[test]
fn bad_gltf_files_are_one_error_naming_the_file_and_the_reason() {
    let square = soup(&[[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]]);
    let doc = |mode: u32| Doc {
        meshes: vec![vec![Prim { mode, ..square[0].clone() }]],
        nodes: vec![Node { mesh: Some(0), ..Node::default() }],
        roots: vec![0],
        ..Doc::default()
    };
    let t = Tmp::new("gltf-bad");
    std::fs::write(t.path("s.toml"), toml("m.gltf", CAMERA)).unwrap();
    let (json, _) = doc(4).to_gltf("gone.bin");
    std::fs::write(t.path("m.gltf"), json).unwrap();
    assert_load_error(&t, "m.gltf", &["buffer 0 ('gone.bin')", "not found", "gone.bin"]);

    std::fs::write(t.path("s.toml"), toml("m.glb", CAMERA)).unwrap();
    std::fs::write(t.path("m.glb"), doc(1).to_glb()).unwrap();
    assert_load_error(&t, "m.glb", &["mesh 0 primitive 0", "mode Lines is not supported", "TRIANGLES"]);

    std::fs::write(t.path("m.glb"), b"glTF not really").unwrap();
    assert_load_error(&t, "m.glb", &["not a readable glTF 2.0 file"]);

    let (json, bin) = doc(4).to_gltf("m.bin");
    std::fs::write(t.path("s.toml"), toml("m.gltf", CAMERA)).unwrap();
    std::fs::write(t.path("m.gltf"), json).unwrap();
    std::fs::write(t.path("m.bin"), &bin[..bin.len() / 2]).unwrap();
    assert_load_error(&t, "m.gltf", &["buffer 0", "truncated"]);

    // No camera anywhere: the scene file's fault.
    std::fs::write(t.path("m.bin"), &bin).unwrap();
    std::fs::write(t.path("s.toml"), toml("m.gltf", "")).unwrap();
    assert_load_error(&t, "s.toml", &["key `camera`: missing", "has no camera", "[camera.perspective]"]);
}

/// A 2×2 RGBA PNG: left column opaque, right column transparent.
fn half_mask_png() -> Vec<u8> {
    let img =
        image::RgbaImage::from_fn(2, 2, |x, _| image::Rgba([200, 200, 200, if x == 0 { 255 } else { 0 }]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// A square whose material is `MASK` with the given image bytes as its base colour texture.
fn masked_square(png: Vec<u8>) -> Doc {
    let mut prims =
        soup(&[[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]], [[0.0; 3], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]]);
    prims[0].uvs = Some(vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    prims[0].material = Some(0);
    Doc {
        meshes: vec![prims],
        nodes: vec![Node { mesh: Some(0), ..Node::default() }],
        roots: vec![0],
        materials: vec![Material { base_color_factor: [1.0; 4], texture: Some(0), alpha_cutoff: Some(0.5) }],
        images: vec![png],
        ..Doc::default()
    }
}

#[test]
fn alpha_masked_textures_cut_holes_and_a_bad_one_is_an_error() {
    let t = Tmp::new("gltf-mask");
    let own = "[camera.perspective]\neye = [0.5, 0.5, 3.0]\ntarget = [0.5, 0.5, 0.0]\nup = [0.0, 1.0, 0.0]\n\
        fov_y_deg = 45.0\n";
    std::fs::write(t.path("s.toml"), toml("m.glb", own)).unwrap();
    std::fs::write(t.path("m.glb"), masked_square(half_mask_png()).to_glb()).unwrap();
    let s = load_scene(&t.path("s.toml")).unwrap();
    assert!(hemilab::load::dropped_warning(&s).is_none(), "masks are applied: nothing to warn about");
    // The left half (u < 0.5) is opaque, the right half transparent: rays straight down from the eye's
    // height hit only on the left.
    let down = |x: f32| {
        let o = glam::Vec3::new(x, 0.5, 3.0) - s.origin.as_vec3();
        s.accel.closest(&hemilab::scene::accel::Ray::new(o, -glam::Vec3::Z, f32::INFINITY)).is_some()
    };
    assert!(down(0.2) && down(0.45) && !down(0.55) && !down(0.8));
    std::fs::write(t.path("m.glb"), masked_square(b"\x89PNG but not really".to_vec()).to_glb()).unwrap();
    assert_load_error(&t, "m.glb", &["mesh 0 primitive 0: image 0", "does not decode as PNG"]);
}

//! OBJ alpha masks (`map_d` in the material library, `scene::mtl`): a card masked by a `map_d`
//! texture renders bit for bit as the same card masked in glTF (whose closed form
//! `scene_alpha` checks), whichever channel, format, folder, option or compression carries the mask;
//! a library that is missing leaves the card solid with one warning; bad libraries and textures are
//! one error naming the mesh file, the library, its line and the reason; scenes whose libraries mask
//! nothing (the kitchen's) keep their content hash.

use crate::support::common::Tmp;
use hemilab::load::{dropped_warning, load_scene};
use hemilab::render::render;
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::Scene;
use hemilab::scene::gltf_write::{Doc, Material, Node, Prim};
use std::path::Path;

/// Floor (z = 0, ±2) and card (z = 0.8), as written in both formats (f32 values, printed exactly).
const FLOOR: [[f32; 3]; 4] = [[-2.0, -2.0, 0.0], [2.0, -2.0, 0.0], [2.0, 2.0, 0.0], [-2.0, 2.0, 0.0]];
const CARD: [[f32; 3]; 4] = [[-0.4, -0.3, 0.8], [0.6, -0.3, 0.8], [0.6, 0.5, 0.8], [-0.4, 0.5, 0.8]];
/// The card corners' texture coordinates in OBJ's convention (v = 0 at the image's bottom row).
const VT: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];

const TOML: &str = "resolution = [16, 16]\nao_distance = \"infinite\"\n[camera.orthographic]\n\
    eye = [0.1, 0.1, 10.0]\ntarget = [0.1, 0.1, 0.0]\nup = [0.0, 1.0, 0.0]\nview_width = 4.0\n";

/// 2 × 2 texels, only the top-left one opaque (`value` of each texel in the image's own row order).
fn opaque_top_left(x: u32, y: u32) -> u8 {
    if x == 0 && y == 0 { 255 } else { 0 }
}

fn encode(img: image::DynamicImage, format: image::ImageFormat) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, format).unwrap();
    out.into_inner()
}

fn rgba_png() -> Vec<u8> {
    let img = image::RgbaImage::from_fn(2, 2, |x, y| image::Rgba([9, 9, 9, opaque_top_left(x, y)]));
    encode(img.into(), image::ImageFormat::Png)
}

/// `obj` with a card of material `leaf` whose corners have texture coordinates `vt`.
fn obj(mtllib: &str, vt: [[f32; 2]; 4], textured: bool) -> String {
    let mut s = format!("mtllib {mtllib}\n");
    for v in FLOOR.iter().chain(&CARD) {
        s += &format!("v {} {} {}\n", v[0], v[1], v[2]);
    }
    for t in vt {
        s += &format!("vt {} {}\n", t[0], t[1]);
    }
    s += "usemtl floor\nf 1 2 3 4\nusemtl leaf\n";
    s += if textured { "f 5/1 6/2 7/3 8/4\n" } else { "f 5 6 7 8\n" };
    s
}

fn image_bits(scene: &Scene) -> Vec<u32> {
    let job = crate::support::jobs::render_job(
        Distribution::SineCosine,
        SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 32, 7).unwrap(),
        (16, 16),
        scene.ao_distance,
    );
    let out = render(scene, &job, &|_| {});
    out.ao.data.iter().chain(&out.coverage.data).map(|v| v.to_bits()).collect()
}

/// The glTF card: the same triangles, its texture coordinates glTF's (v' = 1 − v), the RGBA PNG.
fn gltf_card(t: &Tmp) -> Scene {
    let quad = |p: [[f32; 3]; 4], uvs: Option<Vec<[f32; 2]>>, material| Prim {
        positions: p.to_vec(),
        indices: Some(vec![0, 1, 2, 0, 2, 3]),
        mode: 4,
        uvs,
        material,
    };
    let uvs = VT.iter().map(|t| [t[0], 1.0 - t[1]]).collect();
    let doc = Doc {
        meshes: vec![vec![quad(FLOOR, None, None), quad(CARD, Some(uvs), Some(0))]],
        nodes: vec![Node { mesh: Some(0), ..Node::default() }],
        roots: vec![0],
        materials: vec![Material { base_color_factor: [1.0; 4], texture: Some(0), alpha_cutoff: Some(0.5) }],
        images: vec![rgba_png()],
        ..Doc::default()
    };
    std::fs::write(t.path("card.glb"), doc.to_glb()).unwrap();
    std::fs::write(t.path("g.toml"), format!("mesh = \"card.glb\"\n{TOML}")).unwrap();
    load_scene(&t.path("g.toml")).unwrap()
}

/// Writes `mesh` (OBJ text, or zstd-compressed if the name ends in .zst) and its scene file, loads it.
fn load_obj(t: &Tmp, name: &str, mesh: &str) -> Result<Scene, String> {
    let bytes = if name.ends_with(".zst") {
        ruzstd::encoding::compress_to_vec(mesh.as_bytes(), ruzstd::encoding::CompressionLevel::Fastest)
    } else {
        mesh.as_bytes().to_vec()
    };
    std::fs::write(t.path(name), bytes).unwrap();
    std::fs::write(t.path("o.toml"), format!("mesh = \"{name}\"\n{TOML}")).unwrap();
    load_scene(&t.path("o.toml")).map_err(|e| e.to_string())
}

#[test]
fn a_map_d_card_renders_as_the_same_card_masked_in_gltf() {
    let t = Tmp::new("obj-mask");
    let want = image_bits(&gltf_card(&t));
    std::fs::create_dir_all(t.path("tex")).unwrap();
    let grey = image::GrayImage::from_fn(2, 2, |x, y| image::Luma([opaque_top_left(x, y)]));
    std::fs::write(t.path("grey.png"), encode(grey.clone().into(), image::ImageFormat::Png)).unwrap();
    std::fs::write(t.path("tex/grey.tga"), encode(grey.into(), image::ImageFormat::Tga)).unwrap();
    std::fs::write(t.path("rgba.png"), rgba_png()).unwrap();
    let red = image::RgbImage::from_fn(2, 2, |x, y| image::Rgb([opaque_top_left(x, y), 255, 255]));
    std::fs::write(t.path("red.png"), encode(red.into(), image::ImageFormat::Png)).unwrap();
    // Texture coordinates halved and moved by −1, undone by -s 2 2 -o 1 1 (exact in f32).
    let moved = VT.map(|v| v.map(|c| (c - 1.0) / 2.0));
    let cases: [(&str, &str, [[f32; 2]; 4]); 6] = [
        ("card.obj", "map_d rgba.png", VT),               // the alpha channel
        ("card.obj", "map_d grey.png", VT),               // no alpha: luminance
        ("card.obj", "map_d -imfchan r red.png", VT),     // a chosen channel (luminance would be > 1/2)
        ("card.obj", "map_d -boost 2 tex\\grey.tga", VT), // TGA, a folder written the Windows way
        ("card.obj", "map_d -s 2 2 -o 1 1 rgba.png", moved),
        ("card.obj.zst", "map_d rgba.png", VT), // decoded in a stream
    ];
    for (name, map_d, vt) in cases {
        std::fs::write(t.path("card.mtl"), format!("newmtl floor\nKd 1 1 1\nnewmtl leaf\nd 0.3\n{map_d}\n"))
            .unwrap();
        let s = load_obj(&t, name, &obj("card.mtl", vt, true)).unwrap();
        assert!(s.accel.has_alpha() && dropped_warning(&s).is_none(), "{map_d}");
        assert_eq!(image_bits(&s), want, "{name}: {map_d}");
    }
    // Without its library the card is solid (one warning), and that image differs: the mask counts.
    let s = load_obj(&t, "card.obj", &obj("gone.mtl", VT, true)).unwrap();
    let w = dropped_warning(&s).unwrap_or_default();
    assert!(w.contains("material library 'gone.mtl' (mtllib on line 1): file not found"), "{w}");
    assert!(!s.accel.has_alpha());
    assert_ne!(image_bits(&s), want);
    // A library without map_d masks nothing, and its bytes do not enter the scene's hash.
    std::fs::write(t.path("plain.mtl"), "newmtl floor\nnewmtl leaf\nd 0\n").unwrap();
    let mesh = obj("plain.mtl", VT, false);
    let s = load_obj(&t, "card.obj", &mesh).unwrap();
    assert!(!s.accel.has_alpha() && dropped_warning(&s).is_none());
    let toml = format!("mesh = \"card.obj\"\n{TOML}");
    assert_eq!(s.content_hash, hemilab::scene::content_hash(&[toml.as_bytes(), mesh.as_bytes()]));
}

#[test]
fn the_kitchen_reads_its_library_and_keeps_its_hash() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let s = load_scene(&root.join("kitchen.toml")).unwrap();
    assert!(!s.accel.has_alpha());
    assert!(s.notes.is_empty(), "{:?}", s.notes);
    let toml = std::fs::read(root.join("kitchen.toml")).unwrap();
    let mesh = std::fs::read(root.join("kitchen.obj.zst")).unwrap();
    assert_eq!(s.content_hash, hemilab::scene::content_hash(&[&toml, &mesh]));
}

#[test]
fn bad_libraries_and_textures_are_one_error_naming_where() {
    let t = Tmp::new("obj-mask-bad");
    let obj_path = t.path("card.obj").display().to_string();
    std::fs::write(t.path("bad.png"), b"\x89PNG but not really").unwrap();
    for (mtl, textured, want) in [
        (
            "newmtl leaf\nmap_d gone.png\n",
            true,
            vec!["material library 'card.mtl', line 2: map_d texture 'gone.png'", "file not found"],
        ),
        (
            "newmtl leaf\nmap_d bad.png\n",
            true,
            vec!["map_d texture 'bad.png'", "does not decode as PNG or TGA"],
        ),
        (
            "newmtl leaf\nmap_d -foo x.png\n",
            true,
            vec!["material library 'card.mtl' (mtllib on line 1): line 2: map_d option '-foo'"],
        ),
        ("\nmap_d x.png\n", true, vec!["(mtllib on line 1): line 2: `map_d` before any `newmtl`"]),
        ("newmtl leaf\nmap_d bad.png\n", false, vec!["map_d texture 'bad.png'"]),
    ] {
        std::fs::write(t.path("card.mtl"), mtl).unwrap();
        let e = load_obj(&t, "card.obj", &obj("card.mtl", VT, textured)).err().unwrap();
        assert!(e.starts_with(&format!("{obj_path}: ")) && e.lines().count() == 1, "{e}");
        for w in want {
            assert!(e.contains(w), "want '{w}' in: {e}");
        }
    }
    std::fs::write(t.path("card.mtl"), "newmtl leaf\nmap_d rgba.png\n").unwrap();
    std::fs::write(t.path("rgba.png"), rgba_png()).unwrap();
    let e = load_obj(&t, "card.obj", &obj("card.mtl", VT, false)).err().unwrap();
    assert!(
        e.contains("line 17: a face of material 'leaf' has a corner without a texture coordinate"),
        "{e}"
    );
}

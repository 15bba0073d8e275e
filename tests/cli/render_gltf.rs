//! `hemilab render` on glTF scenes: a good .glb renders with the file's own camera; a bad file
//! (missing .bin, unsupported primitive mode, unreadable bytes) is one error naming the mesh file
//! and the reason, exit 2, and nothing is written, as is each glTF extension case that cannot be
//! honoured; the same for an OBJ masked by `map_d`. A required extension that touches neither
//! geometry nor masks renders, with one warning naming the file and the extension.

use super::support::common::{Tmp, assert_error};
use super::support::gltf_ext::{bad_extension_files, extension_source, masked_square};
use hemilab::scene::gltf_write::{Doc, Material, Node, soup};

/// Two triangles of a unit square at z = 0, and a camera 3 in front of it (yfov 0.8 rad).
fn square(mode: u32) -> Doc {
    let mut prims =
        soup(&[[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]], [[0.0; 3], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]]);
    prims[0].mode = mode;
    Doc {
        meshes: vec![prims],
        nodes: vec![
            Node { mesh: Some(0), ..Node::default() },
            Node { camera: Some(0), translation: Some([0.5, 0.5, 3.0]), ..Node::default() },
        ],
        roots: vec![0, 1],
        cameras: vec![0.8],
        ..Doc::default()
    }
}

const SCENE: &str = "mesh = \"m.glb\"\nresolution = [16, 12]\nao_distance = 1.0\n";

#[test]
fn a_glb_renders_with_its_own_camera() {
    let t = Tmp::new("gltf-render");
    std::fs::write(t.path("m.glb"), square(4).to_glb()).unwrap();
    std::fs::write(t.path("s.toml"), SCENE).unwrap();
    let o = t.hemilab(&["render", "s.toml", "--rays", "4", "--output", "out/x.exr"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(t.path("out/x.exr").exists() && t.path("out/x.png").exists());
}

#[test]
fn bad_gltf_files_exit_2_naming_the_file_and_write_nothing() {
    let t = Tmp::new("gltf-render-bad");
    let (json, _) = square(4).to_gltf("m.bin");
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("m.gltf", json.into_bytes(), "buffer 0 ('m.bin'): file not found"),
        ("m.glb", square(0).to_glb(), "mode Points is not supported"),
        ("m.glb", b"{ not json".to_vec(), "not a readable glTF 2.0 file"),
        ("m.glb", bad_texture(), "image 0: the base colour texture does not decode as PNG"),
        ("m.gltf", external_bad_texture(&t), "image 0: the base colour texture does not decode as PNG"),
        ("m.glb", no_texcoords(), "TEXCOORD_0: missing"),
    ];
    // Extensions that cannot be honoured: Draco, an unknown one on geometry or a mask, a mask texture
    // with no source hemilab decodes, a broken DDS, a corrupt meshopt stream.
    let cases = cases.into_iter().chain(bad_extension_files().into_iter().map(|(_, b, w)| ("m.glb", b, w)));
    for (mesh, bytes, want) in cases {
        std::fs::write(t.path(mesh), bytes).unwrap();
        std::fs::write(t.path("s.toml"), SCENE.replace("m.glb", mesh)).unwrap();
        let o = t.hemilab(&["render", "s.toml", "--rays", "4", "--output", "out/x.exr"]);
        let e = assert_error(&o, mesh);
        assert!(e.contains(want), "want '{want}' in: {e}");
        assert!(!t.path("out").exists(), "{mesh}: wrote output");
    }
}

#[test]
fn an_ignored_required_extension_renders_with_one_warning_line() {
    let t = Tmp::new("gltf-render-ext");
    let (mut doc, bin) = masked_square().encode(None);
    doc["materials"][0]["extensions"] = serde_json::json!({"AMD_split_roughnessMetallic": {}});
    hemilab::scene::gltf_write::declare(&mut doc, "AMD_split_roughnessMetallic", true);
    std::fs::write(t.path("m.glb"), hemilab::scene::gltf_write::glb(&doc, &bin)).unwrap();
    std::fs::write(t.path("s.toml"), OBJ_SCENE.replace("m.obj", "m.glb")).unwrap();
    let o = t.hemilab(&["render", "s.toml", "--rays", "4", "--output", "out/x.exr"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(warnings[0].contains("m.glb: requires extension 'AMD_split_roughnessMetallic'"), "{err}");
    // A DDS-only mask texture renders too.
    std::fs::write(
        t.path("m.glb"),
        extension_source("MSFT_texture_dds", super::support::gltf_ext::dds(false)),
    )
    .unwrap();
    let o = t.hemilab(&["render", "s.toml", "--rays", "4", "--output", "dds/x.exr"]);
    assert!(o.status.success() && t.path("dds/x.exr").exists(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The square with an alpha-masked material whose texture is not an image.
fn bad_texture() -> Vec<u8> {
    let mut doc = square(4);
    doc.meshes[0][0].uvs = Some(vec![[0.0; 2]; 6]);
    doc.meshes[0][0].material = Some(0);
    doc.materials = vec![Material { base_color_factor: [1.0; 4], texture: Some(0), alpha_cutoff: Some(0.5) }];
    doc.images = vec![b"not a png".to_vec()];
    doc.to_glb()
}

/// `bad_texture` as a .gltf whose image is a file beside it (as the foliage scene's is).
fn external_bad_texture(t: &Tmp) -> Vec<u8> {
    let mut doc = hemilab::scene::gltf_write::Doc { image_uris: vec!["leaf.png".into()], ..square(4) };
    doc.meshes[0][0].uvs = Some(vec![[0.0; 2]; 6]);
    doc.meshes[0][0].material = Some(0);
    doc.materials = vec![Material { base_color_factor: [1.0; 4], texture: Some(0), alpha_cutoff: Some(0.5) }];
    doc.images = vec![Vec::new()];
    std::fs::write(t.path("leaf.png"), b"\x89PNG truncated").unwrap();
    let (json, bin) = doc.to_gltf("e.bin");
    std::fs::write(t.path("e.bin"), bin).unwrap();
    json.into_bytes()
}

/// An alpha-masked textured material on a primitive without texture coordinates.
fn no_texcoords() -> Vec<u8> {
    let mut doc = square(4);
    doc.meshes[0][0].material = Some(0);
    doc.materials = vec![Material { base_color_factor: [1.0; 4], texture: Some(0), alpha_cutoff: Some(0.5) }];
    let img = image::RgbaImage::from_pixel(1, 1, image::Rgba([0, 0, 0, 255]));
    let mut png = std::io::Cursor::new(Vec::new());
    img.write_to(&mut png, image::ImageFormat::Png).unwrap();
    doc.images = vec![png.into_inner()];
    doc.to_glb()
}

/// The square as OBJ, its material `leaf` masked by `map_d` in `m.mtl`.
const MASKED_OBJ: &str = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
    usemtl leaf\nf 1/1 2/2 3/3 4/4\n";
const OBJ_SCENE: &str = "mesh = \"m.obj\"\nresolution = [16, 12]\nao_distance = 1.0\n[camera.perspective]\n\
    eye = [0.5, 0.5, 3.0]\ntarget = [0.5, 0.5, 0.0]\nup = [0.0, 1.0, 0.0]\nfov_y_deg = 45.0\n";

#[test]
fn obj_map_d_masks_render_and_bad_ones_exit_2_writing_nothing() {
    let t = Tmp::new("obj-mask-render");
    std::fs::write(t.path("m.obj"), MASKED_OBJ).unwrap();
    std::fs::write(t.path("s.toml"), OBJ_SCENE).unwrap();
    let img = image::GrayImage::from_fn(2, 2, |x, _| image::Luma([if x == 0 { 255 } else { 0 }]));
    img.save(t.path("mask.png")).unwrap();
    std::fs::write(t.path("bad.png"), b"not a png").unwrap();
    std::fs::write(t.path("m.mtl"), "newmtl leaf\nmap_d mask.png\n").unwrap();
    let o = t.hemilab(&["render", "s.toml", "--rays", "4", "--output", "ok/x.exr"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        !String::from_utf8_lossy(&o.stderr).contains("warning"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    for (mtl, want) in [
        (
            "newmtl leaf\nmap_d gone.png\n",
            "material library 'm.mtl', line 2: map_d texture 'gone.png': file not found",
        ),
        ("newmtl leaf\nmap_d bad.png\n", "map_d texture 'bad.png': does not decode as PNG or TGA"),
        ("newmtl leaf\nmap_d -t 1 mask.png\n", "line 2: map_d option -t (turbulence) is not supported"),
    ] {
        std::fs::write(t.path("m.mtl"), mtl).unwrap();
        let o = t.hemilab(&["render", "s.toml", "--rays", "4", "--output", "out/x.exr"]);
        let e = assert_error(&o, "m.obj");
        assert!(e.contains(want), "want '{want}' in: {e}");
        assert!(!t.path("out").exists(), "{mtl}: wrote output");
    }
}

//! glTF files as production pipelines ship them: quantized attributes (KHR_mesh_quantization) and
//! compressed buffer views (EXT_meshopt_compression, with and without the EXPONENTIAL filter) give
//! the bits of the plain file; KHR_texture_transform moves and turns a mask as the extension's
//! example says; a mask whose texture has only a DDS source (MSFT_texture_dds) is decoded; an
//! unknown required extension that touches neither geometry nor masks is one warning naming the
//! file and the extension; every other case (Draco, an unknown extension on geometry or on a mask,
//! a mask texture with no source hemilab decodes, a bad DDS, a corrupt stream) is one error. And
//! Crytek Sponza loads as AMD ships it, its three masks cutting holes.

use super::support::common::Tmp;
use super::support::gltf_ext::{bad_extension_files, dds, extension_source, masked_square};
use hemilab::load::{dropped_warning, load_scene};
use hemilab::render::render;
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::Scene;
use hemilab::scene::gltf_write::{declare, glb, meshopt_compress, quantize};
use serde_json::{Value, json};
use std::path::Path;

/// Looking straight down at the unit square [0, 1]² (z = 0) from z = 3.
const SCENE: &str = "mesh = \"m.glb\"\nresolution = [32, 24]\nao_distance = 1.0\n[camera.perspective]\n\
    eye = [0.5, 0.5, 3.0]\ntarget = [0.5, 0.5, 0.0]\nup = [0.0, 1.0, 0.0]\nfov_y_deg = 45.0\n";

/// Writes `glb` as m.glb beside the scene file and loads it.
fn load(t: &Tmp, glb: &[u8]) -> Result<Scene, String> {
    std::fs::write(t.path("m.glb"), glb).unwrap();
    std::fs::write(t.path("s.toml"), SCENE).unwrap();
    load_scene(&t.path("s.toml")).map_err(|e| e.to_string())
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

/// Whether a ray straight down at (x, y) stops on the square (z = 0) rather than the floor.
fn square_at(s: &Scene, x: f32, y: f32) -> bool {
    let o = glam::Vec3::new(x, y, 3.0) - s.origin.as_vec3();
    let hit = s.accel.closest(&hemilab::scene::accel::Ray::new(o, -glam::Vec3::Z, f32::INFINITY));
    hit.is_some_and(|h| h.t < 3.25)
}

#[test]
fn quantized_attributes_load_as_the_floats_they_encode() {
    let t = Tmp::new("gltf-quant");
    let (doc, bin) = masked_square().encode(None);
    let plain = load(&t, &glb(&doc, &bin)).unwrap();
    assert!(square_at(&plain, 0.2, 0.5) && !square_at(&plain, 0.8, 0.5));
    let want = image_bits(&plain);
    // Integer positions (SHORT) with normalized UNSIGNED_SHORT coordinates; normalized BYTE positions
    // with normalized UNSIGNED_BYTE coordinates; float positions with non-normalized SHORT ones.
    for (pos, uv) in
        [(Some((5122, false)), (5123, true)), (Some((5120, true)), (5121, true)), (None, (5122, false))]
    {
        let (mut doc, mut bin) = masked_square().encode(None);
        if let Some((c, n)) = pos {
            quantize(&mut doc, &mut bin, "POSITION", c, n);
        }
        quantize(&mut doc, &mut bin, "TEXCOORD_0", uv.0, uv.1);
        assert_eq!(doc["extensionsRequired"], json!(["KHR_mesh_quantization"]));
        let s = load(&t, &glb(&doc, &bin)).unwrap_or_else(|e| panic!("{pos:?} {uv:?}: {e}"));
        assert!(dropped_warning(&s).is_none(), "{:?}", dropped_warning(&s));
        assert_eq!(image_bits(&s), want, "{pos:?} {uv:?}");
    }
}

#[test]
fn meshopt_compressed_views_decode_to_the_plain_file() {
    let t = Tmp::new("gltf-meshopt");
    let (doc, bin) = masked_square().encode(None);
    let want = image_bits(&load(&t, &glb(&doc, &bin)).unwrap());
    for exponential in [false, true] {
        let (mut doc, bin) = masked_square().encode(None);
        let packed = meshopt_compress(&mut doc, &bin, exponential);
        let views = doc["bufferViews"].as_array().unwrap();
        let modes: Vec<&str> = views
            .iter()
            .filter_map(|v| v["extensions"]["EXT_meshopt_compression"]["mode"].as_str())
            .collect();
        assert!(["ATTRIBUTES", "TRIANGLES", "INDICES"].iter().all(|m| modes.contains(m)), "{modes:?}");
        let s = load(&t, &glb(&doc, &packed)).unwrap_or_else(|e| panic!("exponential {exponential}: {e}"));
        assert_eq!(image_bits(&s), want, "exponential {exponential}");
        // The same as .gltf beside its .bin: the fallback buffer has no URI and no bytes.
        doc["buffers"][0]["uri"] = json!("m.bin");
        std::fs::write(t.path("m.bin"), &packed).unwrap();
        std::fs::write(t.path("m.gltf"), serde_json::to_vec(&doc).unwrap()).unwrap();
        std::fs::write(t.path("s.toml"), SCENE.replace("m.glb", "m.gltf")).unwrap();
        let s = load_scene(&t.path("s.toml")).unwrap();
        assert_eq!(image_bits(&s), want, ".gltf, exponential {exponential}");
    }
}

/// `masked_square` whose base colour texture info carries `transform` (KHR_texture_transform).
fn transformed(transform: Value) -> Vec<u8> {
    let (mut doc, bin) = masked_square().encode(None);
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
        json!({"KHR_texture_transform": transform});
    declare(&mut doc, "KHR_texture_transform", true);
    glb(&doc, &bin)
}

#[test]
fn texture_transform_moves_and_turns_the_mask() {
    let t = Tmp::new("gltf-transform");
    // Opaque where frac(u') < 1/2. Offset by a half: u' = u + 1/2, the right half is opaque.
    let s = load(&t, &transformed(json!({"offset": [0.5, 0.0]}))).unwrap();
    assert!(!square_at(&s, 0.2, 0.5) && square_at(&s, 0.8, 0.5));
    // Turned by π/2: u' = v = 1 − y, so the half above y = 1/2 is opaque (the opposite turn would
    // keep the lower half).
    let s = load(&t, &transformed(json!({"rotation": std::f64::consts::FRAC_PI_2}))).unwrap();
    assert!(square_at(&s, 0.5, 0.8) && !square_at(&s, 0.5, 0.2));
    assert!(square_at(&s, 0.1, 0.8) && square_at(&s, 0.9, 0.8) && !square_at(&s, 0.9, 0.2));
    // Scaled by two: u' = 2u, opaque on [0, 1/4) and [1/2, 3/4).
    let s = load(&t, &transformed(json!({"scale": [2.0, 1.0]}))).unwrap();
    let cols: Vec<bool> = [0.1, 0.35, 0.6, 0.85].iter().map(|&x| square_at(&s, x, 0.5)).collect();
    assert_eq!(cols, [true, false, true, false]);
    // The extension's own example: offset [0, 1], rotation π/2, scale 1/2 reads the lower left
    // quadrant, turned: u' = v / 2 < 1/2 everywhere, so the whole square is opaque.
    let example = json!({"offset": [0.0, 1.0], "rotation": std::f64::consts::FRAC_PI_2, "scale": [0.5, 0.5]});
    let s = load(&t, &transformed(example)).unwrap();
    assert!([0.1, 0.9].iter().all(|&x| [0.1, 0.9].iter().all(|&y| square_at(&s, x, y))));
    assert_eq!(
        hemilab::scene::gltf_mesh::affine([0.0, 1.0], std::f32::consts::FRAC_PI_2, [0.5, 0.5])[1][2],
        1.0
    );
}

#[test]
fn a_mask_whose_only_texture_is_dds_is_decoded() {
    let t = Tmp::new("gltf-dds");
    let s = load(&t, &extension_source("MSFT_texture_dds", dds(false))).unwrap();
    assert!(dropped_warning(&s).is_none());
    assert!(square_at(&s, 0.2, 0.5) && square_at(&s, 0.45, 0.2) && !square_at(&s, 0.55, 0.5));
    let e = load(&t, &extension_source("MSFT_texture_dds", dds(true))).err().expect("BC4 refused");
    assert!(e.contains("image 1: the base colour texture: DDS with DXGI format BC4_UNorm"), "{e}");
    assert_eq!(e.lines().count(), 1);
}

#[test]
fn unknown_required_extensions_off_geometry_and_masks_are_one_warning() {
    // As Sponza ships: every material carries AMD_split_roughnessMetallic, whose roughness texture
    // has only a DDS source, a file that is not there (it is never read: no mask needs it).
    let t = Tmp::new("gltf-unknown");
    let (mut doc, bin) = masked_square().encode(None);
    doc["images"].as_array_mut().unwrap().push(json!({"uri": "rough.dds", "mimeType": "image/vnd-ms.dds"}));
    doc["textures"].as_array_mut().unwrap().push(json!({"extensions": {"MSFT_texture_dds": {"source": 1}}}));
    doc["materials"][0]["extensions"] =
        json!({"AMD_split_roughnessMetallic": {"roughnessTexture": {"index": 1}}});
    declare(&mut doc, "MSFT_texture_dds", false);
    declare(&mut doc, "AMD_split_roughnessMetallic", true);
    let s = load(&t, &glb(&doc, &bin)).unwrap();
    let w = dropped_warning(&s).expect("a warning");
    assert_eq!(w.lines().count(), 1, "{w}");
    assert!(
        w.starts_with("warning: scene 's': m.glb: requires extension 'AMD_split_roughnessMetallic'"),
        "{w}"
    );
    assert!(w.contains("ignored") && w.contains("materials[0]"), "{w}");
    assert!(square_at(&s, 0.2, 0.5) && !square_at(&s, 0.8, 0.5), "the mask is still read");
}

#[test]
fn extension_cases_that_cannot_be_honoured_are_one_error_naming_the_file() {
    let t = Tmp::new("gltf-ext-bad");
    for (name, bytes, want) in bad_extension_files() {
        let e = load(&t, &bytes).err().unwrap_or_else(|| panic!("{name}: loaded"));
        assert!(e.starts_with(&format!("{}: ", t.path("m.glb").display())), "{name}: {e}");
        assert_eq!(e.lines().count(), 1, "{name}: {e}");
        assert!(e.contains(want), "{name}: want '{want}' in: {e}");
    }
}

#[test]
fn sponza_loads_as_shipped_with_its_three_masks() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let s = load_scene(&root.join("sponza.toml")).unwrap();
    assert_eq!((s.triangle_count, s.dropped_triangles), (262_087, 0));
    let w = dropped_warning(&s).expect("the AMD extension's warning");
    assert_eq!(w.lines().count(), 1, "{w}");
    assert!(w.contains("sponza/Sponza.gltf: requires extension 'AMD_split_roughnessMetallic'"), "{w}");
    assert!(s.accel.has_alpha());
    // The same file with its three MASK materials made opaque renders another image: the masks cut.
    let text = std::fs::read_to_string(root.join("sponza/Sponza.gltf")).unwrap();
    let mut doc: Value = serde_json::from_str(&text).unwrap();
    let masked: Vec<usize> = doc["materials"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .filter(|(_, m)| m["alphaMode"] == "MASK")
        .map(|(i, _)| i)
        .collect();
    assert_eq!(masked, [1, 18, 23], "PotPlant1, Chain, Plants");
    for &i in &masked {
        doc["materials"][i]["alphaMode"] = json!("OPAQUE");
    }
    let t = Tmp::new("sponza-opaque");
    std::fs::create_dir_all(t.path("sponza")).unwrap();
    std::fs::copy(root.join("sponza/Sponza.bin"), t.path("sponza/Sponza.bin")).unwrap();
    std::fs::write(t.path("sponza/Sponza.gltf"), serde_json::to_vec(&doc).unwrap()).unwrap();
    std::fs::copy(root.join("sponza.toml"), t.path("sponza.toml")).unwrap();
    let opaque = load_scene(&t.path("sponza.toml")).unwrap();
    assert!(!opaque.accel.has_alpha());
    let (a, b) = (image_bits(&s), image_bits(&opaque));
    let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert!(differ > 0, "masks change nothing");
}

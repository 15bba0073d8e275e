//! glTF test files with the extensions production pipelines use, shared by the stage tests
//! (`scene_gltf_ext`) and the command-line ones (`render_gltf`): a masked square over a floor, its
//! variants whose mask texture has only an extension source, and the bad files of each extension
//! case with the phrase its one error must contain.

use hemilab::scene::gltf_write::{Doc, Material, Node, Prim, declare, glb, meshopt_compress, soup};
use serde_json::{Value, json};

/// A 2×2 RGBA PNG: left column opaque, right column transparent.
pub fn half_mask_png() -> Vec<u8> {
    let img =
        image::RgbaImage::from_fn(2, 2, |x, _| image::Rgba([200, 200, 200, if x == 0 { 255 } else { 0 }]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// The unit square, masked by the half mask (u = x, v = 1 − y), over a 2 × 2 floor at z = −1 drawn
/// as a TRIANGLE_STRIP (so EXT_meshopt_compression codes its indices as a sequence). Every
/// coordinate is −1, 0 or 1, so integer and normalized quantizations hold them exactly.
pub fn masked_square() -> Doc {
    let mut prims =
        soup(&[[[0.0; 3], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]], [[0.0; 3], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]]);
    prims[0].uvs = Some(vec![[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0], [0.0, 0.0]]);
    prims[0].material = Some(0);
    let floor = Prim {
        positions: vec![[-1.0, -1.0, -1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [1.0, 1.0, -1.0]],
        indices: Some(vec![0, 1, 2, 3]),
        mode: 5,
        ..Prim::default()
    };
    Doc {
        meshes: vec![prims, vec![floor]],
        nodes: vec![Node { mesh: Some(0), ..Node::default() }, Node { mesh: Some(1), ..Node::default() }],
        roots: vec![0, 1],
        materials: vec![Material { base_color_factor: [1.0; 4], texture: Some(0), alpha_cutoff: Some(0.5) }],
        images: vec![half_mask_png()],
        ..Doc::default()
    }
}

/// A 2×2 uncompressed RGBA DDS with the half mask's alpha, or a BC4 one (no alpha to read).
pub fn dds(bc4: bool) -> Vec<u8> {
    use ddsfile::{AlphaMode, D3D10ResourceDimension, Dds, DxgiFormat, NewDxgiParams};
    let (w, format) = if bc4 { (4, DxgiFormat::BC4_UNorm) } else { (2, DxgiFormat::R8G8B8A8_UNorm) };
    let mut d = Dds::new_dxgi(NewDxgiParams {
        height: w,
        width: w,
        depth: None,
        format,
        mipmap_levels: None,
        array_layers: None,
        caps2: None,
        is_cubemap: false,
        resource_dimension: D3D10ResourceDimension::Texture2D,
        alpha_mode: AlphaMode::Straight,
    })
    .unwrap();
    let px: &[u8] = if bc4 { &[0; 8] } else { &[9, 9, 9, 255, 9, 9, 9, 0, 9, 9, 9, 255, 9, 9, 9, 0] };
    d.get_mut_data(0).unwrap().copy_from_slice(px);
    let mut out = Vec::new();
    d.write(&mut out).unwrap();
    out
}

/// `masked_square` whose texture's only source is `ext` → image 1 (holding `image`), as AMD's
/// Capsaicin files give their roughness maps.
pub fn extension_source(ext: &str, image: Vec<u8>) -> Vec<u8> {
    let mut doc = masked_square();
    doc.images.push(image);
    let (mut json, bin) = doc.encode(None);
    json["textures"][0] = json!({"extensions": {ext: {"source": 1}}});
    declare(&mut json, ext, true);
    glb(&json, &bin)
}

/// The bad files of the extension cases, and a phrase each one's error must contain.
pub fn bad_extension_files() -> Vec<(&'static str, Vec<u8>, &'static str)> {
    let with = |edit: &dyn Fn(&mut Value)| {
        let (mut doc, bin) = masked_square().encode(None);
        edit(&mut doc);
        glb(&doc, &bin)
    };
    let corrupt = {
        let (mut doc, bin) = masked_square().encode(None);
        let mut packed = meshopt_compress(&mut doc, &bin, false);
        packed.iter_mut().for_each(|b| *b = 0xff);
        glb(&doc, &packed)
    };
    vec![
        (
            "draco",
            with(&|d| declare(d, "KHR_draco_mesh_compression", true)),
            "'KHR_draco_mesh_compression' (Draco-compressed geometry) is not supported",
        ),
        (
            "geometry",
            with(&|d| {
                d["nodes"][0]["extensions"] = json!({"EXT_mesh_gpu_instancing": {"attributes": {}}});
                declare(d, "EXT_mesh_gpu_instancing", true);
            }),
            "'EXT_mesh_gpu_instancing' is not supported, and it changes geometry (used at nodes[0])",
        ),
        (
            "mask",
            with(&|d| {
                d["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] =
                    json!({"X_uv": {}});
                declare(d, "X_uv", true);
            }),
            "'X_uv' is not supported, and it changes an alpha mask",
        ),
        (
            "basisu",
            extension_source("KHR_texture_basisu", b"KTX2 not decoded".to_vec()),
            "texture 0 (the base colour texture of alpha-masked material 0): no image hemilab decodes: no core \
             `source`, only extension sources (KHR_texture_basisu)",
        ),
        ("bad-dds", extension_source("MSFT_texture_dds", b"DDS  broken".to_vec()), "does not read as DDS"),
        ("meshopt", corrupt, "EXT_meshopt_compression: the ATTRIBUTES stream does not decode"),
    ]
}

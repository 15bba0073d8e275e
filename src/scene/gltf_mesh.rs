//! glTF 2.0 (Khronos, "glTF 2.0 Specification", 2021) to the same triangle soup an OBJ gives: the
//! default scene's node tree walked with each node's transform composed in f64, every triangle
//! primitive of every mesh a node instances (indexed or not; `TRIANGLES`, `TRIANGLE_STRIP` and
//! `TRIANGLE_FAN` unrolled as the specification's section 3.7.2.1 orders their vertices), and the
//! file's first camera where a node places it. Points and lines have no surface to occlude with, and
//! are refused rather than dropped: a glTF file says exactly what it draws, so an unsupported mode is
//! a file this renderer cannot show faithfully. Materials with `alphaMode: MASK` become cutouts
//! (`alpha`): their texture decoded once, each triangle given its texture coordinates; a file
//! without such materials carries no mask data at all.
//!
//! No IO here: `fetch` hands over the bytes of a buffer's URI (relative to the .gltf file, or a
//! `data:` URI decoded here), so every fault is a message the caller prefixes with the file name.

use super::MAX_COORDINATE;
use super::alpha::{Cutout, SOLID, Source, Wrap};
use super::camera::{Camera, WorldCamera};
use super::mesh::{Mesh, usable};
use ::gltf::mesh::Mode;
use glam::{DMat4, DVec3};
use rayon::prelude::*;

/// A glTF file's geometry, its first camera (if a node of the scene places it), and the bytes of
/// every external buffer it read (for the scene's content hash).
pub struct Parsed {
    pub mesh: Mesh,
    pub camera: Option<WorldCamera>,
    pub external: Vec<Vec<u8>>,
}

/// Reads a `.gltf` (JSON) or `.glb` (binary) file. `fetch(uri)` returns the bytes of a buffer's
/// external file, or why not (e.g. "not found, looked for /abs/path").
///
/// The file is checked before the `gltf` crate reads it (`gltf_check`), and a panic the checks
/// missed is one error, not an abort (`guard`).
pub fn parse_gltf(
    bytes: &[u8],
    fetch: &mut dyn FnMut(&str) -> Result<Vec<u8>, String>,
) -> Result<Parsed, String> {
    super::guard::contained("glTF", || parse_checked(bytes, fetch))
}

fn parse_checked(
    bytes: &[u8],
    fetch: &mut dyn FnMut(&str) -> Result<Vec<u8>, String>,
) -> Result<Parsed, String> {
    let super::gltf_ext::Prepared { document, blob, json, notes } = super::gltf_ext::prepare(bytes)?;
    let mut buffers = Vec::new();
    let mut external = Vec::new();
    for b in document.buffers() {
        let data = match b.source() {
            // An EXT_meshopt_compression fallback buffer has no bytes: its views are decoded into it.
            // Its length is at most `gltf_check::MAX_DECLARED_BUFFER`; the allocator may still say no.
            _ if super::gltf_meshopt::is_fallback(&json, b.index()) => {
                let mut zeros = Vec::new();
                zeros.try_reserve_exact(b.length()).map_err(|_| {
                    format!(
                        "buffer {}: cannot allocate its {} bytes (fallback buffer)",
                        b.index(),
                        b.length()
                    )
                })?;
                zeros.resize(b.length(), 0);
                zeros
            }
            ::gltf::buffer::Source::Bin => blob.clone().ok_or_else(|| {
                format!("buffer {}: refers to the GLB binary chunk, which the file lacks", b.index())
            })?,
            ::gltf::buffer::Source::Uri(uri) => {
                let data = match uri.strip_prefix("data:") {
                    Some(rest) => {
                        data_uri(rest).map_err(|e| format!("buffer {}: data URI: {e}", b.index()))?
                    }
                    None => fetch(uri).map_err(|e| format!("buffer {} ('{uri}'): {e}", b.index()))?,
                };
                external.push(data.clone());
                data
            }
        };
        if data.len() < b.length() {
            return Err(format!(
                "buffer {}: holds {} bytes, the file declares {} (truncated?)",
                b.index(),
                data.len(),
                b.length()
            ));
        }
        buffers.push(data);
    }
    super::gltf_meshopt::decode_views(&json, &mut buffers)?;
    let mut mesh = Mesh { notes, ..Mesh::default() };
    let mut camera = None;
    let roots: Vec<::gltf::Node> = match document.default_scene().or_else(|| document.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => return Err("no scene: the file lists no `scenes`, so it draws nothing".into()),
    };
    // Depth-first in file order, so the triangles (and which node's camera is "first") are the same
    // on every load.
    let mut stack: Vec<(::gltf::Node, DMat4)> =
        roots.into_iter().rev().map(|n| (n, DMat4::IDENTITY)).collect();
    let mut visited = 0usize;
    // Alpha masks only where a material asks for one: then every triangle records its cutout
    // (`alpha::SOLID` for the others), each masked material's cutout made on first use.
    let masks = document.materials().any(|m| m.alpha_mode() == ::gltf::material::AlphaMode::Mask);
    if masks {
        mesh.alpha = Some(Source::default());
    }
    let mut cutout_of: Vec<Option<Mask>> = vec![None; document.materials().len()];
    while let Some((node, parent)) = stack.pop() {
        visited += 1;
        if visited > 1 << 24 {
            return Err("node tree: more than 2^24 node visits (a cycle among `children`?)".into());
        }
        let local = node.transform().matrix().map(|c| c.map(f64::from));
        let world = parent * DMat4::from_cols_array_2d(&local);
        if let Some(m) = node.mesh() {
            for p in m.primitives() {
                let what = || format!("mesh {} primitive {}", m.index(), p.index());
                let material = p.material();
                let mask = match (masks, material.index()) {
                    (true, Some(i)) if material.alpha_mode() == ::gltf::material::AlphaMode::Mask => {
                        if cutout_of[i].is_none() {
                            let (c, set, uv) =
                                cutout(&material, &document, &json, &buffers, fetch, &mut external)
                                    .map_err(|e| format!("{}: {e}", what()))?;
                            let source = mesh.alpha.as_mut().expect("masks");
                            source.cutouts.push(c);
                            cutout_of[i] = Some(Mask { cutout: source.cutouts.len() as u32 - 1, set, uv });
                        }
                        cutout_of[i]
                    }
                    (true, _) => Some(Mask { cutout: SOLID, set: None, uv: None }),
                    (false, _) => None,
                };
                primitive(&p, &buffers, world, &mut mesh, mask).map_err(|e| format!("{}: {e}", what()))?;
            }
        }
        if camera.is_none() {
            camera = node.camera().filter(|c| c.index() == 0).map(|c| place_camera(&c, world));
        }
        for child in node.children().collect::<Vec<_>>().into_iter().rev() {
            stack.push((child, world));
        }
    }
    if mesh.indices.is_empty() {
        return Err(if mesh.dropped > 0 {
            format!("empty mesh: all {} triangles have zero area or non-finite vertices", mesh.dropped)
        } else {
            "empty mesh: no node of the scene draws a triangle (AO needs at least one)".into()
        });
    }
    Ok(Parsed { mesh, camera, external })
}

/// An affine map of texture coordinates, as rows of (u, v, 1): `KHR_texture_transform` (`affine`).
type UvMap = [[f64; 3]; 2];

/// Which cutout a masked primitive's triangles use (`SOLID` for the unmasked ones of a scene with
/// masks), read at which TEXCOORD set, through which `KHR_texture_transform` (`affine`).
#[derive(Clone, Copy)]
struct Mask {
    cutout: u32,
    set: Option<u32>,
    uv: Option<UvMap>,
}

/// A masked material's cutout: its base colour texture's alpha (decoded here; nearest texel, wrapped
/// as its sampler says) times its `baseColorFactor` alpha against its `alphaCutoff` (default 0.5);
/// with the TEXCOORD set it reads and its texture transform. The image is the texture's core
/// `source`, else its `MSFT_texture_dds` one; a DDS image (known by its magic number) is decoded by
/// `dds`, anything else as PNG.
fn cutout(
    material: &::gltf::Material,
    document: &::gltf::Document,
    json: &serde_json::Value,
    buffers: &[Vec<u8>],
    fetch: &mut dyn FnMut(&str) -> Result<Vec<u8>, String>,
    external: &mut Vec<Vec<u8>>,
) -> Result<(Cutout, Option<u32>, Option<UvMap>), String> {
    let pbr = material.pbr_metallic_roughness();
    let (factor, cutoff) = (pbr.base_color_factor()[3], material.alpha_cutoff().unwrap_or(0.5));
    let Some(info) = pbr.base_color_texture() else {
        return Ok((Cutout::uniform(factor, cutoff), None, None));
    };
    let texture = info.texture();
    let image = match texture.source() {
        Some(image) => image,
        None => {
            let t = texture.index();
            let ext = &json["textures"][t]["extensions"];
            let dds = ext["MSFT_texture_dds"]["source"].as_u64();
            match dds.and_then(|i| document.images().nth(i as usize)) {
                Some(image) => image,
                None => {
                    let names: Vec<String> =
                        ext.as_object().map_or(Vec::new(), |m| m.keys().cloned().collect());
                    let only = if names.is_empty() {
                        String::new()
                    } else {
                        format!(", only extension sources ({})", names.join(", "))
                    };
                    return Err(format!(
                        "texture {t} (the base colour texture of alpha-masked material {}): no image hemilab \
                         decodes: no core `source`{only}; a mask reads PNG, or DDS through MSFT_texture_dds",
                        material.index().map_or("?".into(), |i| i.to_string())
                    ));
                }
            }
        }
    };
    let bytes =
        image_bytes(&image, buffers, fetch, external).map_err(|e| format!("image {}: {e}", image.index()))?;
    let (w, h, alpha) = if bytes.starts_with(b"DDS ") {
        super::dds::alpha(&bytes)
            .map_err(|e| format!("image {}: the base colour texture: {e}", image.index()))?
    } else {
        super::alpha::decode(&bytes, Some(super::alpha::Channel::Alpha), "")
            .map_err(|e| format!("image {}: the base colour texture {e}", image.index()))?
    };
    let sampler = info.texture().sampler();
    let wrap = |w: ::gltf::texture::WrappingMode| match w {
        ::gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
        ::gltf::texture::WrappingMode::MirroredRepeat => Wrap::Mirror,
        ::gltf::texture::WrappingMode::ClampToEdge => Wrap::Clamp,
    };
    let transform = info.texture_transform();
    let set = transform.as_ref().and_then(|t| t.tex_coord()).unwrap_or(info.tex_coord());
    let uv = transform.map(|t| affine(t.offset(), t.rotation(), t.scale()));
    let cut = Cutout::new(w, h, &alpha, factor, cutoff, [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())]);
    Ok((cut, Some(set), uv))
}

/// `KHR_texture_transform` as the rows of an affine map of (u, v, 1): translation × rotation × scale.
/// The rotation's sign is the one the extension's own example fixes ("offset [0, 1], rotation π/2,
/// scale 0.5 utilizes the lower left quadrant, rotated clockwise 90°") and three.js implements:
/// u' = cos·u + sin·v, v' = −sin·u + cos·v, with v running down the image. Applied to each vertex's
/// coordinates at load: an affine map commutes with the barycentric interpolation at a hit.
pub fn affine(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> UvMap {
    let (s, c) = (rotation as f64).sin_cos();
    let (sx, sy) = (scale[0] as f64, scale[1] as f64);
    [[c * sx, s * sy, offset[0] as f64], [-s * sx, c * sy, offset[1] as f64]]
}

/// Appends one primitive's triangles, in world coordinates; with `mask` (the scene has alpha
/// masks), each kept triangle's cutout and, from TEXCOORD_`set`, its corners' coordinates.
fn primitive(
    p: &::gltf::Primitive,
    buffers: &[Vec<u8>],
    world: DMat4,
    mesh: &mut Mesh,
    mask: Option<Mask>,
) -> Result<(), String> {
    let mode = p.mode();
    if !matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
        return Err(format!(
            "primitive mode {mode:?} is not supported (AO renders surfaces: use TRIANGLES, TRIANGLE_STRIP or \
             TRIANGLE_FAN)"
        ));
    }
    let reader = p.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
    let position = p.get(&::gltf::Semantic::Positions).ok_or("POSITION: missing")?;
    let positions: Vec<DVec3> = super::gltf_accessor::read::<3>(&position, buffers)
        .map_err(|e| format!("POSITION: {e}"))?
        .into_iter()
        .map(|v| world.transform_point3(DVec3::from_array(v)))
        .collect();
    if let Some(c) = positions.iter().flat_map(|v| v.to_array()).find(|c| c.abs() > MAX_COORDINATE) {
        return Err(format!(
            "a vertex coordinate ({c:e} after the node transforms) is beyond ±{MAX_COORDINATE:e}"
        ));
    }
    let indices: Vec<u32> = match p.indices() {
        None => (0..positions.len() as u32).collect(),
        Some(_) => {
            reader.read_indices().ok_or("indices: their data lies outside its buffer")?.into_u32().collect()
        }
    };
    if let Some(&i) = indices.iter().find(|&&i| i as usize >= positions.len()) {
        return Err(format!("index {i} out of range (the primitive has {} vertices)", positions.len()));
    }
    let n = indices.len();
    let corners: Vec<[u32; 3]> = match mode {
        Mode::Triangles => {
            if !n.is_multiple_of(3) {
                return Err(format!("TRIANGLES with {n} vertices (not a multiple of 3)"));
            }
            indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
        }
        // Section 3.7.2.1: p_i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}}, which keeps the winding.
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .map(|i| [indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]])
            .collect(),
        // Section 3.7.2.1: p_i = {v_{i+1}, v_{i+2}, v_0}.
        _ => (0..n.saturating_sub(2)).map(|i| [indices[i + 1], indices[i + 2], indices[0]]).collect(),
    };
    let uvs: Option<Vec<[f32; 2]>> = match mask {
        Some(Mask { cutout, set: Some(set), uv }) if cutout != SOLID => {
            let accessor = p.get(&::gltf::Semantic::TexCoords(set)).ok_or_else(|| {
                format!("TEXCOORD_{set}: missing (the material's alpha mask needs texture coordinates)")
            })?;
            let uvs = super::gltf_accessor::read::<2>(&accessor, buffers)
                .map_err(|e| format!("TEXCOORD_{set}: {e}"))?;
            if uvs.len() < positions.len() {
                return Err(format!(
                    "TEXCOORD_{set}: {} entries for {} vertices",
                    uvs.len(),
                    positions.len()
                ));
            }
            let m = uv.unwrap_or([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
            let apply = |r: [f64; 3], t: [f64; 2]| (r[0] * t[0] + r[1] * t[1] + r[2]) as f32;
            Some(uvs.into_iter().map(|t| [apply(m[0], t), apply(m[1], t)]).collect())
        }
        _ => None,
    };
    // Each instance's positions once (in world coordinates), its triangles indexing them.
    let base = mesh.positions.len() as u32;
    // The test in parallel: it reads the positions through the indices, slow for a large mesh
    // whose triangles are not in the order of their vertices.
    let ok: Vec<bool> = corners.par_iter().map(|c| usable(&c.map(|i| positions[i as usize]))).collect();
    for (c, ok) in corners.into_iter().zip(ok) {
        if ok {
            mesh.indices.push(c.map(|i| base + i));
            if let (Some(Mask { cutout: cut, .. }), Some(source)) = (mask, mesh.alpha.as_mut()) {
                let uv = uvs.as_ref().map_or([[0.0; 2]; 3], |u| c.map(|i| u[i as usize]));
                source.push(cut, uv);
            }
        } else {
            mesh.dropped += 1;
        }
    }
    mesh.positions.extend(positions);
    Ok(())
}

/// The encoded bytes of an image: from a buffer view, a `data:` URI, or a file beside the glTF.
fn image_bytes(
    image: &::gltf::Image,
    buffers: &[Vec<u8>],
    fetch: &mut dyn FnMut(&str) -> Result<Vec<u8>, String>,
    external: &mut Vec<Vec<u8>>,
) -> Result<Vec<u8>, String> {
    match image.source() {
        ::gltf::image::Source::View { view, .. } => {
            let (start, len) = (view.offset(), view.length());
            buffers[view.buffer().index()]
                .get(start..start.saturating_add(len))
                .map(<[u8]>::to_vec)
                .ok_or_else(|| format!("buffer view {} lies outside its buffer", view.index()))
        }
        ::gltf::image::Source::Uri { uri, .. } => {
            let bytes = match uri.strip_prefix("data:") {
                Some(rest) => data_uri(rest).map_err(|e| format!("data URI: {e}"))?,
                None => fetch(uri).map_err(|e| format!("'{uri}': {e}"))?,
            };
            external.push(bytes.clone());
            Ok(bytes)
        }
    }
}

/// A glTF camera looks down its node's −Z with +Y up (section 3.10.1). The image's aspect comes from
/// the scene's resolution, as for a TOML camera; an orthographic camera's width is twice its `xmag`.
fn place_camera(c: &::gltf::Camera, world: DMat4) -> WorldCamera {
    let eye = world.transform_point3(DVec3::ZERO);
    let target = eye + world.transform_vector3(DVec3::NEG_Z);
    let up = world.transform_vector3(DVec3::Y);
    match c.projection() {
        ::gltf::camera::Projection::Perspective(p) => {
            Camera::Perspective { eye, target, up, fov_y_deg: p.yfov().to_degrees() }
        }
        ::gltf::camera::Projection::Orthographic(o) => {
            let scale = world.transform_vector3(DVec3::X).length();
            Camera::Orthographic { eye, target, up, view_width: (2.0 * o.xmag() as f64 * scale) as f32 }
        }
    }
}

/// `data:[<mediatype>][;base64],<data>` (RFC 2397), the part after `data:`.
fn data_uri(rest: &str) -> Result<Vec<u8>, String> {
    let (head, data) = rest.split_once(',').ok_or("no ',' before the data")?;
    if !head.ends_with(";base64") {
        return Err("only base64 data URIs are supported".into());
    }
    base64(data)
}

/// Standard base64 (RFC 4648, section 4), padding optional.
fn base64(s: &str) -> Result<Vec<u8>, String> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => Some(c - b'A'),
        b'a'..=b'z' => Some(c - b'a' + 26),
        b'0'..=b'9' => Some(c - b'0' + 52),
        b'+' => Some(62),
        b'/' => Some(63),
        _ => None,
    };
    let (mut out, mut acc, mut bits) = (Vec::with_capacity(s.len() * 3 / 4), 0u32, 0);
    for &c in s.trim_end_matches('=').as_bytes() {
        let v = value(c).ok_or_else(|| format!("'{}' is not a base64 character", c as char))?;
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    Ok(out)
}

/// A relative URI as a file path: percent-escapes decoded (RFC 3986, section 2.1).
pub fn uri_path(uri: &str) -> String {
    let b = uri.as_bytes();
    let (mut out, mut i) = (Vec::with_capacity(b.len()), 0);
    while i < b.len() {
        let hex = |j: usize| b.get(j).and_then(|&c| (c as char).to_digit(16));
        match (b[i], hex(i + 1), hex(i + 2)) {
            (b'%', Some(h), Some(l)) => {
                out.push((h * 16 + l) as u8);
                i += 3;
            }
            (c, _, _) => {
                out.push(c);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_and_uris_decode() {
        assert_eq!(base64("aGVsbG8=").unwrap(), b"hello");
        assert_eq!(base64("aGVsbG8").unwrap(), b"hello");
        assert!(base64("a*").is_err());
        assert_eq!(uri_path("my%20mesh.bin"), "my mesh.bin");
        assert_eq!(uri_path("100%"), "100%");
    }
}

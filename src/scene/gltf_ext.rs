//! glTF files as production pipelines ship them: which extensions a file may *require*
//! (`extensionsRequired`, glTF 2.0 section 3.12: "a client that does not support all of them must
//! not load the asset") and what this reader does with each. AO reads geometry and alpha masks
//! only, so a required extension that touches neither (a shading model, a split roughness texture,
//! a light) changes nothing here: it is one warning, not a refusal. One that touches geometry or a
//! mask and is not implemented is an error, because the image would silently be wrong.
//!
//! Implemented: `KHR_mesh_quantization` (integer positions and texture coordinates,
//! `gltf_accessor`), `EXT_meshopt_compression` (compressed buffer views, `gltf_meshopt`),
//! `KHR_texture_transform` (on mask textures, `gltf_mesh`) and `MSFT_texture_dds` (DDS images,
//! read only when a mask needs one, `dds`). Refused: `KHR_draco_mesh_compression`, whose decoder is
//! a large C++ library with no pure-Rust equivalent.
//!
//! Where an unknown extension is used is read from the JSON: the `extensions` objects that name it.
//! Geometry is everything under `meshes`, `accessors`, `bufferViews`, `buffers`, `nodes` and
//! `scenes`; a mask is a `MASK` material's base colour `textureInfo` and its texture's sampler.
//! A texture's own extensions are alternative image sources: a mask reads the core `source` (or
//! the DDS one), and says so in one error if it has neither.

use serde_json::Value;

/// Required extensions this reader implements.
const IMPLEMENTED: &[&str] =
    &["KHR_mesh_quantization", "EXT_meshopt_compression", "KHR_texture_transform", "MSFT_texture_dds"];

/// A parsed, validated glTF document with its raw JSON (for extension data the `gltf` crate does not
/// model) and the warnings its extensions gave.
pub struct Prepared {
    pub document: ::gltf::Document,
    pub blob: Option<Vec<u8>>,
    pub json: Value,
    pub notes: Vec<String>,
}

/// Parses a `.gltf` or `.glb`: the extension policy above applied to `extensionsRequired` before the
/// `gltf` crate validates the document (it refuses every required extension it does not know).
pub fn prepare(bytes: &[u8]) -> Result<Prepared, String> {
    let unreadable = |e: &dyn std::fmt::Display| format!("not a readable glTF 2.0 file: {e}");
    let (text, blob) = if bytes.starts_with(b"glTF") {
        super::gltf_check::glb_header(bytes)?;
        let glb = ::gltf::Glb::from_slice(bytes).map_err(|e| unreadable(&e))?;
        (glb.json.into_owned(), glb.bin.map(|b| b.into_owned()))
    } else {
        (bytes.to_vec(), None)
    };
    let json: Value = serde_json::from_slice(&text).map_err(|e| unreadable(&e))?;
    // What the crate's validation and readers assume, checked first (`gltf_check`).
    super::gltf_check::document(&json)?;
    let mut root: ::gltf::json::Root =
        ::gltf::json::deserialize::from_slice(&text).map_err(|e| unreadable(&e))?;
    let notes = required(&root.extensions_required, &json)?;
    // Every required extension is now implemented here or known to be harmless: the crate's own
    // check (an allow-list of the extensions it models) has nothing left to decide.
    root.extensions_required.clear();
    let document = ::gltf::Document::from_json(root).map_err(|e| unreadable(&e))?;
    Ok(Prepared { document, blob, json, notes })
}

/// The warnings for the required extensions, or the error for the first one that cannot be ignored.
fn required(required: &[String], json: &Value) -> Result<Vec<String>, String> {
    let mut notes = Vec::new();
    for ext in required {
        if IMPLEMENTED.contains(&ext.as_str()) {
            continue;
        }
        if ext == "KHR_draco_mesh_compression" {
            return Err(format!(
                "extensionsRequired: '{ext}' (Draco-compressed geometry) is not supported: hemilab has no Draco \
                 decoder; write the file without Draco (e.g. `gltf-transform copy in.glb out.glb`), or with \
                 EXT_meshopt_compression or KHR_mesh_quantization, which it reads"
            ));
        }
        let mut places = Vec::new();
        uses(json, ext, &mut String::new(), &mut places);
        let masks = mask_places(json);
        if let Some(p) = places.iter().find(|p| geometry(p)) {
            return Err(format!(
                "extensionsRequired: '{ext}' is not supported, and it changes geometry (used at {p}); AO \
                 cannot be rendered faithfully without it"
            ));
        }
        if let Some(p) = places.iter().find(|p| masks.iter().any(|m| p.starts_with(m.as_str()))) {
            return Err(format!(
                "extensionsRequired: '{ext}' is not supported, and it changes an alpha mask (used at {p})"
            ));
        }
        let shown: Vec<&str> = places.iter().take(3).map(String::as_str).collect();
        let more = if places.len() > 3 { format!(" and {} more", places.len() - 3) } else { String::new() };
        let at = if places.is_empty() { "nowhere in the file".to_string() } else { shown.join(", ") + &more };
        notes.push(format!(
            "requires extension '{ext}', which hemilab does not implement; ignored, as it touches neither \
             geometry nor alpha masks (used at {at})"
        ));
    }
    Ok(notes)
}

/// Whether a JSON path lies in what a glTF file draws.
fn geometry(path: &str) -> bool {
    ["meshes[", "accessors[", "bufferViews[", "buffers[", "nodes[", "scenes["]
        .iter()
        .any(|g| path.starts_with(g))
}

/// The JSON paths (`materials[3].pbrMetallicRoughness.baseColorTexture`, …) of every object whose
/// `extensions` names `ext` (arrays in order, keys sorted: the same list on every load).
fn uses(v: &Value, ext: &str, path: &mut String, out: &mut Vec<String>) {
    match v {
        Value::Object(map) => {
            if map.get("extensions").and_then(|e| e.get(ext)).is_some() {
                out.push(if path.is_empty() { "the top level".into() } else { path.clone() });
            }
            for (k, child) in map {
                let len = path.len();
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(k);
                uses(child, ext, path, out);
                path.truncate(len);
            }
        }
        Value::Array(items) => {
            for (i, child) in items.iter().enumerate() {
                let len = path.len();
                path.push_str(&format!("[{i}]"));
                uses(child, ext, path, out);
                path.truncate(len);
            }
        }
        _ => {}
    }
}

/// The paths an alpha mask reads: each `MASK` material's base colour texture info and the sampler
/// of its texture.
fn mask_places(json: &Value) -> Vec<String> {
    let mut out = Vec::new();
    let materials = json.get("materials").and_then(Value::as_array).map_or(&[][..], |m| &m[..]);
    for (i, m) in materials.iter().enumerate() {
        if m.get("alphaMode").and_then(Value::as_str) != Some("MASK") {
            continue;
        }
        let info = &m["pbrMetallicRoughness"]["baseColorTexture"];
        if info.is_null() {
            continue;
        }
        out.push(format!("materials[{i}].pbrMetallicRoughness.baseColorTexture"));
        let texture = info.get("index").and_then(Value::as_u64).map(|t| &json["textures"][t as usize]);
        if let Some(s) = texture.and_then(|t| t.get("sampler")).and_then(Value::as_u64) {
            out.push(format!("samplers[{s}]"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn an_extension_is_placed_by_the_objects_that_name_it() {
        let doc = json!({
            "materials": [
                {"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0,
                    "extensions": {"X_uv": {}}}}, "extensions": {"X_shade": {}}},
                {"extensions": {"X_shade": {}}}
            ],
            "textures": [{"source": 0, "sampler": 1}],
            "meshes": [{"primitives": [{"extensions": {"X_geo": {}}}]}],
        });
        let mut p = Vec::new();
        uses(&doc, "X_shade", &mut String::new(), &mut p);
        assert_eq!(p, ["materials[0]", "materials[1]"]);
        let notes = required(&["X_shade".into()], &doc).unwrap();
        assert_eq!(notes.len(), 1);
        assert!(
            notes[0].contains("'X_shade'") && notes[0].contains("materials[0], materials[1]"),
            "{notes:?}"
        );
        let e = required(&["X_geo".into()], &doc).unwrap_err();
        assert!(e.contains("changes geometry (used at meshes[0].primitives[0])"), "{e}");
        let e = required(&["X_uv".into()], &doc).unwrap_err();
        assert!(e.contains("changes an alpha mask"), "{e}");
        assert_eq!(mask_places(&doc), ["materials[0].pbrMetallicRoughness.baseColorTexture", "samplers[1]"]);
        assert!(required(&["KHR_draco_mesh_compression".into()], &doc).unwrap_err().contains("Draco"));
        assert!(required(&["KHR_mesh_quantization".into()], &doc).unwrap().is_empty());
    }
}

//! A minimal glTF 2.0 writer for tests and generated scenes: meshes of triangle primitives (any
//! mode, indexed or not, with optional texture coordinates and material), a node tree with
//! translation / scale / matrix, one optional camera, and materials whose base colour may carry an
//! alpha mask (`alphaMode: MASK`) from a PNG. Written as one `.glb`, or as `.gltf` JSON beside a
//! `.bin`. Only what `gltf_mesh` reads is written; everything is little-endian, as glTF requires.
//! `quantize`, `meshopt_compress` and `declare` rewrite an encoded document the way production
//! pipelines do (KHR_mesh_quantization, EXT_meshopt_compression), for the extensions' tests.

use serde_json::{Value, json};

/// One primitive: `mode` is glTF's number (4 TRIANGLES, 5 TRIANGLE_STRIP, 6 TRIANGLE_FAN, 1 LINES…).
#[derive(Debug, Clone, Default)]
pub struct Prim {
    pub positions: Vec<[f32; 3]>,
    pub indices: Option<Vec<u32>>,
    pub mode: u32,
    pub uvs: Option<Vec<[f32; 2]>>,
    pub material: Option<usize>,
}

/// A node: what it draws or places, its local transform, its children.
#[derive(Debug, Clone, Default)]
pub struct Node {
    pub mesh: Option<usize>,
    pub camera: Option<usize>,
    pub translation: Option<[f64; 3]>,
    pub scale: Option<[f64; 3]>,
    /// Column-major, replaces translation and scale.
    pub matrix: Option<[f64; 16]>,
    pub children: Vec<usize>,
}

/// A material; `texture` is an image's index, `alpha_cutoff` makes it `MASK`.
#[derive(Debug, Clone)]
pub struct Material {
    pub base_color_factor: [f32; 4],
    pub texture: Option<usize>,
    pub alpha_cutoff: Option<f32>,
}

/// A whole document; `cameras` are (yfov radians) perspective cameras.
#[derive(Debug, Clone, Default)]
pub struct Doc {
    pub meshes: Vec<Vec<Prim>>,
    pub nodes: Vec<Node>,
    /// The scene's root nodes.
    pub roots: Vec<usize>,
    pub cameras: Vec<f32>,
    pub materials: Vec<Material>,
    /// Image files' bytes (PNG), stored in the binary buffer.
    pub images: Vec<Vec<u8>>,
    /// If not empty, each image's file name instead: the JSON names it by `uri` (the caller writes
    /// the bytes of `images` there) rather than storing it in the buffer.
    pub image_uris: Vec<String>,
}

impl Doc {
    /// The JSON (its one buffer with `uri` if given, else the GLB chunk) and the binary buffer.
    pub fn encode(&self, uri: Option<&str>) -> (Value, Vec<u8>) {
        let mut bin = Vec::new();
        let (mut views, mut accessors) = (Vec::new(), Vec::new());
        let mut push = |bin: &mut Vec<u8>, bytes: &[u8], accessor: Option<Value>| -> usize {
            while !bin.len().is_multiple_of(4) {
                bin.push(0);
            }
            views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len()}));
            bin.extend_from_slice(bytes);
            if let Some(mut a) = accessor {
                a["bufferView"] = json!(views.len() - 1);
                accessors.push(a);
                accessors.len() - 1
            } else {
                views.len() - 1
            }
        };
        let f32s = |v: &mut dyn Iterator<Item = f32>| v.flat_map(f32::to_le_bytes).collect::<Vec<u8>>();
        let mut meshes = Vec::new();
        for m in &self.meshes {
            let mut prims = Vec::new();
            for p in m {
                let (lo, hi) = p.positions.iter().fold(([f32::MAX; 3], [f32::MIN; 3]), |(lo, hi), v| {
                    (std::array::from_fn(|i| lo[i].min(v[i])), std::array::from_fn(|i| hi[i].max(v[i])))
                });
                let pos = f32s(&mut p.positions.iter().flatten().copied());
                let a = json!({"componentType": 5126, "count": p.positions.len(), "type": "VEC3",
                    "min": lo, "max": hi});
                let mut attributes = json!({"POSITION": push(&mut bin, &pos, Some(a))});
                if let Some(uvs) = &p.uvs {
                    let t = f32s(&mut uvs.iter().flatten().copied());
                    let a = json!({"componentType": 5126, "count": uvs.len(), "type": "VEC2"});
                    attributes["TEXCOORD_0"] = json!(push(&mut bin, &t, Some(a)));
                }
                let mut prim = json!({"attributes": attributes, "mode": p.mode});
                if let Some(ix) = &p.indices {
                    let b: Vec<u8> = ix.iter().flat_map(|i| i.to_le_bytes()).collect();
                    let a = json!({"componentType": 5125, "count": ix.len(), "type": "SCALAR"});
                    prim["indices"] = json!(push(&mut bin, &b, Some(a)));
                }
                if let Some(m) = p.material {
                    prim["material"] = json!(m);
                }
                prims.push(prim);
            }
            meshes.push(json!({"primitives": prims}));
        }
        let images: Vec<Value> = self
            .images
            .iter()
            .enumerate()
            .map(|(i, png)| match self.image_uris.get(i) {
                Some(uri) => json!({"uri": uri}),
                None => json!({"bufferView": push(&mut bin, png, None), "mimeType": "image/png"}),
            })
            .collect();
        let nodes: Vec<Value> = self
            .nodes
            .iter()
            .map(|n| {
                let mut v = json!({});
                if let Some(m) = n.mesh {
                    v["mesh"] = json!(m);
                }
                if let Some(c) = n.camera {
                    v["camera"] = json!(c);
                }
                if let Some(t) = n.translation {
                    v["translation"] = json!(t);
                }
                if let Some(s) = n.scale {
                    v["scale"] = json!(s);
                }
                if let Some(m) = n.matrix {
                    v["matrix"] = json!(m);
                }
                if !n.children.is_empty() {
                    v["children"] = json!(n.children);
                }
                v
            })
            .collect();
        let materials: Vec<Value> = self
            .materials
            .iter()
            .map(|m| {
                let mut pbr = json!({"baseColorFactor": m.base_color_factor});
                if let Some(t) = m.texture {
                    pbr["baseColorTexture"] = json!({"index": t});
                }
                let mut v = json!({"pbrMetallicRoughness": pbr});
                if let Some(c) = m.alpha_cutoff {
                    v["alphaMode"] = json!("MASK");
                    v["alphaCutoff"] = json!(c);
                }
                v
            })
            .collect();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let mut buffer = json!({"byteLength": bin.len()});
        if let Some(u) = uri {
            buffer["uri"] = json!(u);
        }
        let cameras: Vec<Value> = self
            .cameras
            .iter()
            .map(|&y| json!({"type": "perspective", "perspective": {"yfov": y, "znear": 0.01}}))
            .collect();
        let mut doc = json!({
            "asset": {"version": "2.0", "generator": "hemilab gltf_write"},
            "scene": 0,
            "scenes": [{"nodes": self.roots}],
            "nodes": nodes,
            "meshes": meshes,
            "buffers": [buffer],
            "bufferViews": views,
            "accessors": accessors,
        });
        let textures: Vec<Value> = (0..images.len()).map(|i| json!({"source": i})).collect();
        for (key, list) in
            [("cameras", cameras), ("materials", materials), ("images", images), ("textures", textures)]
        {
            if !list.is_empty() {
                doc[key] = Value::Array(list);
            }
        }
        (doc, bin)
    }

    /// A binary glTF: header, JSON chunk (space-padded), BIN chunk (glTF 2.0 section 4.4).
    pub fn to_glb(&self) -> Vec<u8> {
        let (doc, bin) = self.encode(None);
        glb(&doc, &bin)
    }

    /// A `.gltf` JSON text whose one buffer is the file `bin_uri`, and that buffer's bytes.
    pub fn to_gltf(&self, bin_uri: &str) -> (String, Vec<u8>) {
        let (doc, bin) = self.encode(Some(bin_uri));
        (serde_json::to_string_pretty(&doc).expect("json"), bin)
    }
}

/// A binary glTF of `doc` and its BIN chunk `bin` (glTF 2.0 section 4.4): header, JSON chunk
/// (space-padded), BIN chunk.
pub fn glb(doc: &Value, bin: &[u8]) -> Vec<u8> {
    let mut text = serde_json::to_vec(doc).expect("json");
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let total = 12 + 8 + text.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    for w in [0x4654_6C67u32, 2, total as u32, text.len() as u32, 0x4E4F_534A] {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out.extend_from_slice(&text);
    for w in [bin.len() as u32, 0x004E_4942] {
        out.extend_from_slice(&w.to_le_bytes());
    }
    out.extend_from_slice(bin);
    out
}

/// Adds `ext` to the document's `extensionsUsed` and, if `required`, `extensionsRequired`.
pub fn declare(doc: &mut Value, ext: &str, required: bool) {
    let keys: &[&str] =
        if required { &["extensionsUsed", "extensionsRequired"] } else { &["extensionsUsed"] };
    for key in keys {
        let list = doc[*key].as_array().cloned().unwrap_or_default();
        if !list.iter().any(|e| e == ext) {
            let mut list = list;
            list.push(json!(ext));
            doc[*key] = Value::Array(list);
        }
    }
}

/// `KHR_mesh_quantization`: every accessor of attribute `semantic` (`POSITION`, `TEXCOORD_0`) is
/// rewritten as glTF component type `component` (5120 BYTE, 5121 UNSIGNED_BYTE, 5122 SHORT, 5123
/// UNSIGNED_SHORT), `normalized` or not: each value x stored as round(x · (2^(b-1) − 1)) (signed)
/// or round(x · (2^b − 1)) (unsigned) if normalized, else round(x), in a new buffer view whose
/// elements are padded to 4 bytes (the specification's alignment rule). The extension is declared
/// required.
pub fn quantize(doc: &mut Value, bin: &mut Vec<u8>, semantic: &str, component: u32, normalized: bool) {
    let (size, max) = match component {
        5120 => (1, 127.0),
        5121 => (1, 255.0),
        5122 => (2, 32767.0),
        5123 => (2, 65535.0),
        _ => panic!("component type {component}"),
    };
    let scale = if normalized { max } else { 1.0 };
    let mut targets: Vec<u64> = Vec::new();
    for m in doc["meshes"].as_array().cloned().unwrap_or_default() {
        for p in m["primitives"].as_array().cloned().unwrap_or_default() {
            if let Some(a) = p["attributes"][semantic].as_u64().filter(|a| !targets.contains(a)) {
                targets.push(a);
            }
        }
    }
    for a in targets {
        let acc = doc["accessors"][a as usize].clone();
        let n = if acc["type"] == "VEC3" { 3 } else { 2 };
        let view = &doc["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
        let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let count = acc["count"].as_u64().unwrap() as usize;
        let values: Vec<f64> = (0..count * n)
            .map(|i| f32::from_le_bytes(bin[start + 4 * i..start + 4 * i + 4].try_into().unwrap()) as f64)
            .collect();
        let stride = (n * size).div_ceil(4) * 4;
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let offset = bin.len();
        let q = |x: f64| (x * scale).round();
        for e in values.chunks_exact(n) {
            let mut bytes: Vec<u8> = e
                .iter()
                .flat_map(|&x| match component {
                    5120 => vec![q(x) as i8 as u8],
                    5121 => vec![q(x) as u8],
                    5122 => (q(x) as i16).to_le_bytes().to_vec(),
                    _ => (q(x) as u16).to_le_bytes().to_vec(),
                })
                .collect();
            bytes.resize(stride, 0);
            bin.extend_from_slice(&bytes);
        }
        let views = doc["bufferViews"].as_array_mut().unwrap();
        views.push(
            json!({"buffer": 0, "byteOffset": offset, "byteLength": count * stride, "byteStride": stride,
            "target": 34962}),
        );
        let v = views.len() - 1;
        let acc = &mut doc["accessors"][a as usize];
        acc["bufferView"] = json!(v);
        acc["componentType"] = json!(component);
        if normalized {
            acc["normalized"] = json!(true);
        }
        for key in ["min", "max"] {
            if let Some(list) = acc[key].as_array().cloned() {
                acc[key] = json!(list.iter().map(|x| q(x.as_f64().unwrap())).collect::<Vec<f64>>());
            }
        }
    }
    doc["buffers"][0]["byteLength"] = json!(bin.len());
    declare(doc, "KHR_mesh_quantization", true);
}

/// `EXT_meshopt_compression` (declared required): every buffer view an accessor uses is stored
/// compressed (attributes by the vertex codec, element-sized strides; `u32` indices of TRIANGLES
/// primitives by the index codec, other indices by the index-sequence codec) in buffer 0, which
/// becomes the returned bytes; the views themselves move to a new `fallback` buffer 1 without data.
/// With `exponential`, float attributes are first encoded by the EXPONENTIAL filter with a fixed
/// exponent of −16 (exact for values with at most 16 fractional bits under 128). Image views are
/// copied into buffer 0 as they are.
pub fn meshopt_compress(doc: &mut Value, bin: &[u8], exponential: bool) -> Vec<u8> {
    use meshopt_rs::index::IndexEncodingVersion;
    use meshopt_rs::index::{buffer, sequence};
    use meshopt_rs::vertex::VertexEncodingVersion;
    use meshopt_rs::vertex::buffer::{encode_vertex_buffer, encode_vertex_buffer_bound};
    fn vertices<const N: usize>(data: &[u8]) -> Vec<u8> {
        let v: Vec<[u8; N]> = data.chunks_exact(N).map(|c| c.try_into().unwrap()).collect();
        let mut out = vec![0; encode_vertex_buffer_bound(v.len(), N)];
        let n = encode_vertex_buffer(&mut out, &v, VertexEncodingVersion::V0).expect("room");
        out.truncate(n);
        out
    }
    let mut modes: Vec<Option<(&str, usize, usize)>> =
        vec![None; doc["bufferViews"].as_array().unwrap().len()];
    let mut triangles = Vec::new();
    for m in doc["meshes"].as_array().unwrap() {
        for p in m["primitives"].as_array().unwrap() {
            if p["mode"].as_u64().unwrap_or(4) == 4 {
                triangles.extend(p["indices"].as_u64());
            }
        }
    }
    for (i, a) in doc["accessors"].as_array().unwrap().iter().enumerate() {
        let view = a["bufferView"].as_u64().unwrap() as usize;
        let count = a["count"].as_u64().unwrap() as usize;
        modes[view] = Some(match a["type"].as_str().unwrap() {
            "SCALAR" if triangles.contains(&(i as u64)) && count.is_multiple_of(3) => ("TRIANGLES", 4, count),
            "SCALAR" => ("INDICES", 4, count),
            "VEC3" => ("ATTRIBUTES", 12, count),
            _ => ("ATTRIBUTES", 8, count),
        });
    }
    let mut out = Vec::new();
    let views = doc["bufferViews"].as_array_mut().unwrap();
    for (view, mode) in views.iter_mut().zip(modes) {
        let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let data = &bin[start..start + view["byteLength"].as_u64().unwrap() as usize];
        while !out.len().is_multiple_of(4) {
            out.push(0);
        }
        let at = out.len();
        let Some((mode, stride, count)) = mode else {
            out.extend_from_slice(data);
            view["buffer"] = json!(0);
            view["byteOffset"] = json!(at);
            continue;
        };
        let filtered: Vec<u8>;
        let data = if exponential && mode == "ATTRIBUTES" {
            filtered = data
                .chunks_exact(4)
                .flat_map(|c| {
                    let m = (f32::from_le_bytes(c.try_into().unwrap()) as f64 * 65536.0).round() as i32;
                    (((-16i8 as u8 as u32) << 24) | (m as u32 & 0x00FF_FFFF)).to_le_bytes()
                })
                .collect();
            &filtered[..]
        } else {
            data
        };
        let encoded = match mode {
            "ATTRIBUTES" if stride == 12 => vertices::<12>(data),
            "ATTRIBUTES" => vertices::<8>(data),
            _ => {
                let ix: Vec<u32> =
                    data.chunks_exact(4).map(|c| u32::from_le_bytes(c.try_into().unwrap())).collect();
                let vertices = ix.iter().max().map_or(0, |&m| m as usize + 1);
                if mode == "TRIANGLES" {
                    let mut e = vec![0; buffer::encode_index_buffer_bound(ix.len(), vertices)];
                    let n = buffer::encode_index_buffer(&mut e, &ix, IndexEncodingVersion::V1).expect("room");
                    e.truncate(n);
                    e
                } else {
                    let mut e = vec![0; sequence::encode_index_sequence_bound(ix.len(), vertices)];
                    let n = sequence::encode_index_sequence(&mut e, &ix, IndexEncodingVersion::V1);
                    e.truncate(n);
                    e
                }
            }
        };
        out.extend_from_slice(&encoded);
        let mut ext = json!({"buffer": 0, "byteOffset": at, "byteLength": encoded.len(), "byteStride": stride,
            "count": count, "mode": mode});
        if exponential && mode == "ATTRIBUTES" {
            ext["filter"] = json!("EXPONENTIAL");
        }
        view["buffer"] = json!(1);
        view["extensions"] = json!({"EXT_meshopt_compression": ext});
    }
    while !out.len().is_multiple_of(4) {
        out.push(0);
    }
    let mut data_buffer = doc["buffers"][0].clone();
    data_buffer["byteLength"] = json!(out.len());
    doc["buffers"] = json!([data_buffer, {"byteLength": bin.len(),
        "extensions": {"EXT_meshopt_compression": {"fallback": true}}}]);
    declare(doc, "EXT_meshopt_compression", true);
    out
}

/// A mesh of one TRIANGLES primitive, indexed, from a triangle soup (each triangle its own 3 vertices).
pub fn soup(triangles: &[[[f32; 3]; 3]]) -> Vec<Prim> {
    let positions: Vec<[f32; 3]> = triangles.iter().flatten().copied().collect();
    let indices = Some((0..positions.len() as u32).collect());
    vec![Prim { positions, indices, mode: 4, ..Prim::default() }]
}

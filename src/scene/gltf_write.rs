//! A minimal glTF 2.0 writer for tests and generated scenes: meshes of triangle primitives (any
//! mode, indexed or not, with optional texture coordinates and material), a node tree with
//! translation / scale / matrix, one optional camera, and materials whose base colour may carry an
//! alpha mask (`alphaMode: MASK`) from a PNG. Written as one `.glb`, or as `.gltf` JSON beside a
//! `.bin`. Only what `gltf_mesh` reads is written; everything is little-endian, as glTF requires.

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
        let mut text = serde_json::to_vec(&doc).expect("json");
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
        out.extend_from_slice(&bin);
        out
    }

    /// A `.gltf` JSON text whose one buffer is the file `bin_uri`, and that buffer's bytes.
    pub fn to_gltf(&self, bin_uri: &str) -> (String, Vec<u8>) {
        let (doc, bin) = self.encode(Some(bin_uri));
        (serde_json::to_string_pretty(&doc).expect("json"), bin)
    }
}

/// A mesh of one TRIANGLES primitive, indexed, from a triangle soup (each triangle its own 3 vertices).
pub fn soup(triangles: &[[[f32; 3]; 3]]) -> Vec<Prim> {
    let positions: Vec<[f32; 3]> = triangles.iter().flatten().copied().collect();
    let indices = Some((0..positions.len() as u32).collect());
    vec![Prim { positions, indices, mode: 4, ..Prim::default() }]
}

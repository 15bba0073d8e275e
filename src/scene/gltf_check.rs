//! The wall in front of the `gltf` crate: a glTF file's JSON checked before the crate's validation
//! and readers touch it. The crate trusts what it validates and some of its own validation trusts
//! more than it checks: its POSITION check indexes `accessors` directly (a file without them
//! panics), `Camera::projection` unwraps the object its `type` names, `Image::source` unwraps a
//! `uri` or a `bufferView` and its `mimeType`, the index reader has no arm for FLOAT, and the
//! accessor iterator slices a byte stride smaller than its element. Each such assumption is made a
//! rule here with one message naming the object (`accessors[3]`, `cameras[0]`), as the glTF 2.0
//! specification states it; the crate's own validation then reports the rest.
//!
//! Sizes are checked against what the file declares (an accessor within its view, a view within its
//! buffer; `gltf_mesh` then checks every buffer holds its declared bytes), so no reader slices past
//! its data and nothing is allocated from a count the bytes cannot back.

use serde_json::Value;

/// The largest buffer hemilab allocates from a declared `byteLength` alone (an
/// `EXT_meshopt_compression` fallback buffer, which has no bytes of its own): 4 GiB, far above any
/// scene's geometry here and below what a typo (2^40) would ask the allocator for.
pub const MAX_DECLARED_BUFFER: u64 = 1 << 32;

/// The most elements a sparse accessor without a `bufferView` (zeros, then its sparse values) may
/// have: 2^26, 64 M vertices.
pub const MAX_SPARSE_ONLY: u64 = 1 << 26;

/// A JSON member as the crate reads it: `null` is absent (serde gives `None` for it).
trait Field {
    fn field(&self, key: &str) -> Option<&Value>;
}

impl Field for Value {
    fn field(&self, key: &str) -> Option<&Value> {
        self.get(key).filter(|v| !v.is_null())
    }
}

/// The array `key` of the top level (empty when absent).
fn list<'a>(j: &'a Value, key: &str) -> &'a [Value] {
    j.field(key).and_then(Value::as_array).map_or(&[], |a| &a[..])
}

/// The index `v[key]`, if present, checked against the top-level array `target`; `at` names `v`.
fn reference(j: &Value, v: &Value, key: &str, target: &str, at: &dyn Fn() -> String) -> Result<(), String> {
    let Some(x) = v.field(key) else { return Ok(()) };
    index(j, x, target, &|| format!("{}.{key}", at())).map(|_| ())
}

/// `x` as an index into the top-level array `target`.
fn index(j: &Value, x: &Value, target: &str, at: &dyn Fn() -> String) -> Result<usize, String> {
    let n = list(j, target).len();
    match x.as_u64() {
        Some(i) if (i as usize) < n && i < u32::MAX as u64 => Ok(i as usize),
        _ => Err(format!(
            "{}: {x} is not an index of `{target}` (the file has {n}{}, indices 0 to {})",
            at(),
            if n == 0 { format!(": no `{target}` array") } else { String::new() },
            n as i64 - 1
        )),
    }
}

/// Checks a GLB file's 12-byte header before `gltf::Glb::from_slice` reads it: the crate subtracts
/// the header's size from the declared length unchecked (a length under 12 overflows), so the
/// version must be 2 and the declared length hold the header and a chunk header, within the file
/// (glTF 2.0 §4.4.2). Found by the cargo-fuzz `gltf` target.
pub fn glb_header(bytes: &[u8]) -> Result<(), String> {
    let word = |at: usize| bytes.get(at..at + 4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        return Err(format!(
            "not a readable glTF 2.0 file: a GLB header is 12 bytes, the file has {}",
            bytes.len()
        ));
    };
    if version != 2 {
        return Err(format!("not a readable glTF 2.0 file: GLB version {version}; allowed: 2"));
    }
    if !(20..=bytes.len() as u64).contains(&u64::from(length)) {
        return Err(format!(
            "not a readable glTF 2.0 file: the GLB header declares {length} bytes; allowed: 20 (a header and \
             a chunk header) up to the file's {} bytes",
            bytes.len()
        ));
    }
    Ok(())
}

/// Checks the document's JSON before the `gltf` crate validates it (see the module doc).
pub fn document(j: &Value) -> Result<(), String> {
    if !j.is_object() {
        return Err("not a readable glTF 2.0 file: the JSON is not an object".into());
    }
    references(j)?;
    for (i, c) in list(j, "cameras").iter().enumerate() {
        let kind = c.field("type").and_then(Value::as_str).unwrap_or("");
        if matches!(kind, "perspective" | "orthographic") && c.field(kind).is_none_or(|o| !o.is_object()) {
            return Err(format!(
                "cameras[{i}]: its `type` is \"{kind}\" but it has no `{kind}` object (the type names the object \
                 that holds the projection)"
            ));
        }
    }
    for (i, image) in list(j, "images").iter().enumerate() {
        match (image.field("uri"), image.field("bufferView"), image.field("mimeType")) {
            (None, None, _) => {
                return Err(format!("images[{i}]: has neither a `uri` nor a `bufferView` (it needs one)"));
            }
            (Some(_), Some(_), _) => {
                return Err(format!("images[{i}]: has both a `uri` and a `bufferView` (it may have one)"));
            }
            (None, Some(_), None) => {
                return Err(format!("images[{i}]: an image in a `bufferView` needs its `mimeType`"));
            }
            _ => {}
        }
    }
    for (i, m) in list(j, "materials").iter().enumerate() {
        if let Some(c) = m.field("alphaCutoff") {
            match c.as_f64() {
                Some(v) if (0.0..=1.0).contains(&v) => {}
                _ => {
                    return Err(format!(
                        "materials[{i}]: alphaCutoff {c} is outside [0, 1] (a texel is opaque when its alpha, in \
                         [0, 1], is at least the cutoff: below 0 or above 1 nothing or everything is cut away)"
                    ));
                }
            }
        }
    }
    for (m, mesh) in list(j, "meshes").iter().enumerate() {
        for (p, prim) in list(mesh, "primitives").iter().enumerate() {
            let Some(a) = prim.field("indices").and_then(Value::as_u64) else { continue };
            let acc = &list(j, "accessors")[a as usize];
            let ct = acc.field("componentType").and_then(Value::as_u64).unwrap_or(0);
            let ty = acc.field("type").and_then(Value::as_str).unwrap_or("");
            if !matches!(ct, 5121 | 5123 | 5125) || ty != "SCALAR" {
                return Err(format!(
                    "meshes[{m}].primitives[{p}].indices: accessors[{a}] is {ty} of componentType {ct}; indices \
                     are SCALAR of UNSIGNED_BYTE (5121), UNSIGNED_SHORT (5123) or UNSIGNED_INT (5125)"
                ));
            }
        }
    }
    sizes(j)?;
    node_trees(j)
}

/// Every index the crate (or this reader) follows, in range. The crate checks most of them too, but
/// after validation hooks that index first.
fn references(j: &Value) -> Result<(), String> {
    for (m, mesh) in list(j, "meshes").iter().enumerate() {
        for (p, prim) in list(mesh, "primitives").iter().enumerate() {
            let at = || format!("meshes[{m}].primitives[{p}]");
            let attributes = prim.field("attributes").and_then(Value::as_object);
            for (name, a) in attributes.into_iter().flatten() {
                index(j, a, "accessors", &|| format!("{}.attributes.{name}", at()))?;
            }
            reference(j, prim, "indices", "accessors", &at)?;
            reference(j, prim, "material", "materials", &at)?;
            for (t, target) in list(prim, "targets").iter().enumerate() {
                for (name, a) in target.as_object().into_iter().flatten() {
                    index(j, a, "accessors", &|| format!("{}.targets[{t}].{name}", at()))?;
                }
            }
        }
    }
    for (i, a) in list(j, "accessors").iter().enumerate() {
        let at = || format!("accessors[{i}]");
        reference(j, a, "bufferView", "bufferViews", &at)?;
        if let Some(s) = a.field("sparse") {
            reference(j, &s["indices"], "bufferView", "bufferViews", &|| format!("{}.sparse.indices", at()))?;
            reference(j, &s["values"], "bufferView", "bufferViews", &|| format!("{}.sparse.values", at()))?;
        }
    }
    for (i, v) in list(j, "bufferViews").iter().enumerate() {
        reference(j, v, "buffer", "buffers", &|| format!("bufferViews[{i}]"))?;
    }
    for (i, n) in list(j, "nodes").iter().enumerate() {
        let at = || format!("nodes[{i}]");
        reference(j, n, "mesh", "meshes", &at)?;
        reference(j, n, "camera", "cameras", &at)?;
        for (k, c) in list(n, "children").iter().enumerate() {
            index(j, c, "nodes", &|| format!("nodes[{i}].children[{k}]"))?;
        }
    }
    for (i, s) in list(j, "scenes").iter().enumerate() {
        for (k, n) in list(s, "nodes").iter().enumerate() {
            index(j, n, "nodes", &|| format!("scenes[{i}].nodes[{k}]"))?;
        }
    }
    reference(j, j, "scene", "scenes", &|| "the top level".into())?;
    for (i, t) in list(j, "textures").iter().enumerate() {
        reference(j, t, "source", "images", &|| format!("textures[{i}]"))?;
        reference(j, t, "sampler", "samplers", &|| format!("textures[{i}]"))?;
    }
    for (i, image) in list(j, "images").iter().enumerate() {
        reference(j, image, "bufferView", "bufferViews", &|| format!("images[{i}]"))?;
    }
    for (i, m) in list(j, "materials").iter().enumerate() {
        let pbr = &m["pbrMetallicRoughness"];
        for (holder, key) in [
            (pbr, "baseColorTexture"),
            (pbr, "metallicRoughnessTexture"),
            (m, "normalTexture"),
            (m, "occlusionTexture"),
            (m, "emissiveTexture"),
        ] {
            if let Some(info) = holder.field(key) {
                reference(j, info, "index", "textures", &|| format!("materials[{i}] {key}"))?;
            }
        }
    }
    Ok(())
}

/// `v[key]` as a size (absent: `default`).
fn size(v: &Value, key: &str, default: Option<u64>, at: &dyn Fn() -> String) -> Result<u64, String> {
    match v.field(key) {
        None => default.ok_or_else(|| format!("{}: `{key}` is missing", at())),
        Some(x) => x.as_u64().ok_or_else(|| format!("{}: `{key}` {x} is not a size", at())),
    }
}

/// The bytes of one element of an accessor (None: a component type or type the crate refuses).
fn element(a: &Value) -> Option<u64> {
    let component = match a.field("componentType")?.as_u64()? {
        5120 | 5121 => 1,
        5122 | 5123 => 2,
        5125 | 5126 => 4,
        _ => return None,
    };
    let n = match a.field("type")?.as_str()? {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" | "MAT2" => 4,
        "MAT3" => 9,
        "MAT4" => 16,
        _ => return None,
    };
    Some(component * n)
}

/// Every view within its buffer's declared length, and every accessor (and its sparse parts) within
/// its view, with a stride no smaller than its element.
fn sizes(j: &Value) -> Result<(), String> {
    let buffers = list(j, "buffers");
    let views = list(j, "bufferViews");
    for (i, b) in buffers.iter().enumerate() {
        let len = size(b, "byteLength", None, &|| format!("buffers[{i}]"))?;
        if b["extensions"]["EXT_meshopt_compression"]["fallback"].as_bool() == Some(true)
            && len > MAX_DECLARED_BUFFER
        {
            return Err(format!(
                "buffers[{i}]: an EXT_meshopt_compression fallback buffer of {len} bytes, more than the \
                 {MAX_DECLARED_BUFFER} hemilab allocates for a buffer with no bytes of its own"
            ));
        }
    }
    // (offset, length, stride) of each view, within its buffer.
    let mut extent = Vec::with_capacity(views.len());
    for (i, v) in views.iter().enumerate() {
        let at = || format!("bufferViews[{i}]");
        let (offset, len) = (size(v, "byteOffset", Some(0), &at)?, size(v, "byteLength", None, &at)?);
        let buffer = v
            .field("buffer")
            .and_then(Value::as_u64)
            .ok_or_else(|| format!("{}: `buffer` is missing", at()))?;
        let room = size(&buffers[buffer as usize], "byteLength", None, &|| format!("buffers[{buffer}]"))?;
        if offset.checked_add(len).is_none_or(|end| end > room) {
            return Err(format!(
                "{}: bytes {offset}..+{len} lie outside buffers[{buffer}] ({room} bytes)",
                at()
            ));
        }
        if let Some(ext) = v.field("extensions").and_then(|e| e.field("EXT_meshopt_compression")) {
            meshopt_view(j, ext, len, &at)?;
        }
        extent.push((len, v.field("byteStride").and_then(Value::as_u64)));
    }
    for (i, a) in list(j, "accessors").iter().enumerate() {
        let at = || format!("accessors[{i}]");
        let count = size(a, "count", None, &at)?;
        if count == 0 {
            return Err(format!("{}: `count` is 0 (an accessor has at least one element)", at()));
        }
        let Some(elem) = element(a) else { continue };
        let offset = size(a, "byteOffset", Some(0), &at)?;
        match a.field("bufferView").and_then(Value::as_u64) {
            Some(v) => {
                within(extent[v as usize], offset, count, elem, &|| format!("{} (bufferViews[{v}])", at()))?
            }
            None if count > MAX_SPARSE_ONLY => {
                return Err(format!(
                    "{}: {count} elements with no `bufferView`, more than the {MAX_SPARSE_ONLY} hemilab reads",
                    at()
                ));
            }
            None => {}
        }
        let Some(s) = a.field("sparse") else { continue };
        let n = size(s, "count", None, &|| format!("{}.sparse", at()))?;
        if n == 0 || n > count {
            return Err(format!("{}.sparse: `count` {n} is not in 1..={count} (the accessor's count)", at()));
        }
        let ix = &s["indices"];
        let ix_size = match ix.field("componentType").and_then(Value::as_u64) {
            Some(5121) => 1,
            Some(5123) => 2,
            Some(5125) => 4,
            other => {
                return Err(format!(
                    "{}.sparse.indices: componentType {} is not UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT",
                    at(),
                    other.map_or("(missing)".into(), |c| c.to_string())
                ));
            }
        };
        for (part, what, elem) in [(ix, "indices", ix_size), (&s["values"], "values", elem)] {
            let at = || format!("{}.sparse.{what}", at());
            let v = size(part, "bufferView", None, &at)?;
            let offset = size(part, "byteOffset", Some(0), &at)?;
            // Sparse data is tightly packed: its views have no stride.
            within((extent[v as usize].0, None), offset, n, elem, &at)?;
        }
    }
    Ok(())
}

/// `count` elements of `elem` bytes from `offset`, `stride` apart, within a view of `len` bytes.
fn within(
    (len, stride): (u64, Option<u64>),
    offset: u64,
    count: u64,
    elem: u64,
    at: &dyn Fn() -> String,
) -> Result<(), String> {
    let stride = stride.unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "{}: its view's byteStride {stride} is smaller than one element ({elem} bytes)",
            at()
        ));
    }
    let end =
        stride.checked_mul(count - 1).and_then(|s| s.checked_add(offset)).and_then(|s| s.checked_add(elem));
    if end.is_none_or(|e| e > len) {
        return Err(format!(
            "{}: {count} elements of {elem} bytes, {stride} apart from byte {offset}, do not fit in its view ({len} \
             bytes)",
            at()
        ));
    }
    Ok(())
}

/// An `EXT_meshopt_compression` view decodes to `count` × `byteStride` bytes: they must fit in the
/// view it fills, and its compressed bytes within their buffer, before anything is decoded.
fn meshopt_view(j: &Value, ext: &Value, len: u64, at: &dyn Fn() -> String) -> Result<(), String> {
    let at = || format!("{}: EXT_meshopt_compression", at());
    let (count, stride) = (size(ext, "count", None, &at)?, size(ext, "byteStride", None, &at)?);
    let decoded = count.checked_mul(stride);
    if decoded.is_none_or(|d| d > len) {
        return Err(format!("{}: decodes to {count} x {stride} bytes, more than the view's {len}", at()));
    }
    let buffer =
        index(j, ext.field("buffer").unwrap_or(&Value::Null), "buffers", &|| format!("{}.buffer", at()))?;
    let room = size(&list(j, "buffers")[buffer], "byteLength", None, &|| format!("buffers[{buffer}]"))?;
    let (offset, n) = (size(ext, "byteOffset", Some(0), &at)?, size(ext, "byteLength", None, &at)?);
    if offset.checked_add(n).is_none_or(|end| end > room) {
        return Err(format!(
            "{}: its data (bytes {offset}..+{n}) lies outside buffers[{buffer}] ({room} bytes)",
            at()
        ));
    }
    Ok(())
}

/// glTF 2.0 section 3.5.3: "the node hierarchy MUST be a set of disjoint strict trees": no node is
/// the child of two nodes, and no node its own ancestor (a cycle would be walked forever).
fn node_trees(j: &Value) -> Result<(), String> {
    let nodes = list(j, "nodes");
    let mut parent: Vec<Option<usize>> = vec![None; nodes.len()];
    for (i, n) in nodes.iter().enumerate() {
        for c in list(n, "children") {
            let c = c.as_u64().expect("checked: an index") as usize;
            if let Some(p) = parent[c] {
                return Err(format!(
                    "nodes[{c}] is a child of nodes[{p}] and nodes[{i}]; a node has at most one parent (glTF 2.0, \
                     section 3.5.3: the node hierarchy is a set of disjoint trees)"
                ));
            }
            parent[c] = Some(i);
        }
    }
    // With one parent each, a cycle is a chain of parents that comes back to where it started.
    let mut state = vec![0u8; nodes.len()]; // 0 unseen, 1 on the current chain, 2 done
    for start in 0..nodes.len() {
        let mut chain: Vec<usize> = Vec::new();
        let mut at = Some(start);
        while let Some(n) = at {
            match state[n] {
                2 => break,
                1 => {
                    let from = chain.iter().position(|&c| c == n).unwrap_or(0);
                    // The chain runs child to parent: reversed, and closed, it reads as `children` do.
                    let mut cycle: Vec<String> = chain[from..].iter().rev().map(|c| c.to_string()).collect();
                    cycle.push(cycle[0].clone());
                    return Err(format!(
                        "nodes: a cycle among `children` ({}); a node may not be its own ancestor",
                        cycle.join(" → ")
                    ));
                }
                _ => {}
            }
            state[n] = 1;
            chain.push(n);
            at = parent[n];
        }
        for c in chain {
            state[c] = 2;
        }
    }
    Ok(())
}

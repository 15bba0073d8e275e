//! Wavefront OBJ (optionally zstd-compressed) to a triangle soup: positions and indices only, because
//! AO needs nothing else. `obj` reads the text, every fault with its line.
//!
//! Positions are read as f64: a scene 1 km from the origin written with millimetre digits keeps them
//! until `Scene::new` has moved it next to the camera; only then are they rounded to the
//! renderer's f32.

use super::obj;
use glam::DVec3;
use std::io::Read;

/// Triangles kept (world coordinates, f64), the count of those dropped (zero area or non-finite),
/// and the elements skipped because they are not faces, for one warning each.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    pub triangles: Vec<[DVec3; 3]>,
    pub dropped: usize,
    /// Elements with no surface (`p`, `l`, `curv`, `curv2`, `surf`): keyword, count, first line.
    pub skipped: Vec<(&'static str, usize, usize)>,
    /// Other things a load warns about, one sentence each.
    pub notes: Vec<String>,
    /// Alpha masks, per triangle (as `triangles`), if the file's materials have any.
    pub alpha: Option<super::alpha::Source>,
}

impl Mesh {
    /// "2 `l` (polylines; first on line 7) and 1 `p` (points; line 9)", if any element was skipped.
    pub fn skipped_description(&self) -> Option<String> {
        let what = |k: &str| match k {
            "p" => "points",
            "l" => "polylines",
            _ => "free-form geometry",
        };
        let parts: Vec<String> = self
            .skipped
            .iter()
            .map(|&(k, n, line)| {
                let first = if n == 1 { format!("line {line}") } else { format!("first on line {line}") };
                format!("{n} `{k}` ({}; {first})", what(k))
            })
            .collect();
        (!parts.is_empty()).then(|| parts.join(", "))
    }
}

/// zstd frames start with this magic number (RFC 8878, 3.1.1), so a renamed file still decodes.
const ZSTD_MAGIC: [u8; 4] = [0x28, 0xB5, 0x2F, 0xFD];

/// Decodes `bytes` (plain OBJ text, or zstd-compressed OBJ) into triangles.
/// The error text says where (line) and what; the caller prefixes the file name.
pub fn parse_obj(bytes: &[u8]) -> Result<Mesh, String> {
    // Plain text is read in place: a copy would hold the whole file twice.
    let decoded;
    let text: &[u8] = if bytes.starts_with(&ZSTD_MAGIC) {
        decoded = decompress(bytes)?;
        &decoded
    } else {
        bytes
    };
    let text = std::str::from_utf8(text).map_err(|e| {
        let line = 1 + text[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count();
        format!("line {line}: not UTF-8 text (is this an OBJ file?)")
    })?;
    let parsed = obj::parse(text)?;
    let mut mesh = Mesh { skipped: parsed.skipped, ..Mesh::default() };
    let mut start = 0;
    for &end in &parsed.face_ends {
        let face = &parsed.corners[start..end];
        let at = |i: u32| parsed.positions[i as usize];
        for pair in face[1..].windows(2) {
            let tri = [at(face[0]), at(pair[0]), at(pair[1])];
            if usable(&tri) {
                mesh.triangles.push(tri);
            } else {
                mesh.dropped += 1;
            }
        }
        start = end;
    }
    if mesh.triangles.is_empty() {
        let skipped = mesh.skipped_description().map_or(String::new(), |s| format!("; skipped {s}"));
        return Err(if mesh.dropped == 1 {
            "empty mesh: its one triangle has zero area or non-finite vertices".into()
        } else if mesh.dropped > 0 {
            format!("empty mesh: all {} triangles have zero area or non-finite vertices", mesh.dropped)
        } else {
            format!("empty mesh: no faces (AO needs at least one triangle){skipped}")
        });
    }
    Ok(mesh)
}

/// The bytes of a mesh file as text bytes: zstd-decoded if they start with zstd's magic number,
/// else unchanged.
pub fn decompress(bytes: &[u8]) -> Result<Vec<u8>, String> {
    if !bytes.starts_with(&ZSTD_MAGIC) {
        return Ok(bytes.to_vec());
    }
    let mut out = Vec::new();
    ruzstd::decoding::StreamingDecoder::new(bytes)
        .map_err(|e| format!("not a readable zstd stream: {e}"))?
        .read_to_end(&mut out)
        .map_err(|e| format!("zstd decoding failed: {e}"))?;
    Ok(out)
}

/// A triangle is usable if its vertices are finite and it has a normal. `Scene::new` checks again
/// after rounding to f32, where more triangles can collapse.
pub fn usable(t: &[DVec3; 3]) -> bool {
    t.iter().all(|v| v.is_finite()) && {
        let n = (t[1] - t[0]).cross(t[2] - t[0]);
        n.is_finite() && n.length_squared() > 0.0 && n.normalize().is_finite()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_is_two_triangles_and_degenerates_are_counted() {
        let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nf 1 2 2\n";
        let m = parse_obj(obj.as_bytes()).unwrap();
        assert_eq!((m.triangles.len(), m.dropped), (2, 1));
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse_obj(b"v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 4\n").unwrap_err();
        assert!(e.contains("line 4") && e.contains("out of range"), "{e}");
        let e = parse_obj(b"v 0 0 0\nv 1 0 0\nf 1 2\n").unwrap_err();
        assert!(e.contains("line 3") && e.contains("triangulated"), "{e}");
        let e = parse_obj(b"# nothing\n").unwrap_err();
        assert!(e.contains("empty mesh"), "{e}");
        let e = parse_obj(b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n").unwrap_err();
        assert!(e.contains("zero area"), "{e}");
        let e = parse_obj(b"v 0 0\n").unwrap_err();
        assert!(e.contains("line 1"), "{e}");
    }
}

//! Wavefront OBJ (optionally zstd-compressed) to a triangle soup: positions and indices only, because
//! AO needs nothing else. tobj does the parsing; a light line scan first finds the faults tobj would
//! report without a line number (index out of range, faces of fewer than three vertices).
//!
//! Positions are read as f64 (tobj's `use_f64`): a scene 1 km from the origin written with
//! millimetre digits keeps them until `Scene::new` has moved it next to the camera; only then are
//! they rounded to the renderer's f32.

use glam::DVec3;
use std::io::Read;

/// Triangles kept (world coordinates, f64) and the count of those dropped (zero area or non-finite),
/// for one warning.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    pub triangles: Vec<[DVec3; 3]>,
    pub dropped: usize,
}

/// zstd frames start with this magic number (RFC 8878, 3.1.1), so a renamed file still decodes.
const ZSTD_MAGIC: [u8; 4] = [0x28, 0xB5, 0x2F, 0xFD];

/// Decodes `bytes` (plain OBJ text, or zstd-compressed OBJ) into triangles.
/// The error text says where (line) and what; the caller prefixes the file name.
pub fn parse_obj(bytes: &[u8]) -> Result<Mesh, String> {
    let text = decompress(bytes)?;
    let text = std::str::from_utf8(&text).map_err(|e| {
        let line = 1 + text[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count();
        format!("line {line}: not UTF-8 text (is this an OBJ file?)")
    })?;
    scan_lines(text)?;

    let options =
        tobj::LoadOptions { triangulate: true, single_index: false, ignore_points: true, ignore_lines: true };
    // Materials are never needed for AO: a loader that returns nothing skips every .mtl.
    let no_materials = |_: &std::path::Path| Ok((Vec::new(), Default::default()));
    let (models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &options, no_materials)
        .map_err(|e| format!("cannot parse OBJ: {e}"))?;

    let mut mesh = Mesh::default();
    for model in &models {
        let m = &model.mesh;
        let vertex = |i: u32| -> Result<DVec3, String> {
            let i = i as usize * 3;
            match m.positions.get(i..i + 3) {
                Some(p) => Ok(DVec3::new(p[0], p[1], p[2])),
                None => Err(format!("object '{}': face index out of range", model.name)),
            }
        };
        for f in m.indices.chunks(3) {
            if f.len() < 3 {
                return Err(format!("object '{}': a face is not a triangle", model.name));
            }
            let tri = [vertex(f[0])?, vertex(f[1])?, vertex(f[2])?];
            if usable(&tri) {
                mesh.triangles.push(tri);
            } else {
                mesh.dropped += 1;
            }
        }
    }
    if mesh.triangles.is_empty() {
        return Err(if mesh.dropped == 1 {
            "empty mesh: its one triangle has zero area or non-finite vertices".into()
        } else if mesh.dropped > 0 {
            format!("empty mesh: all {} triangles have zero area or non-finite vertices", mesh.dropped)
        } else {
            "empty mesh: no faces (AO needs at least one triangle)".into()
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

/// Finds, with its line number, the first face that indexes a missing vertex or has fewer than three
/// vertices, and the first vertex line that is not three numbers.
fn scan_lines(text: &str) -> Result<(), String> {
    let total = text.lines().filter(|l| is_keyword(l, "v")).count() as i64;
    let mut seen = 0i64;
    for (no, line) in text.lines().enumerate() {
        let line_no = no + 1;
        if is_keyword(line, "v") {
            seen += 1;
            let nums: Vec<&str> = line.split_whitespace().skip(1).collect();
            if nums.len() < 3 || nums.iter().take(3).any(|s| s.parse::<f64>().is_err()) {
                return Err(format!("line {line_no}: a vertex needs three numbers, found '{}'", line.trim()));
            }
        } else if is_keyword(line, "f") {
            let corners: Vec<&str> = line.split_whitespace().skip(1).collect();
            if corners.len() < 3 {
                return Err(format!(
                    "line {line_no}: a face with {} vertices cannot be triangulated (need at least 3)",
                    corners.len()
                ));
            }
            for c in corners {
                let first = c.split('/').next().unwrap_or("");
                let idx: i64 = first
                    .parse()
                    .map_err(|_| format!("line {line_no}: face vertex '{c}' is not an index"))?;
                // Positive indices count from 1 over the whole file; negative ones back from this line.
                let ok = if idx > 0 { idx <= total } else { idx < 0 && seen + idx >= 0 };
                if !ok {
                    return Err(format!(
                        "line {line_no}: face index {idx} out of range (the file has {total} vertices, \
                         {seen} before this line; indices start at 1)"
                    ));
                }
            }
        }
    }
    Ok(())
}

fn is_keyword(line: &str, key: &str) -> bool {
    let mut it = line.split_whitespace();
    it.next() == Some(key)
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

//! Wavefront OBJ (optionally zstd-compressed) to an indexed mesh: positions and indices only, because
//! AO needs nothing else. `obj` reads the text, every fault with its line.
//!
//! Positions are read as f64: a scene 1 km from the origin written with millimetre digits keeps them
//! until `Scene::new` has moved it next to the camera; only then are they rounded to the
//! renderer's f32.

use super::obj;
pub use super::obj_masks::Fetch;
use glam::DVec3;
use rayon::prelude::*;
use std::io::Read;

/// Triangles kept (world coordinates, f64), the count of those dropped (zero area or non-finite),
/// and the elements skipped because they are not faces, for one warning each. Indexed, each position
/// once: a grid's vertex is shared by six triangles, so a soup (72 bytes a triangle in f64) would
/// be three times the 24 bytes of positions and indices a 10 M-triangle load holds here.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    pub positions: Vec<DVec3>,
    /// The kept triangles, as indices into `positions`.
    pub indices: Vec<[u32; 3]>,
    pub dropped: usize,
    /// Elements with no surface (`p`, `l`, `curv`, `curv2`, `surf`): keyword, count, first line.
    pub skipped: Vec<(&'static str, usize, usize)>,
    /// Other things a load warns about, one sentence each.
    pub notes: Vec<String>,
    /// Alpha masks, per triangle (as `triangles`), if the file's materials have any.
    pub alpha: Option<super::alpha::Source>,
}

impl Mesh {
    /// A mesh of separate triangles (each its own three positions).
    pub fn from_soup(triangles: Vec<[DVec3; 3]>) -> Mesh {
        let indices = (0..triangles.len() as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        Mesh { positions: triangles.into_iter().flatten().collect(), indices, ..Mesh::default() }
    }

    /// The kept triangles' vertices, in order.
    pub fn triangles(&self) -> impl ExactSizeIterator<Item = [DVec3; 3]> + '_ {
        self.indices.iter().map(|t| t.map(|i| self.positions[i as usize]))
    }

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

/// A compressed file is decoded in batches of about this many bytes of text, each parsed (in parallel
/// parts) while the next is decoded: the text is never held whole (a 10 M-triangle OBJ is 0.4 GB of
/// it), and decoding overlaps parsing.
const BATCH_BYTES: usize = 8 * obj::PART_BYTES;

/// An OBJ file's mesh with its masks, and the bytes they came from (hashed with the scene: they
/// change its images). No masks, no bytes: a library that masks nothing changes no image.
pub struct ObjLoad {
    pub mesh: Mesh,
    pub external: Vec<Vec<u8>>,
}

/// Decodes `bytes` (plain OBJ text, or zstd-compressed OBJ) into triangles, geometry only: `mtllib`
/// is not followed, so no mask is applied (tools and tests that need none).
/// The error text says where (line) and what; the caller prefixes the file name.
pub fn parse_obj(bytes: &[u8]) -> Result<Mesh, String> {
    parse_obj_with(bytes, None).map(|l| l.mesh)
}

/// `parse_obj`, reading the material libraries (`mtllib`) and their `map_d` textures through `fetch`
/// (a path relative to the OBJ file, `/`-separated, to its bytes): materials with a `map_d` become
/// alpha masks (`scene::mtl`). A library that cannot be read is a note (its materials render solid);
/// a fault in a library, or a `map_d` texture that is missing or does not decode, is an error.
pub fn parse_obj_with(bytes: &[u8], fetch: Option<Fetch<'_>>) -> Result<ObjLoad, String> {
    let parsed = read(bytes, BATCH_BYTES)?;
    let mut mesh = Mesh { skipped: parsed.skipped.clone(), ..Mesh::default() };
    let masks = match fetch {
        // Its textures are decoded by the `image` crate: a panic there is one error (`guard`).
        Some(fetch) => {
            super::guard::contained("image", || super::obj_masks::masks(&parsed, fetch, &mut mesh.notes))?
        }
        None => None,
    };
    let mut source = masks.as_ref().map(|_| super::alpha::Source::default());
    let mut runs = parsed.material_runs.iter().peekable();
    let mut material = None;
    let at = |i: u32| parsed.positions[i as usize];
    let face =
        |f: usize| &parsed.corners[if f == 0 { 0 } else { parsed.face_ends[f - 1] }..parsed.face_ends[f]];
    // The test of every triangle (fan) in parallel: it reads the positions through the indices,
    // slow for a large mesh whose faces are not in the order of their vertices.
    let ok: Vec<bool> = (0..parsed.face_ends.len())
        .into_par_iter()
        .flat_map_iter(|f| {
            let face = face(f);
            (1..face.len() - 1).map(move |k| usable(&[face[0], face[k], face[k + 1]].map(at)))
        })
        .collect();
    let mut ok = ok.into_iter();
    let mut start = 0;
    for (f, &end) in parsed.face_ends.iter().enumerate() {
        while let Some(run) = runs.next_if(|r| r.first_face <= f) {
            material = Some(run.material as usize);
        }
        let face = &parsed.corners[start..end];
        for k in 1..face.len() - 1 {
            let idx = [face[0], face[k], face[k + 1]];
            if !ok.next().expect("one flag a triangle") {
                mesh.dropped += 1;
                continue;
            }
            mesh.indices.push(idx);
            if let (Some(m), Some(source)) = (&masks, source.as_mut()) {
                let corners = [start, start + k, start + k + 1];
                m.push(source, material, &parsed, corners);
            }
        }
        start = end;
    }
    let positions = parsed.positions;
    mesh.positions = positions;
    if mesh.indices.is_empty() {
        let skipped = mesh.skipped_description().map_or(String::new(), |s| format!("; skipped {s}"));
        return Err(if mesh.dropped == 1 {
            "empty mesh: its one triangle has zero area or non-finite vertices".into()
        } else if mesh.dropped > 0 {
            format!("empty mesh: all {} triangles have zero area or non-finite vertices", mesh.dropped)
        } else {
            format!("empty mesh: no faces (AO needs at least one triangle){skipped}")
        });
    }
    let mut external = Vec::new();
    if let (Some(m), Some(mut source)) = (masks, source)
        && source.any()
    {
        source.cutouts = m.cutouts;
        mesh.alpha = Some(source);
        external = m.bytes;
    }
    Ok(ObjLoad { mesh, external })
}

/// The OBJ text of `bytes` parsed: plain text in place (a copy would hold the file twice), zstd
/// decoded batch by batch (of about `batch` bytes), concatenated frames one after another. A stream that does
/// not decode is reported as such, whatever its text held before the fault.
fn read(bytes: &[u8], batch_bytes: usize) -> Result<obj::Parsed, String> {
    let mut reader = obj::Reader::default();
    if !bytes.starts_with(&ZSTD_MAGIC) {
        reader.feed_bytes(bytes);
        return reader.finish();
    }
    let mut frames = Frames { input: bytes, frame: None };
    let mut batch = Vec::new();
    let mut carry = Vec::new();
    loop {
        let (_, next) = rayon::join(
            || reader.feed_bytes(&batch),
            || frames.fill(std::mem::take(&mut carry), batch_bytes),
        );
        let (mut text, end) = next?;
        if end {
            reader.feed_bytes(&text);
            return reader.finish();
        }
        // Whole lines now; the last, unfinished one is carried into the next batch.
        let whole = text.iter().rposition(|&b| b == b'\n').map_or(0, |k| k + 1);
        carry = text.split_off(whole);
        batch = text;
    }
}

/// The decoded text of one or more concatenated zstd frames.
struct Frames<'a> {
    input: &'a [u8],
    frame: Option<ruzstd::decoding::StreamingDecoder<&'a [u8], ruzstd::decoding::FrameDecoder>>,
}

impl Frames<'_> {
    /// `buf` with decoded text appended until it holds `batch` bytes (or the last frame ended: true).
    fn fill(&mut self, mut buf: Vec<u8>, batch: usize) -> Result<(Vec<u8>, bool), String> {
        buf.reserve(batch.saturating_sub(buf.len()));
        // At least one read: `buf` may already hold a batch's worth of an unfinished line.
        let mut first = true;
        while first || buf.len() < batch {
            first = false;
            let frame = match &mut self.frame {
                Some(f) => f,
                None if self.input.is_empty() => return Ok((buf, true)),
                None => {
                    let f = ruzstd::decoding::StreamingDecoder::new(self.input)
                        .map_err(|e| format!("not a readable zstd stream: {e}"))?;
                    self.frame.insert(f)
                }
            };
            let old = buf.len();
            let want = batch.saturating_sub(old).clamp(1, 1 << 16);
            buf.resize(old + want, 0);
            let n = frame.read(&mut buf[old..]).map_err(|e| format!("zstd decoding failed: {e}"))?;
            buf.truncate(old + n);
            if n == 0 {
                // The frame ended: what follows it is the next frame, if anything.
                self.input = self.frame.take().expect("a frame").into_inner();
            }
        }
        Ok((buf, false))
    }
}

/// The bytes of a mesh file as text bytes: zstd-decoded if they start with zstd's magic number,
/// else unchanged.
pub fn decompress(bytes: &[u8]) -> Result<Vec<u8>, String> {
    if !bytes.starts_with(&ZSTD_MAGIC) {
        return Ok(bytes.to_vec());
    }
    let mut out = Vec::new();
    let mut frames = Frames { input: bytes, frame: None };
    loop {
        let (text, end) = frames.fill(out, BATCH_BYTES)?;
        out = text;
        if end {
            return Ok(out);
        }
    }
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
        assert_eq!((m.indices.len(), m.dropped), (2, 1));
    }

    /// A compressed file read in batches of any size (cut inside lines, inside frames) is the file
    /// read whole; concatenated frames are one file.
    #[test]
    fn zstd_streams_in_batches_and_frames_concatenate() {
        let zst = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/kitchen.obj.zst")).unwrap();
        let text = decompress(&zst).unwrap();
        let whole = read(&text, usize::MAX).unwrap();
        for batch in [4000, 70_000, 1 << 20] {
            let p = read(&zst, batch).unwrap();
            assert_eq!(
                (p.positions, p.corners, p.face_ends),
                (whole.positions.clone(), whole.corners.clone(), whole.face_ends.clone())
            );
            assert_eq!(
                (p.texcoords, p.corner_texcoords),
                (whole.texcoords.clone(), whole.corner_texcoords.clone())
            );
            assert_eq!(
                (p.materials, p.material_runs),
                (whole.materials.clone(), whole.material_runs.clone())
            );
        }
        let twice = decompress(&[&zst[..], &zst[..]].concat()).unwrap();
        assert_eq!(twice, [&text[..], &text[..]].concat());
        // A fault in a later batch keeps its line.
        let mut bad = text.clone();
        bad.extend(b"f 1 2\n");
        let lines = bad.iter().filter(|&&b| b == b'\n').count();
        let packed = ruzstd::encoding::compress_to_vec(&bad[..], ruzstd::encoding::CompressionLevel::Fastest);
        let e = read(&packed, 5000).err().unwrap();
        assert!(e.starts_with(&format!("line {lines}: a face with 2 vertices")), "{e}");
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

//! The statements of a Wavefront OBJ file that AO needs, read line by line so that every fault is
//! reported with its line: vertices (`v`) and faces (`f`), and for alpha masks (`map_d` in a
//! material library) texture coordinates (`vt`), a face's references to them, `mtllib` and `usemtl`.
//! Normals (`vn`) and a face's references to them are ignored (AO needs none), as are grouping
//! statements (`o`, `g`, `s`). Elements that are not faces (`p` points, `l` polylines, `curv`,
//! `curv2`, `surf` free-form geometry) have no surface to occlude with and are skipped and counted,
//! for one warning. A `#` starts a comment anywhere on a line.
//!
//! Faces are split into triangles as a fan from their first corner, (a, b, c), (a, c, d), …, in file
//! order: the triangles tobj (the loader used before) made, bit for bit, so stored images and
//! references stay valid.
//!
//! The text comes in batches of whole lines (`Reader::feed`), so a compressed file is parsed as it is
//! decoded and never held whole; each batch is cut into parts read in parallel. The one
//! thing a part cannot know is how many vertices the whole file has, which an out-of-range index's
//! message states and a forward reference (`f 9 …` before the ninth `v`) needs: such indices are
//! checked at the end (`Reader::finish`), and the first fault in file order is the one reported,
//! with the message a one-pass read of the whole file gives.

mod values;

use glam::DVec3;
use values::{texcoord, vertex};

/// A corner without a texture coordinate (`f 1 2 3`, `f 1//4 …`).
pub const NO_TEXCOORD: u32 = u32::MAX;

/// A file's geometry: positions, and faces as runs of 0-based position indices; the texture
/// coordinates and materials an alpha mask needs.
#[derive(Debug, Default)]
pub struct Parsed {
    pub positions: Vec<DVec3>,
    /// Every face's corners, one face after another.
    pub corners: Vec<u32>,
    /// Where each face's corners end in `corners`.
    pub face_ends: Vec<usize>,
    /// Elements skipped because they are not faces: keyword, count, first line, in order of first use.
    pub skipped: Vec<(&'static str, usize, usize)>,
    /// `vt u [v [w]]` as (u, v), as written (OBJ's v = 0 is the image's bottom row).
    pub texcoords: Vec<[f32; 2]>,
    /// Per corner (as `corners`) its 0-based texture coordinate or `NO_TEXCOORD`; empty if no face
    /// refers to one (no memory for a file without them).
    pub corner_texcoords: Vec<u32>,
    /// Material libraries named by `mtllib`, with their lines, in file order.
    pub libraries: Vec<(String, usize)>,
    /// Material names in order of first `usemtl`.
    pub materials: Vec<String>,
    /// One per `usemtl`: faces from there on use that material until the next; faces before the
    /// first use none.
    pub material_runs: Vec<Run>,
    /// The first line of a face without texture coordinates before this part's first `usemtl` (a
    /// part's faces continue the material of the part before).
    leading_untextured: Option<usize>,
}

/// The faces from `first_face` on use `material` (index into `Parsed::materials`), from `usemtl` on
/// `line`; `untextured`: the line of the first of them with a corner without texture coordinates
/// (which a masked material cannot have).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Run {
    pub first_face: usize,
    pub material: u32,
    pub line: usize,
    pub untextured: Option<usize>,
}

impl Parsed {
    /// The index of material `name` in `materials`, added if new (a part's `usemtl`, and a part's
    /// materials when it is merged into the file's).
    fn material(&mut self, name: &str) -> u32 {
        match self.materials.iter().position(|n| n == name) {
            Some(k) => k as u32,
            None => {
                self.materials.push(name.to_string());
                self.materials.len() as u32 - 1
            }
        }
    }
}

/// Elements with no surface; counted, not rendered.
const NOT_FACES: [&str; 5] = ["p", "l", "curv", "curv2", "surf"];

/// Batches are cut into parts of about this size, read in parallel (a 10 M-triangle OBJ is 0.4 GB of
/// text); smaller ones are one part.
pub const PART_BYTES: usize = 4 << 20;

/// Reads `text`, a whole file; the error says where (line) and what.
#[cfg(test)]
pub fn parse(text: &str) -> Result<Parsed, String> {
    let mut r = Reader::default();
    r.feed(text);
    r.finish()
}

/// An index not yet checked (it needs the file's total), or a fault found.
#[derive(Debug, Clone)]
enum Fault {
    /// The whole message.
    Text(String),
    /// An index out of range: `seen` vertices (or texture coordinates) came before its line.
    Index { line: usize, idx: i64, seen: i64, texture: bool },
}

/// A positive index beyond what its line has seen: valid iff the file has that many in all.
#[derive(Debug, Clone, Copy)]
struct Forward {
    line: usize,
    idx: i64,
    seen: i64,
    texture: bool,
}

/// Reads a file batch by batch (`feed`), then `finish`.
#[derive(Debug)]
pub struct Reader {
    parsed: Parsed,
    /// Lines, vertices and texture coordinates in the batches fed so far.
    lines: usize,
    vertices: usize,
    texcoords: usize,
    forward: Vec<Forward>,
    /// The first fault found; after it, batches are only counted.
    fault: Option<Fault>,
    /// The first bytes that are not UTF-8, as the message; after them nothing is read.
    not_text: Option<String>,
    part_bytes: usize,
}

impl Default for Reader {
    fn default() -> Self {
        Self::with_parts(PART_BYTES)
    }
}

/// What one part read: its faces and so on, and the fault that stopped it, if one did.
struct Part {
    parsed: Parsed,
    forward: Vec<Forward>,
    fault: Option<Fault>,
    /// Reused by `face`.
    scratch: Vec<u32>,
}

impl Reader {
    /// A reader cutting batches into parts of about `part_bytes` (tests cut small files into many).
    pub fn with_parts(part_bytes: usize) -> Self {
        Self {
            parsed: Parsed::default(),
            lines: 0,
            vertices: 0,
            texcoords: 0,
            forward: Vec::new(),
            fault: None,
            not_text: None,
            part_bytes: part_bytes.max(1),
        }
    }

    /// The next bytes of the file: whole lines (the batch ends after a line end, or is the file's
    /// end). Bytes that are not UTF-8 are a fault at their line that wins over any other (the file
    /// is not text: what its lines seemed to say does not matter), as when the whole file was
    /// checked before parsing.
    pub fn feed_bytes(&mut self, bytes: &[u8]) {
        if self.not_text.is_some() {
            return;
        }
        match std::str::from_utf8(bytes) {
            Ok(text) => self.feed(text),
            Err(e) => {
                let valid = &bytes[..e.valid_up_to()];
                let line = self.lines + 1 + valid.iter().filter(|&&b| b == b'\n').count();
                self.not_text = Some(format!("line {line}: not UTF-8 text (is this an OBJ file?)"));
            }
        }
    }

    /// The next whole lines of the file (as `feed_bytes`).
    pub fn feed(&mut self, text: &str) {
        use rayon::prelude::*;
        if self.fault.is_some() {
            return self.count(text);
        }
        let mut parts = Vec::new();
        let mut start = 0;
        while start < text.len() {
            let cut = start.saturating_add(self.part_bytes).min(text.len());
            let end =
                text.as_bytes()[cut..].iter().position(|&b| b == b'\n').map_or(text.len(), |k| cut + k + 1);
            parts.push(&text[start..end]);
            start = end;
        }
        // Lines, vertices and texture coordinates in each part; then where each part starts.
        let counts: Vec<[usize; 3]> = parts.par_iter().map(|t| counts(t)).collect();
        let mut firsts = Vec::with_capacity(parts.len());
        let mut at = [self.lines, self.vertices, self.texcoords];
        for c in &counts {
            firsts.push(at);
            at = [at[0] + c[0], at[1] + c[1], at[2] + c[2]];
        }
        [self.lines, self.vertices, self.texcoords] = at;
        let read: Vec<Part> = parts.par_iter().zip(&firsts).map(|(t, &f)| parse_part(t, f)).collect();
        for part in read {
            self.merge(part.parsed);
            self.forward.extend(part.forward);
            if part.fault.is_some() {
                self.fault = part.fault;
                break;
            }
        }
    }

    /// Counts the lines, vertices and texture coordinates of text after a fault (the message of an
    /// earlier out-of-range index states the file's total).
    fn count(&mut self, text: &str) {
        let c = counts(text);
        self.lines += c[0];
        self.vertices += c[1];
        self.texcoords += c[2];
    }

    /// Appends a part read after everything read so far.
    fn merge(&mut self, part: Parsed) {
        let p = &mut self.parsed;
        let (corners, faces) = (p.corners.len(), p.face_ends.len());
        // Kept for every corner once any corner has one (`NO_TEXCOORD` for the rest).
        if !part.corner_texcoords.is_empty() || !p.corner_texcoords.is_empty() {
            p.corner_texcoords.resize(corners, NO_TEXCOORD);
            if part.corner_texcoords.is_empty() {
                p.corner_texcoords.resize(corners + part.corners.len(), NO_TEXCOORD);
            } else {
                p.corner_texcoords.extend(part.corner_texcoords);
            }
        }
        p.positions.extend(part.positions);
        p.corners.extend(part.corners);
        p.face_ends.extend(part.face_ends.iter().map(|e| e + corners));
        p.texcoords.extend(part.texcoords);
        for (kind, n, line) in part.skipped {
            match p.skipped.iter_mut().find(|s| s.0 == kind) {
                Some(s) => s.1 += n,
                None => p.skipped.push((kind, n, line)),
            }
        }
        p.libraries.extend(part.libraries);
        match p.material_runs.last_mut() {
            Some(run) if run.untextured.is_none() => run.untextured = part.leading_untextured,
            None if p.leading_untextured.is_none() => p.leading_untextured = part.leading_untextured,
            _ => {}
        }
        for run in part.material_runs {
            let name = &part.materials[run.material as usize];
            let material = p.material(name);
            p.material_runs.push(Run { first_face: run.first_face + faces, material, ..run });
        }
    }

    /// The file read: every index checked against the file's totals, the first fault in file order.
    pub fn finish(self) -> Result<Parsed, String> {
        if let Some(e) = self.not_text {
            return Err(e);
        }
        let totals = [self.vertices as i64, self.texcoords as i64];
        let render = |f: Fault| match f {
            Fault::Text(s) => s,
            Fault::Index { line, idx, seen, texture } => {
                let (what, total) =
                    if texture { ("texture coordinates (`vt`)", totals[1]) } else { ("vertices", totals[0]) };
                let kind = if texture { "face texture index" } else { "face index" };
                format!(
                    "line {line}: {kind} {idx} out of range (the file has {total} {what}, {seen} before this \
                     line; indices start at 1)"
                )
            }
        };
        if let Some(f) = self.forward.iter().find(|f| f.idx > totals[f.texture as usize]) {
            let Forward { line, idx, seen, texture } = *f;
            return Err(render(Fault::Index { line, idx, seen, texture }));
        }
        match self.fault {
            Some(f) => Err(render(f)),
            None => Ok(self.parsed),
        }
    }
}

/// The statement's keyword: its first word outside a comment.
fn keyword(line: &str) -> Option<&str> {
    line.split('#').next().unwrap_or_default().split_whitespace().next()
}

/// Lines, `v` and `vt` statements in `text`.
fn counts(text: &str) -> [usize; 3] {
    let mut c = [0; 3];
    for line in text.lines() {
        c[0] += 1;
        match keyword(line) {
            Some("v") => c[1] += 1,
            Some("vt") => c[2] += 1,
            _ => {}
        }
    }
    c
}

/// One part of a file: its first line is line `first[0] + 1`, `first[1]` vertices and `first[2]`
/// texture coordinates come before it.
fn parse_part(text: &str, first: [usize; 3]) -> Part {
    let mut part = Part { parsed: Parsed::default(), forward: Vec::new(), fault: None, scratch: Vec::new() };
    for (no, line) in text.lines().enumerate() {
        let line_no = first[0] + no + 1;
        if let Err(f) = statement(&mut part, line, line_no, first) {
            part.fault = Some(f);
            break;
        }
    }
    part
}

/// One line.
fn statement(part: &mut Part, line: &str, line_no: usize, first: [usize; 3]) -> Result<(), Fault> {
    let content = line.split('#').next().unwrap_or_default();
    let mut words = content.split_whitespace();
    let p = &mut part.parsed;
    match words.next() {
        Some("v") => p.positions.push(vertex(line, words, line_no).map_err(Fault::Text)?),
        Some("vt") => p.texcoords.push(texcoord(line, words, line_no).map_err(Fault::Text)?),
        Some("f") => face(part, line, words, line_no, first)?,
        Some("mtllib") => {
            let names: Vec<&str> = words.collect();
            if names.is_empty() {
                return Err(Fault::Text(format!("line {line_no}: `mtllib` needs a file name")));
            }
            p.libraries.extend(names.into_iter().map(|n| (n.to_string(), line_no)));
        }
        Some("usemtl") => {
            // A name may contain spaces (some exporters write them): the rest of the line.
            let name = content.trim_start().strip_prefix("usemtl").unwrap_or_default().trim();
            if name.is_empty() {
                return Err(Fault::Text(format!("line {line_no}: `usemtl` needs a material name")));
            }
            let material = p.material(name);
            p.material_runs.push(Run {
                first_face: p.face_ends.len(),
                material,
                line: line_no,
                untextured: None,
            });
        }
        Some(k) => {
            if let Some(&kind) = NOT_FACES.iter().find(|&&n| n == k) {
                match p.skipped.iter_mut().find(|s| s.0 == kind) {
                    Some(s) => s.1 += 1,
                    None => p.skipped.push((kind, 1, line_no)),
                }
            }
        }
        None => {}
    }
    Ok(())
}

/// Index `idx` of a face's corner (1-based, or negative: back from the last before the line) with
/// `seen` before the line, as a 0-based index; a positive one beyond `seen` is kept to be checked
/// against the file's total at the end.
fn resolve(part: &mut Part, idx: i64, seen: i64, line: usize, texture: bool) -> Result<u32, Fault> {
    let at = if idx > 0 { idx - 1 } else { seen + idx };
    if idx == 0 || at < 0 || at >= u32::MAX as i64 {
        return Err(Fault::Index { line, idx, seen, texture });
    }
    if idx > seen {
        part.forward.push(Forward { line, idx, seen, texture });
    }
    Ok(at as u32)
}

/// `f v1 v2 v3 …`, each corner `v`, `v/vt`, `v//vn` or `v/vt/vn`; indices count from 1, negative
/// ones back from the last vertex before the line.
fn face<'a>(
    part: &mut Part,
    line: &str,
    words: impl Iterator<Item = &'a str>,
    line_no: usize,
    first: [usize; 3],
) -> Result<(), Fault> {
    let start = part.parsed.corners.len();
    let seen = (first[1] + part.parsed.positions.len()) as i64;
    let seen_vt = (first[2] + part.parsed.texcoords.len()) as i64;
    // The corners' texture coordinates, in a buffer the part reuses (no allocation per face).
    let mut vts = std::mem::take(&mut part.scratch);
    vts.clear();
    for c in words {
        let mut fields = c.split('/');
        let v = fields.next().unwrap_or_default();
        let vt = fields.next().unwrap_or_default();
        let vn = fields.next().unwrap_or_default();
        let not_index = || Fault::Text(format!("line {line_no}: face vertex '{c}' is not an index"));
        if fields.next().is_some() || !(vn.is_empty() || vn.parse::<i64>().is_ok()) {
            return Err(not_index());
        }
        let idx: i64 = v.parse().map_err(|_| not_index())?;
        let t = if vt.is_empty() { None } else { Some(vt.parse::<i64>().map_err(|_| not_index())?) };
        let at = resolve(part, idx, seen, line_no, false)?;
        part.parsed.corners.push(at);
        vts.push(match t {
            Some(t) => resolve(part, t, seen_vt, line_no, true)?,
            None => NO_TEXCOORD,
        });
    }
    let p = &mut part.parsed;
    let n = p.corners.len() - start;
    if n < 3 {
        return Err(Fault::Text(format!(
            "line {line_no}: a face with {n} vertices cannot be triangulated (need at least 3): '{}'",
            line.trim()
        )));
    }
    if vts.contains(&NO_TEXCOORD) {
        let first = match p.material_runs.last_mut() {
            Some(run) => &mut run.untextured,
            None => &mut p.leading_untextured,
        };
        first.get_or_insert(line_no);
    }
    if vts.iter().any(|&t| t != NO_TEXCOORD) || !p.corner_texcoords.is_empty() {
        p.corner_texcoords.resize(start, NO_TEXCOORD);
        p.corner_texcoords.extend_from_slice(&vts);
    }
    p.face_ends.push(p.corners.len());
    part.scratch = vts;
    Ok(())
}

#[cfg(test)]
mod tests;

//! The statements of a Wavefront OBJ file that AO needs, read line by line so that every fault is
//! reported with its line: vertices (`v`) and faces (`f`). Texture coordinates and normals (`vt`,
//! `vn`) and a face's references to them are ignored (AO needs neither), as are grouping and
//! material statements (`o`, `g`, `s`, `mtllib`, `usemtl`: no .mtl file is ever opened). Elements
//! that are not faces (`p` points, `l` polylines, `curv`, `curv2`, `surf` free-form geometry) have
//! no surface to occlude with and are skipped and counted, for one warning. A `#` starts a comment
//! anywhere on a line.
//!
//! Faces are split into triangles as a fan from their first corner, (a, b, c), (a, c, d), …, in file
//! order: the triangles tobj (the loader used before) made, bit for bit, so stored images and
//! references stay valid.

use super::MAX_COORDINATE;
use glam::DVec3;

/// A file's geometry: positions, and faces as runs of 0-based position indices.
#[derive(Debug, Default)]
pub struct Parsed {
    pub positions: Vec<DVec3>,
    /// Every face's corners, one face after another.
    pub corners: Vec<u32>,
    /// Where each face's corners end in `corners`.
    pub face_ends: Vec<usize>,
    /// Elements skipped because they are not faces: keyword, count, first line, in order of first use.
    pub skipped: Vec<(&'static str, usize, usize)>,
    /// Vertices in the file before this part of it (`parse` reads large files in parts).
    first_vertex: usize,
}

/// Elements with no surface; counted, not rendered.
const NOT_FACES: [&str; 5] = ["p", "l", "curv", "curv2", "surf"];

/// Files larger than this are read in parts of about this size, in parallel (issue 29: a 10 M-triangle
/// OBJ is 0.4 GB of text); smaller ones in one part.
const PART_BYTES: usize = 4 << 20;

/// Reads `text`; the error says where (line) and what. A large file is cut at line ends into parts
/// read in parallel: a first pass counts each part's lines and vertices, so that every part knows
/// its first line number and the vertices before it (relative indices count back from there,
/// positive ones are checked against the file's total), and the first fault in file order is the
/// one reported, with the message reading the whole file in one part would give.
pub fn parse(text: &str) -> Result<Parsed, String> {
    parse_in_parts(text, PART_BYTES)
}

/// `parse` with parts of about `part_bytes` (tests cut small files into many).
fn parse_in_parts(text: &str, part_bytes: usize) -> Result<Parsed, String> {
    use rayon::prelude::*;
    let mut parts = Vec::new();
    let mut start = 0;
    while start < text.len() {
        let cut = start.saturating_add(part_bytes).min(text.len());
        let end = text.as_bytes()[cut..].iter().position(|&b| b == b'\n').map_or(text.len(), |k| cut + k + 1);
        parts.push(&text[start..end]);
        start = end;
    }
    // Lines and vertices in each part; then where each part starts, in both.
    let counts: Vec<(usize, usize)> =
        parts.par_iter().map(|t| (t.lines().count(), t.lines().filter(|l| is_vertex(l)).count())).collect();
    let total = counts.iter().map(|c| c.1).sum();
    let mut firsts = Vec::with_capacity(parts.len());
    let (mut line, mut vertex) = (0, 0);
    for &(lines, vertices) in &counts {
        firsts.push((line, vertex));
        (line, vertex) = (line + lines, vertex + vertices);
    }
    let read: Vec<Result<Parsed, String>> =
        parts.par_iter().zip(&firsts).map(|(t, &(l, v))| parse_part(t, l, v, total)).collect();
    let mut p = Parsed { positions: Vec::with_capacity(total), ..Parsed::default() };
    for part in read {
        let part = part?;
        let offset = p.corners.len();
        p.positions.extend(part.positions);
        p.corners.extend(part.corners);
        p.face_ends.extend(part.face_ends.iter().map(|e| e + offset));
        for (kind, n, line) in part.skipped {
            match p.skipped.iter_mut().find(|s| s.0 == kind) {
                Some(s) => s.1 += n,
                None => p.skipped.push((kind, n, line)),
            }
        }
    }
    Ok(p)
}

/// A `v` statement.
fn is_vertex(line: &str) -> bool {
    line.split_whitespace().next() == Some("v")
}

/// One part of a file: its first line is line `first_line + 1`, `first_vertex` vertices come before
/// it, and the file has `total`.
fn parse_part(text: &str, first_line: usize, first_vertex: usize, total: usize) -> Result<Parsed, String> {
    let mut p = Parsed { first_vertex, ..Parsed::default() };
    for (no, line) in text.lines().enumerate() {
        let line_no = first_line + no + 1;
        let content = line.split('#').next().unwrap_or_default();
        let mut words = content.split_whitespace();
        match words.next() {
            Some("v") => p.positions.push(vertex(line, words, line_no)?),
            Some("f") => face(&mut p, line, words, line_no, total)?,
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
    }
    Ok(p)
}

/// `v x y z`, optionally followed by `w` (the point is (x, y, z) / w) or by a colour `r g b`.
fn vertex<'a>(line: &str, mut words: impl Iterator<Item = &'a str>, line_no: usize) -> Result<DVec3, String> {
    let three = |w: &mut dyn Iterator<Item = &'a str>| -> Option<[&'a str; 3]> {
        Some([w.next()?, w.next()?, w.next()?])
    };
    let bad = || format!("line {line_no}: a vertex needs three numbers, found '{}'", line.trim());
    let xyz = three(&mut words).ok_or_else(bad)?;
    let mut c = [0.0f64; 3];
    for (slot, s) in c.iter_mut().zip(xyz) {
        *slot = s.parse().map_err(|_| bad())?;
        coordinate_ok(*slot, s, line_no)?;
    }
    let rest: Vec<&str> = words.collect();
    let numbers = |what: &str| -> Result<Vec<f64>, String> {
        rest.iter()
            .map(|s| {
                s.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| format!("line {line_no}: vertex {what} '{s}' is not a finite number"))
            })
            .collect()
    };
    match rest.len() {
        0 => {}
        1 => {
            let w = numbers("weight w")?[0];
            if w == 0.0 {
                return Err(format!("line {line_no}: vertex weight w is 0 (the point is (x, y, z) / w)"));
            }
            for (x, s) in c.iter_mut().zip(xyz) {
                *x /= w;
                coordinate_ok(*x, &format!("{s} / {}", rest[0]), line_no)?;
            }
        }
        3 => {
            numbers("colour")?;
        }
        n => {
            return Err(format!(
                "line {line_no}: a vertex is `v x y z`, optionally followed by w or by r g b; found {n} more \
                 values in '{}'",
                line.trim()
            ));
        }
    }
    Ok(DVec3::from_array(c))
}

/// A coordinate must be finite and within ±`MAX_COORDINATE`.
fn coordinate_ok(x: f64, written: &str, line_no: usize) -> Result<(), String> {
    if !x.is_finite() {
        return Err(format!("line {line_no}: vertex coordinate '{written}' is not a finite number"));
    }
    if x.abs() > MAX_COORDINATE {
        return Err(format!(
            "line {line_no}: vertex coordinate {written} is beyond ±{MAX_COORDINATE:e}, the largest hemilab \
             accepts (it renders in f32 relative to the camera, and beyond that a triangle's edge products \
             overflow); scale the mesh down"
        ));
    }
    Ok(())
}

/// `f v1 v2 v3 …`, each corner `v`, `v/vt`, `v//vn` or `v/vt/vn`; indices count from 1, negative
/// ones back from the last vertex before the line.
fn face<'a>(
    p: &mut Parsed,
    line: &str,
    words: impl Iterator<Item = &'a str>,
    line_no: usize,
    total: usize,
) -> Result<(), String> {
    let start = p.corners.len();
    let seen = (p.first_vertex + p.positions.len()) as i64;
    for c in words {
        let mut parts = c.split('/');
        let first = parts.next().unwrap_or_default();
        let rest_ok = parts.clone().count() <= 2 && parts.all(|s| s.is_empty() || s.parse::<i64>().is_ok());
        let idx: i64 = match first.parse() {
            Ok(i) if rest_ok => i,
            _ => return Err(format!("line {line_no}: face vertex '{c}' is not an index")),
        };
        let at = if idx > 0 { idx - 1 } else { seen + idx };
        if idx == 0 || at < 0 || at >= total as i64 {
            return Err(format!(
                "line {line_no}: face index {idx} out of range (the file has {total} vertices, {seen} before \
                 this line; indices start at 1)"
            ));
        }
        p.corners.push(at as u32);
    }
    let n = p.corners.len() - start;
    if n < 3 {
        return Err(format!(
            "line {line_no}: a face with {n} vertices cannot be triangulated (need at least 3): '{}'",
            line.trim()
        ));
    }
    p.face_ends.push(p.corners.len());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comments_weights_colours_and_skipped_elements() {
        let text = "v 0 0 0 # origin\nv 2 0 0 2\nv 0 1 0 0.5 0.5 0.5\nl 1 2 3\np 1\nl 2 3\nf 1 2 3\n";
        let p = parse(text).unwrap();
        assert_eq!(p.positions[1], DVec3::new(1.0, 0.0, 0.0), "w divides");
        assert_eq!((p.corners.len(), p.face_ends.len()), (3, 1));
        assert_eq!(p.skipped, vec![("l", 2, 4), ("p", 1, 5)]);
    }

    #[test]
    fn parts_read_as_one_file() {
        let mut text = String::from("# a grid with relative indices\r\n");
        for i in 0..40 {
            text += &format!("v {i} 0 0\nv {i} 1 0\n");
            if i > 0 {
                text += "f -4 -3 -1 -2\n";
            }
            if i % 7 == 0 {
                text += &format!("l {} {}\np 1\n", 2 * i + 1, 2 * i + 2);
            }
        }
        text += "f 1 2 3"; // no line end
        let whole = parse_in_parts(&text, usize::MAX).unwrap();
        for part_bytes in [1, 5, 17, 64] {
            let p = parse_in_parts(&text, part_bytes).unwrap();
            assert_eq!(p.positions, whole.positions);
            assert_eq!(
                (&p.corners, &p.face_ends, &p.skipped),
                (&whole.corners, &whole.face_ends, &whole.skipped)
            );
        }
        // A fault's line and vertex counts are the whole file's, whichever part it is in.
        for bad in ["f 1 2 999", "f -100 1 2", "v 1 x 2", "f 1 2"] {
            let lines: Vec<&str> = text.lines().collect();
            for at in [3, 50, lines.len() - 1] {
                let mut l = lines.clone();
                l.insert(at, bad);
                let t = l.join("\n");
                let want = parse_in_parts(&t, usize::MAX).err().unwrap();
                assert!(want.starts_with(&format!("line {}:", at + 1)), "{want}");
                for part_bytes in [1, 9, 100] {
                    assert_eq!(parse_in_parts(&t, part_bytes).err().unwrap(), want);
                }
            }
        }
    }

    #[test]
    fn faults_name_their_line() {
        for (text, want) in [
            ("v 0 0 0\nv 1e30 0 0\n", "line 2: vertex coordinate 1e30 is beyond ±1e18"),
            ("v 0 0 inf\n", "line 1: vertex coordinate 'inf' is not a finite number"),
            ("v 0 0 1e999\n", "line 1: vertex coordinate '1e999' is not a finite number"),
            ("v 0 0 nan\n", "line 1: vertex coordinate 'nan' is not a finite number"),
            ("v 1 1 1 0\n", "line 1: vertex weight w is 0"),
            ("v 1 1 1 1e-300\n", "line 1: vertex coordinate 1 / 1e-300 is beyond"),
            ("v 1 1 1 1 1\n", "line 1: a vertex is `v x y z`"),
            ("v 1 1 1 a b c\n", "line 1: vertex colour 'a'"),
            ("v 0 0 0\nf 1 1/x 1\n", "line 2: face vertex '1/x' is not an index"),
            ("v 0 0 0\nf 1 1/2/3/4 1\n", "line 2: face vertex '1/2/3/4' is not an index"),
            ("v 0 0 0\nf 1 1 -2\n", "line 2: face index -2 out of range"),
        ] {
            let e = parse(text).err().unwrap_or_default();
            assert!(e.starts_with(want), "{text:?}: want '{want}', got '{e}'");
        }
    }
}

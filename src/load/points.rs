//! Reading a point set the user names into a sequence (`sampling::point_file`).
//!
//! - `.npy` (NumPy's format, versions 1–3): float64 or float32, either byte order, C or Fortran
//!   order, of shape N × 2 (one set) or P × N × 2 (P sets: pixel p reads set p mod P).
//! - Any other extension is text as UTK writes it: one point `x y` per line (spaces, tabs or a
//!   comma between), `#` comments; a blank or `#` line after points ends a set, so a file may hold
//!   several sets, all of the same size.
//!
//! Every point must lie in [0, 1)²: one outside is an error naming its line (its index in an
//! `.npy`). The sequence's name is `points:PATH#hash8` (PATH as written, hash8 the file's content
//! hash), so an edited file never resumes the old one's results.

use crate::io;
use crate::sampling::point_file::PointFile;
use crate::sampling::seed::FIX_ONE;
use crate::sampling::{Sequence, register_file};
use std::path::Path;

/// Loads the point set `written` (relative to `base`), registers it and returns its sequence.
pub fn points(base: &Path, written: &str) -> Result<Sequence, String> {
    let file = base.join(written);
    let shown = file.display();
    if !io::exists(&file) {
        let at = std::path::absolute(&file).unwrap_or_else(|_| file.clone());
        return Err(format!("point file '{written}' not found (looked for {})", at.display()));
    }
    let bytes = io::read_bytes(&file).map_err(|e| e.to_string())?;
    let npy = file.extension().is_some_and(|e| e.eq_ignore_ascii_case("npy"));
    let (sets, per_set, xy) = if npy {
        npy_points(&bytes).map_err(|e| format!("point file {shown}: {e}"))?
    } else {
        text_points(&bytes).map_err(|e| format!("point file {shown}: {e}"))?
    };
    if per_set == 0 || sets == 0 {
        return Err(format!("point file {shown} holds no points"));
    }
    let _ = sets;
    let fixed: Vec<(u32, u32)> =
        xy.iter().map(|&(x, y)| ((x * FIX_ONE as f64) as u32, (y * FIX_ONE as f64) as u32)).collect();
    let hash8 = crate::scene::content_hash(&[&bytes])[..8].to_string();
    let name = format!("points:{written}#{hash8}");
    let label = format!("points {written}");
    let seq = PointFile::new(&name, &label, fixed, per_set as u32);
    register_file(Box::new(seq)).map_err(|e| format!("point file {shown}: {e}"))
}

/// What a file holds: (sets, points per set, the points set after set).
type Read = (usize, usize, Vec<(f64, f64)>);

/// Whether a coordinate is in [0, 1).
fn unit(v: f64) -> bool {
    (0.0..1.0).contains(&v)
}

/// (sets, points per set, points) of a text file; errors name the line.
fn text_points(bytes: &[u8]) -> Result<Read, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "is neither an .npy nor UTF-8 text".to_string())?;
    let mut all = Vec::new();
    let mut sizes: Vec<(usize, usize)> = Vec::new(); // (points, first line)
    let mut current = 0usize;
    let mut first_line = 0usize;
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let t = line.trim();
        if t.is_empty() || t.starts_with('#') {
            if current > 0 {
                sizes.push((current, first_line));
                current = 0;
            }
            continue;
        }
        let nums: Vec<&str> =
            t.split(|c: char| c.is_whitespace() || c == ',').filter(|s| !s.is_empty()).collect();
        let parsed: Vec<Option<f64>> = nums.iter().map(|s| s.parse::<f64>().ok()).collect();
        let (x, y) = match parsed[..] {
            [Some(x), Some(y)] => (x, y),
            _ => {
                return Err(format!(
                    "line {n}: '{}' is not a point `x y` (two numbers per line)",
                    t.chars().take(60).collect::<String>()
                ));
            }
        };
        if !unit(x) || !unit(y) {
            return Err(format!("line {n}: point ({x}, {y}) is outside [0, 1)²"));
        }
        if current == 0 {
            first_line = n;
        }
        current += 1;
        all.push((x, y));
    }
    if current > 0 {
        sizes.push((current, first_line));
    }
    let Some(&(per_set, _)) = sizes.first() else { return Err("holds no points".into()) };
    if let Some((k, &(m, line))) = sizes.iter().enumerate().find(|(_, s)| s.0 != per_set) {
        return Err(format!(
            "line {line}: set {} has {m} points, set 1 has {per_set}; every set of a file must have as many",
            k + 1
        ));
    }
    Ok((sizes.len(), per_set, all))
}

/// (sets, points per set, points) of an `.npy`; errors name the point's index.
fn npy_points(bytes: &[u8]) -> Result<Read, String> {
    if bytes.len() < 10 || &bytes[..6] != b"\x93NUMPY" {
        return Err("is not an .npy file (no \\x93NUMPY magic)".into());
    }
    let (len, start) = match bytes[6] {
        1 => (u16::from_le_bytes([bytes[8], bytes[9]]) as usize, 10),
        2 | 3 if bytes.len() >= 12 => {
            (u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize, 12)
        }
        v => return Err(format!("has .npy version {v}; readable: 1, 2, 3")),
    };
    let header = bytes.get(start..start + len).ok_or("its .npy header is cut short")?;
    let header = std::str::from_utf8(header).map_err(|_| "its .npy header is not text")?;
    let field = |key: &str| -> Option<&str> {
        let at = header.find(&format!("'{key}'"))? + key.len() + 2;
        let rest = header[at..].trim_start().strip_prefix(':')?.trim_start();
        Some(rest)
    };
    let descr = field("descr").and_then(|r| r.strip_prefix('\'')).and_then(|r| r.split('\'').next());
    let (size, little) = match descr {
        Some("<f8") | Some("=f8") => (8, true),
        Some(">f8") => (8, false),
        Some("<f4") | Some("=f4") => (4, true),
        Some(">f4") => (4, false),
        other => {
            return Err(format!(
                "has dtype {}; readable: float64, float32",
                other.unwrap_or("?").escape_debug()
            ));
        }
    };
    let fortran = field("fortran_order").is_some_and(|r| r.starts_with("True"));
    let dims = field("shape")
        .and_then(|r| r.strip_prefix('('))
        .and_then(|r| r.split(')').next())
        .ok_or("its .npy header has no shape")?;
    let shape: Vec<usize> = dims
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            // Shown on one line, as the header holds it (escaped), however it is broken.
            let shown = |t: &str| t.chars().take(60).collect::<String>().escape_debug().to_string();
            s.parse().map_err(|_| format!("its .npy shape ({}) has '{}', not a size", shown(dims), shown(s)))
        })
        .collect::<Result<_, _>>()?;
    let (sets, per_set) = match shape[..] {
        [n, 2] => (1, n),
        [p, n, 2] => (p, n),
        _ => return Err(format!("has shape {shape:?}; a point set is N × 2 or P × N × 2")),
    };
    let data = &bytes[start + len..];
    // The header's promise checked against the bytes before anything is allocated: a shape whose
    // size overflows (2^62 × 2 points) is simply more than the file holds.
    let needed = sets.checked_mul(per_set).and_then(|n| n.checked_mul(2 * size));
    if needed.is_none_or(|b| b > data.len()) {
        let needs = needed.map_or("more than 2^64".to_string(), |b| b.to_string());
        return Err(format!("holds {} bytes of data, its shape {shape:?} needs {needs}", data.len()));
    }
    let read = |k: usize| -> f64 {
        let b = &data[k * size..(k + 1) * size];
        match (size, little) {
            (8, true) => f64::from_le_bytes(b.try_into().unwrap_or([0; 8])),
            (8, false) => f64::from_be_bytes(b.try_into().unwrap_or([0; 8])),
            (_, true) => f32::from_le_bytes(b.try_into().unwrap_or([0; 4])) as f64,
            (_, false) => f32::from_be_bytes(b.try_into().unwrap_or([0; 4])) as f64,
        }
    };
    // Element (p, i, c) of a P × N × 2 array, C or Fortran order.
    let at = |p: usize, i: usize, c: usize| {
        if fortran { c * sets * per_set + i * sets + p } else { (p * per_set + i) * 2 + c }
    };
    let mut out = Vec::with_capacity(sets * per_set);
    for p in 0..sets {
        for i in 0..per_set {
            let (x, y) = (read(at(p, i, 0)), read(at(p, i, 1)));
            if !unit(x) || !unit(y) {
                let which = if sets == 1 { format!("point {i}") } else { format!("set {p}, point {i}") };
                return Err(format!("{which} (0-based): ({x}, {y}) is outside [0, 1)²"));
            }
            out.push((x, y));
        }
    }
    Ok((sets, per_set, out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_sets_split_at_blank_or_hash_lines_and_must_match() {
        let (sets, n, p) = text_points(b"# utk\n0.1 0.2\n0.3\t0.4\n#\n0.5,0.6\n0.7 0.8\n").unwrap();
        assert_eq!((sets, n, p.len()), (2, 2, 4));
        let e = text_points(b"0.1 0.2\n\n0.3 0.4\n0.5 0.6\n").unwrap_err();
        assert!(e.starts_with("line 3: set 2 has 2 points, set 1 has 1"), "{e}");
        let e = text_points(b"0.1 0.2\n0.3 1.0\n").unwrap_err();
        assert!(e.starts_with("line 2: point (0.3, 1)"), "{e}");
    }
}

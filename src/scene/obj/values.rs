//! The numbers of one OBJ statement: a vertex (`v`) and a texture coordinate (`vt`), each fault a
//! message with its line.

use super::super::MAX_COORDINATE;
use glam::DVec3;

/// `v x y z`, optionally followed by `w` (the point is (x, y, z) / w) or by a colour `r g b`.
pub(super) fn vertex<'a>(
    line: &str,
    mut words: impl Iterator<Item = &'a str>,
    line_no: usize,
) -> Result<DVec3, String> {
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

/// `vt u [v [w]]` (v defaults to 0; w, for 3D textures, is not used).
pub(super) fn texcoord<'a>(
    line: &str,
    words: impl Iterator<Item = &'a str>,
    line_no: usize,
) -> Result<[f32; 2], String> {
    let values: Vec<&str> = words.collect();
    let bad = || {
        format!(
            "line {line_no}: a texture coordinate is `vt u [v [w]]` with finite numbers, found '{}'",
            line.trim()
        )
    };
    if values.is_empty() || values.len() > 3 {
        return Err(bad());
    }
    let mut uv = [0.0f32; 2];
    for (k, s) in values.iter().enumerate() {
        let x: f64 = s.parse().ok().filter(|x: &f64| x.is_finite()).ok_or_else(bad)?;
        if k < 2 {
            uv[k] = x as f32;
        }
    }
    Ok(uv)
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

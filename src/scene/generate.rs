//! The procedural scenes of `scenes/`, written as OBJ text: an arcaded atrium (columns, arches, deep
//! crevices), thin parallel slats over a floor (the geometry that makes a static seed's error into
//! moiré), and open terrain under the sky. Each is chosen for what AO is sensitive to (see
//! scenes/README.md). Pure: `examples/write_scenes.rs` writes the files; the committed `.obj.zst`
//! are checked against this code by `tests/stages/scene_files.rs`, so the meshes stay reproducible.
//!
//! Coordinates are printed with 4 decimals (0.1 mm in these metre-scale scenes): enough for AO,
//! small when compressed, and the same text on every machine.

use std::f64::consts::PI;
use std::fmt::Write as _;

type P = [f64; 3];

/// Collects vertices and polygons and prints them as OBJ.
#[derive(Default)]
pub struct ObjWriter {
    text: String,
    vertices: usize,
    faces: usize,
}

impl ObjWriter {
    pub fn new(header: &str) -> Self {
        let mut w = ObjWriter::default();
        for line in header.lines() {
            let _ = writeln!(w.text, "# {line}");
        }
        w
    }

    /// Adds a vertex and returns its 1-based OBJ index.
    fn v(&mut self, p: P) -> usize {
        let c = |x: f64| {
            // -0.0000 and 0.0000 are the same point; print one of them.
            let s = format!("{x:.4}");
            if s == "-0.0000" { "0.0000".to_string() } else { s }
        };
        let _ = writeln!(self.text, "v {} {} {}", c(p[0]), c(p[1]), c(p[2]));
        self.vertices += 1;
        self.vertices
    }

    /// A planar convex polygon through new vertices; corners that coincide (an arch's springing
    /// point is on both the arc and the wall's edge) are merged, and a polygon left with fewer than
    /// three corners is skipped.
    fn poly(&mut self, ps: &[P]) {
        let same = |p: &P, q: &P| (0..3).all(|k| (p[k] - q[k]).abs() < 1e-6);
        let mut kept: Vec<P> = Vec::with_capacity(ps.len());
        for &p in ps {
            if !kept.last().is_some_and(|q| same(&p, q)) {
                kept.push(p);
            }
        }
        if kept.len() > 1 && same(&kept[0], &kept[kept.len() - 1]) {
            kept.pop();
        }
        if kept.len() < 3 {
            return;
        }
        let idx: Vec<usize> = kept.iter().map(|&p| self.v(p)).collect();
        self.face(&idx);
    }

    fn face(&mut self, idx: &[usize]) {
        let list: Vec<String> = idx.iter().map(|i| i.to_string()).collect();
        let _ = writeln!(self.text, "f {}", list.join(" "));
        self.faces += 1;
    }

    /// An axis-aligned box from `lo` to `hi`: six quads (the bottom too, so it may float).
    fn cuboid(&mut self, lo: P, hi: P) {
        let c = |i: usize| {
            [
                if i & 1 == 0 { lo[0] } else { hi[0] },
                if i & 2 == 0 { lo[1] } else { hi[1] },
                if i & 4 == 0 { lo[2] } else { hi[2] },
            ]
        };
        let v: Vec<usize> = (0..8).map(|i| self.v(c(i))).collect();
        for f in [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]] {
            self.face(&[v[f[0]], v[f[1]], v[f[2]], v[f[3]]]);
        }
    }

    /// A vertical cylinder (axis along y) of `segments` sides, with its top cap.
    fn cylinder(&mut self, x: f64, z: f64, r: f64, y0: f64, y1: f64, segments: usize) {
        let ring = |w: &mut ObjWriter, y: f64| -> Vec<usize> {
            (0..segments)
                .map(|k| {
                    let a = 2.0 * PI * k as f64 / segments as f64;
                    w.v([x + r * a.cos(), y, z + r * a.sin()])
                })
                .collect()
        };
        let (lo, hi) = (ring(self, y0), ring(self, y1));
        for k in 0..segments {
            let k1 = (k + 1) % segments;
            self.face(&[lo[k], lo[k1], hi[k1], hi[k]]);
        }
        self.face(&hi);
    }

    pub fn finish(self) -> String {
        self.text
    }

    pub fn counts(&self) -> (usize, usize) {
        (self.vertices, self.faces)
    }
}

/// A wall of thickness `t` in the plane z = `zc` (or x = `zc` when `along_z`), spanning `a0..a1`
/// horizontally and `y0..y1` vertically, with a semicircular arch opening of the full width springing
/// at `y0` (so the wall stands on two columns at `a0` and `a1`). The opening's curved underside (the
/// intrados) is modelled, so the arch casts AO into itself.
#[allow(clippy::too_many_arguments)]
fn arch_bay(
    w: &mut ObjWriter,
    along_z: bool,
    zc: f64,
    t: f64,
    a0: f64,
    a1: f64,
    y0: f64,
    y1: f64,
    seg: usize,
) {
    let place = |a: f64, y: f64, z: f64| if along_z { [z, y, a] } else { [a, y, z] };
    let (c, r) = (0.5 * (a0 + a1), 0.5 * (a1 - a0));
    // Angles from π (left springing) to 0 (right), plus the angles of the two top corners, so every
    // quad between consecutive angles has its outer points on one edge of the rectangle.
    let corner = (y1 - y0).atan2(r);
    let mut angles: Vec<f64> = (0..=seg).map(|k| PI * (1.0 - k as f64 / seg as f64)).collect();
    angles.extend([corner, PI - corner]);
    angles.sort_by(|a, b| b.total_cmp(a));
    angles.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let arc = |a: f64| (c + r * a.cos(), y0 + r * a.sin());
    let outer = |a: f64| {
        // Where the ray from the arch centre at angle a meets the rectangle [a0, a1] x [y0, y1].
        let (dx, dy) = (a.cos(), a.sin());
        let tx = if dx.abs() < 1e-12 { f64::INFINITY } else { r / dx.abs() };
        let ty = if dy.abs() < 1e-12 { f64::INFINITY } else { (y1 - y0) / dy };
        let s = tx.min(ty);
        (c + s * dx, y0 + s * dy)
    };
    for side in [-0.5 * t, 0.5 * t] {
        for k in 0..angles.len() - 1 {
            let (p0, p1) = (arc(angles[k]), arc(angles[k + 1]));
            let (q0, q1) = (outer(angles[k]), outer(angles[k + 1]));
            w.poly(&[
                place(p0.0, p0.1, zc + side),
                place(p1.0, p1.1, zc + side),
                place(q1.0, q1.1, zc + side),
                place(q0.0, q0.1, zc + side),
            ]);
        }
    }
    for k in 0..angles.len() - 1 {
        let (p0, p1) = (arc(angles[k]), arc(angles[k + 1]));
        w.poly(&[
            place(p0.0, p0.1, zc - 0.5 * t),
            place(p1.0, p1.1, zc - 0.5 * t),
            place(p1.0, p1.1, zc + 0.5 * t),
            place(p0.0, p0.1, zc + 0.5 * t),
        ]);
    }
    w.poly(&[
        place(a0, y1, zc - 0.5 * t),
        place(a1, y1, zc - 0.5 * t),
        place(a1, y1, zc + 0.5 * t),
        place(a0, y1, zc + 0.5 * t),
    ]);
}

/// A column: square plinth, round shaft, square capital.
fn column(w: &mut ObjWriter, x: f64, z: f64, y0: f64, h: f64, r: f64) {
    let (pb, pc) = (1.4 * r, 1.3 * r);
    w.cuboid([x - pb, y0, z - pb], [x + pb, y0 + 0.3, z + pb]);
    w.cylinder(x, z, r, y0 + 0.3, y0 + h - 0.3, 16);
    w.cuboid([x - pc, y0 + h - 0.3, z - pc], [x + pc, y0 + h, z + pc]);
}

/// Half-sizes of the atrium's courtyard (x, z) and its gallery depth, in metres.
const COURT: [f64; 2] = [9.0, 5.0];
const GALLERY: f64 = 3.0;

/// A two-storey arcaded courtyard in the manner of the Sponza atrium, open to the sky: columns with
/// plinths and capitals, semicircular arches, galleries roofed by slabs and closed by outer walls, a
/// parapet on the upper storey. Y up, metres.
pub fn atrium() -> String {
    let mut w = ObjWriter::new(
        "hemilab procedural atrium (src/scene/generate.rs::atrium): two storeys of arcades around an\n\
         open courtyard. Y up, metres. Generated; MIT OR Apache-2.0 like hemilab.",
    );
    let [cx, cz] = COURT;
    let (ox, oz) = (cx + GALLERY, cz + GALLERY);
    let (storey, col_h, arch_top) = (6.0, 4.0, 5.6);
    w.poly(&[[-ox, 0.0, -oz], [ox, 0.0, -oz], [ox, 0.0, oz], [-ox, 0.0, oz]]);
    // Outer walls, full height.
    let top = 2.0 * storey + 0.5;
    w.cuboid([-ox - 0.4, 0.0, -oz - 0.4], [ox + 0.4, top, -oz]);
    w.cuboid([-ox - 0.4, 0.0, oz], [ox + 0.4, top, oz + 0.4]);
    w.cuboid([-ox - 0.4, 0.0, -oz], [-ox, top, oz]);
    w.cuboid([ox, 0.0, -oz], [ox + 0.4, top, oz]);
    let bays_x = 6; // along the long sides
    let bays_z = 4; // along the short sides
    for level in 0..2 {
        let y0 = level as f64 * storey;
        let r = if level == 0 { 0.35 } else { 0.28 };
        let xs: Vec<f64> = (0..=bays_x).map(|i| -cx + 2.0 * cx * i as f64 / bays_x as f64).collect();
        let zs: Vec<f64> = (0..=bays_z).map(|i| -cz + 2.0 * cz * i as f64 / bays_z as f64).collect();
        for &x in &xs {
            for z in [-cz, cz] {
                column(&mut w, x, z, y0, col_h, r);
            }
        }
        for &z in &zs[1..bays_z] {
            for x in [-cx, cx] {
                column(&mut w, x, z, y0, col_h, r);
            }
        }
        let t = 0.6;
        for pair in xs.windows(2) {
            for z in [-cz, cz] {
                arch_bay(&mut w, false, z, t, pair[0], pair[1], y0 + col_h, y0 + storey, 12);
            }
        }
        for pair in zs.windows(2) {
            for x in [-cx, cx] {
                arch_bay(&mut w, true, x, t, pair[0], pair[1], y0 + col_h, y0 + storey, 12);
            }
        }
        // The gallery's ceiling slab, from the arcade to the outer wall (a ring of four slabs).
        let (s0, s1) = (y0 + arch_top, y0 + storey);
        let e = 0.5 * t;
        w.cuboid([-ox, s0, -oz], [ox, s1, -cz + e]);
        w.cuboid([-ox, s0, cz - e], [ox, s1, oz]);
        w.cuboid([-ox, s0, -cz + e], [-cx + e, s1, cz - e]);
        w.cuboid([cx - e, s0, -cz + e], [ox, s1, cz - e]);
        if level == 1 {
            continue;
        }
        // Parapet along the upper storey's arcade.
        let (p0, p1, pt) = (storey, storey + 1.0, 0.15);
        w.cuboid([-cx, p0, -cz - pt], [cx, p1, -cz + pt]);
        w.cuboid([-cx, p0, cz - pt], [cx, p1, cz + pt]);
        w.cuboid([-cx - pt, p0, -cz + pt], [-cx + pt, p1, cz - pt]);
        w.cuboid([cx - pt, p0, -cz + pt], [cx + pt, p1, cz - pt]);
    }
    // Steps and a well head in the courtyard: more contact shadows on the open floor.
    for k in 0..3 {
        let s = 1.6 - 0.4 * k as f64;
        w.cuboid([-s, 0.15 * k as f64, -s], [s, 0.15 * (k + 1) as f64, s]);
    }
    w.cylinder(0.0, 0.0, 0.7, 0.45, 1.3, 24);
    w.finish()
}

/// Slat spacing and width (metres) of `slats`.
pub const SLAT_PITCH: f64 = 0.12;
pub const SLAT_WIDTH: f64 = 0.03;

/// A louvred pergola: 40 thin parallel slats (3 cm wide, 12 cm apart) on two beams and four posts,
/// 0.7 m above a floor, beside a picket fence. Seen from above at a slant, the floor under the slats
/// and the fence carry fine periodic AO: the geometry on which one point set shared by every pixel
/// (a static seed) turns its error into moiré. Y up, metres.
pub fn slats() -> String {
    let mut w = ObjWriter::new(
        "hemilab procedural slats (src/scene/generate.rs::slats): a louvred pergola and a picket fence\n\
         over a floor. Y up, metres. Generated; MIT OR Apache-2.0 like hemilab.",
    );
    w.poly(&[[-4.0, 0.0, -4.0], [4.0, 0.0, -4.0], [4.0, 0.0, 4.0], [-4.0, 0.0, 4.0]]);
    let (h, n) = (0.7, 40);
    let x0 = -0.5 * SLAT_PITCH * (n - 1) as f64;
    for i in 0..n {
        let x = x0 + SLAT_PITCH * i as f64;
        w.cuboid([x - 0.5 * SLAT_WIDTH, h, -1.8], [x + 0.5 * SLAT_WIDTH, h + 0.08, 1.8]);
    }
    let span = -x0 + 0.2;
    for z in [-1.5, 1.5] {
        w.cuboid([-span, h - 0.12, z - 0.05], [span, h, z + 0.05]);
        for x in [-span + 0.1, span - 0.1] {
            w.cuboid([x - 0.05, 0.0, z - 0.05], [x + 0.05, h - 0.12, z + 0.05]);
        }
    }
    // Picket fence along z = -2.6: 50 pickets 4 cm wide on two rails.
    for i in 0..50 {
        let x = -3.0 + 0.12 * i as f64;
        w.cuboid([x - 0.02, 0.0, -2.62], [x + 0.02, 0.7, -2.58]);
    }
    for y in [0.15, 0.55] {
        w.cuboid([-3.1, y, -2.66], [3.0, y + 0.06, -2.62]);
    }
    w.finish()
}

/// SplitMix64 of a lattice point: the terrain's value noise, the same on every machine.
fn lattice_hash(i: i64, j: i64, seed: u64) -> f64 {
    let mut z = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (j as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ seed;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// Smoothly interpolated value noise in [0, 1].
fn value_noise(x: f64, z: f64, seed: u64) -> f64 {
    let (i, j) = (x.floor() as i64, z.floor() as i64);
    let (fx, fz) = (x - x.floor(), z - z.floor());
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (sx, sz) = (s(fx), s(fz));
    let a = lattice_hash(i, j, seed) * (1.0 - sx) + lattice_hash(i + 1, j, seed) * sx;
    let b = lattice_hash(i, j + 1, seed) * (1.0 - sx) + lattice_hash(i + 1, j + 1, seed) * sx;
    a * (1.0 - sz) + b * sz
}

/// Terrain height (metres) at (x, z): four octaves of value noise, rising away from the camera.
pub fn terrain_height(x: f64, z: f64) -> f64 {
    let mut h = 0.0;
    let (mut amp, mut freq) = (6.0, 1.0 / 24.0);
    for octave in 0..4 {
        h += amp * (value_noise(x * freq, z * freq, 17 + octave) - 0.5);
        amp *= 0.45;
        freq *= 2.1;
    }
    h + 0.04 * (-z).max(0.0)
}

/// Rolling terrain, 120 m square on a 1 m grid, with scattered boulders (boxes half sunk and tilted
/// by the slope) and a low drystone wall, under the open sky: most AO rays escape, occlusion comes
/// from near the horizon. Y up, metres.
pub fn terrain() -> String {
    let mut w = ObjWriter::new(
        "hemilab procedural terrain (src/scene/generate.rs::terrain): hills, boulders and a low wall\n\
         under the open sky. Y up, metres. Generated; MIT OR Apache-2.0 like hemilab.",
    );
    let (half, step) = (60i64, 1.0);
    let n = (2 * half + 1) as usize;
    let first = w.vertices + 1;
    for j in -half..=half {
        for i in -half..=half {
            let (x, z) = (i as f64 * step, j as f64 * step);
            w.v([x, terrain_height(x, z), z]);
        }
    }
    let id = |i: usize, j: usize| first + j * n + i;
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            w.face(&[id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
            w.face(&[id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    for k in 0..60u64 {
        let x = (lattice_hash(k as i64, 1, 99) - 0.5) * 50.0;
        let z = -(lattice_hash(k as i64, 2, 99)) * 50.0 + 5.0;
        let s = 0.3 + 1.2 * lattice_hash(k as i64, 3, 99).powi(2);
        let y = terrain_height(x, z);
        w.cuboid([x - s, y - 0.5 * s, z - s], [x + s, y + s, z + s]);
    }
    // A drystone wall across the slope: blocks of uneven height.
    for k in 0..40 {
        let x = -20.0 + k as f64;
        let z = -12.0 + 0.15 * k as f64;
        let hb = 0.6 + 0.4 * lattice_hash(k, 4, 99);
        let y = terrain_height(x + 0.5, z);
        w.cuboid([x, y - 0.3, z - 0.3], [x + 0.95, y + hb, z + 0.3]);
    }
    w.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mesh::parse_obj;

    #[test]
    fn every_generated_scene_parses_without_dropped_triangles() {
        for (name, text) in [("atrium", atrium()), ("slats", slats()), ("terrain", terrain())] {
            let m = parse_obj(text.as_bytes()).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(m.dropped, 0, "{name}");
            assert!(m.indices.len() > 500, "{name}: {}", m.indices.len());
        }
    }

    #[test]
    fn generation_is_deterministic_and_noise_in_range() {
        assert_eq!(slats(), slats());
        for k in 0..100 {
            let v = value_noise(k as f64 * 0.37, k as f64 * -1.3, 5);
            assert!((0.0..=1.0).contains(&v));
        }
    }
}

//! FLIP's separable kernels and the two convolution passes. The contrast sensitivity functions are
//! Gaussians in the frequency domain, hence Gaussians in space; the blue–yellow one is a sum of two
//! and is separated as two products, each with the square root of its amplitude (the repository's
//! `misc/separatedConvolutions.pdf`). Borders repeat the edge pixel. Each output sums its taps in
//! kernel order, as flip-evaluator does, so the rounding agrees with it.

use std::f32::consts::PI;

/// Amplitudes a and scales b of the spatial filters (the paper's Table 1): Y, Cx, Cz's first
/// Gaussian, then Cz's second.
const A1: [f32; 3] = [1.0, 1.0, 34.1];
const B1: [f32; 3] = [0.0047, 0.0053, 0.04];
const A2Z: f32 = 13.5;
const B2Z: f32 = 0.025;
/// The largest scale parameter, which sets the spatial radius.
const B_MAX: f32 = 0.04;

/// Width of the edge and point detectors in degrees (w in the paper).
const GW: f32 = 0.082;

/// The paper's Gaussian in its frequency-derived form, a·√(π/b)·exp(−π²x²/b), x² in degrees².
fn gaussian(x2: f32, a: f32, b: f32) -> f32 {
    a * (PI / b).sqrt() * (-(PI * PI) * x2 / b).exp()
}

/// The same with the amplitude under a square root, so that a product of two 1-D taps is one 2-D tap.
fn gaussian_sqrt(x2: f32, a: f32, b: f32) -> f32 {
    (a * (PI / b).sqrt()).sqrt() * (-(PI * PI) * x2 / b).exp()
}

/// The 1-D spatial taps: `y`, `cx` (each normalized to sum 1) and `cz1`, `cz2` (normalized
/// together, so that the 2-D sum of cz1⊗cz1 + cz2⊗cz2 is 1).
pub(super) struct SpatialTaps {
    pub y: Vec<f32>,
    pub cx: Vec<f32>,
    pub cz1: Vec<f32>,
    pub cz2: Vec<f32>,
}

impl SpatialTaps {
    pub(super) fn new(ppd: f32) -> Self {
        let radius = (3.0 * (B_MAX / (2.0 * (PI * PI))).sqrt() * ppd).ceil() as i32;
        let dx = 1.0 / ppd;
        let (mut y, mut cx, mut cz1, mut cz2) = (vec![], vec![], vec![], vec![]);
        let (mut sy, mut scx, mut sz1, mut sz2) = (0.0f32, 0.0f32, 0.0f32, 0.0f32);
        for i in -radius..=radius {
            let x = i as f32 * dx;
            let x2 = x * x;
            let t = [
                gaussian(x2, A1[0], B1[0]),
                gaussian(x2, A1[1], B1[1]),
                gaussian_sqrt(x2, A1[2], B1[2]),
                gaussian_sqrt(x2, A2Z, B2Z),
            ];
            y.push(t[0]);
            cx.push(t[1]);
            cz1.push(t[2]);
            cz2.push(t[3]);
            sy += t[0];
            scx += t[1];
            sz1 += t[2];
            sz2 += t[3];
        }
        let (ny, ncx) = (1.0 / sy, 1.0 / scx);
        let nz = 1.0 / (sz1 * sz1 + sz2 * sz2).sqrt();
        y.iter_mut().for_each(|v| *v *= ny);
        cx.iter_mut().for_each(|v| *v *= ncx);
        cz1.iter_mut().for_each(|v| *v *= nz);
        cz2.iter_mut().for_each(|v| *v *= nz);
        SpatialTaps { y, cx, cz1, cz2 }
    }
}

/// The 1-D feature taps: a Gaussian of σ = w/2 degrees (sum 1), its first derivative and its second
/// (positive and negative parts each normalized to ±1).
pub(super) struct FeatureTaps {
    pub g: Vec<f32>,
    pub dg: Vec<f32>,
    pub ddg: Vec<f32>,
}

impl FeatureTaps {
    pub(super) fn new(ppd: f32) -> Self {
        let sd = 0.5 * GW * ppd;
        let radius = (3.0 * sd).ceil() as i32;
        let (mut g, mut dg, mut ddg) = (vec![], vec![], vec![]);
        let (mut sg, mut dpos, mut dneg, mut ddpos, mut ddneg) = (0.0f32, 0.0f32, 0.0f32, 0.0f32, 0.0f32);
        for i in -radius..=radius {
            let x = i as f32;
            let gi = (-(x * x) / (2.0 * sd * sd)).exp();
            sg += gi;
            let d = -x * gi;
            if d > 0.0 {
                dpos += d;
            } else {
                dneg -= d;
            }
            let dd = (x * x / (sd * sd) - 1.0) * gi;
            if dd > 0.0 {
                ddpos += dd;
            } else {
                ddneg -= dd;
            }
            g.push(gi);
            dg.push(d);
            ddg.push(dd);
        }
        g.iter_mut().for_each(|v| *v /= sg);
        dg.iter_mut().for_each(|v| *v /= if *v > 0.0 { dpos } else { dneg });
        ddg.iter_mut().for_each(|v| *v /= if *v > 0.0 { ddpos } else { ddneg });
        FeatureTaps { g, dg, ddg }
    }
}

/// Convolves every row of `src` (`w` wide) with each of `taps` at once, repeating edge pixels:
/// `outs[k][x] = Σ_i taps[k][i] · src[clamp(x + i − r)]`, summed in i order.
pub(super) fn rows(src: &[f32], w: usize, taps: &[&[f32]], outs: &mut [&mut [f32]]) {
    let r = taps[0].len() / 2;
    let mut padded = vec![0.0f32; w + 2 * r];
    for (row_index, row) in src.chunks_exact(w).enumerate() {
        for (p, v) in padded.iter_mut().enumerate() {
            *v = row[p.saturating_sub(r).min(w - 1)];
        }
        for (k, t) in taps.iter().enumerate() {
            let out = &mut outs[k][row_index * w..(row_index + 1) * w];
            out.iter_mut().for_each(|o| *o = 0.0);
            for (i, &wt) in t.iter().enumerate() {
                for (o, &s) in out.iter_mut().zip(&padded[i..i + w]) {
                    *o += wt * s;
                }
            }
        }
    }
}

/// Convolves every column of `src` (`w` wide) with `taps`, repeating edge rows, into `out`;
/// summed in tap order like `rows`.
pub(super) fn columns(src: &[f32], w: usize, taps: &[f32], out: &mut [f32]) {
    let h = src.len() / w;
    let r = (taps.len() / 2) as isize;
    for y in 0..h {
        let o = &mut out[y * w..(y + 1) * w];
        o.iter_mut().for_each(|v| *v = 0.0);
        for (i, &wt) in taps.iter().enumerate() {
            let yy = (y as isize + i as isize - r).clamp(0, h as isize - 1) as usize;
            for (v, &s) in o.iter_mut().zip(&src[yy * w..(yy + 1) * w]) {
                *v += wt * s;
            }
        }
    }
}

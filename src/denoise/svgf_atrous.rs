//! SVGF's spatial part (`svgf`, Schied et al. 2017 §4.3): one edge-avoiding à-trous pass of the
//! colour under the kept edge-stopping taps (`taps`) and the variance-scaled luminance weight
//!
//!   w_l = exp(−|l_p − l_q| / (σ_l √(g₃ₓ₃(Var(l_p))) + ε)),
//!
//! the variance pre-filtered by a 3 × 3 Gaussian and filtered along with the value by the squared
//! weights (eq. 6). Apart from `svgf` (its history and temporal accumulation) because each pass
//! is a whole image's work of its own.

use super::edges::{Guide, Taps};
use super::taps::Pass as TapPass;
use rayon::prelude::*;

/// ε of the luminance weight: keeps a zero variance from dividing by zero.
pub const LUMINANCE_EPS: f64 = 1e-10;

/// With `SvgfOptions::relative_eps`, the variance floor of the luminance weight as a share of the
/// frame's mean level squared: σ_l √(g₃ₓ₃(Var) + `RELATIVE_EPS` · l̄²) + `LUMINANCE_EPS`, l̄ the
/// mean of the temporally accumulated colour over covered pixels. 1e-4 is a standard deviation of
/// 1 % of the mean level: where the variance is 0 (a converged or noise-free input) neighbours
/// differing by a few percent of the level are still averaged, instead of none at all.
pub const RELATIVE_EPS: f64 = 1e-4;

/// The 3 × 3 Gaussian (1/4, 1/2, 1/4)² of the variance over covered pixels, normalized by the
/// covered taps' weight: g₃ₓ₃(Var) of the luminance weight.
pub(super) fn prefilter(guide: &Guide, var: &[f64]) -> Vec<f64> {
    const G: [f64; 3] = [0.25, 0.5, 0.25];
    let (w, h) = (guide.width(), guide.height());
    guide.per_covered(|x, y, _| {
        let (mut s, mut ws) = (0.0f64, 0.0f64);
        for (ky, gy) in G.iter().enumerate() {
            for (kx, gx) in G.iter().enumerate() {
                let (qx, qy) = (x + kx as i64 - 1, y + ky as i64 - 1);
                if qx < 0 || qy < 0 || qx >= w || qy >= h {
                    continue;
                }
                let q = (qy * w + qx) as usize;
                if guide.is_covered(q) {
                    s += gx * gy * var[q];
                    ws += gx * gy;
                }
            }
        }
        s / ws
    })
}

pub(super) type Pass = (Vec<f64>, Vec<f64>, Option<Vec<f64>>);

/// The luminance weight w_l = exp(−|d| / scale) of a tap of edge weight `g`, as its product with
/// `g` needs it: exp is called only where its value matters, so that g · w_l has exp's bits. Where
/// d = 0, exp(−0) = 1; below −746, exp underflows to +0 (its least subnormal is exp(−744.4)); for
/// g = 0 (a tap across an edge, w_z or w_n underflowed) g · w_l is +0 for any w_l in [0, 1].
/// A NaN goes to exp as before.
#[inline]
fn luminance_weight(d: f64, scale: f64, g: f64) -> f64 {
    let x = -d.abs() / scale;
    if x == 0.0 || (g == 0.0 && !x.is_nan()) {
        1.0
    } else if x < -746.0 {
        0.0
    } else {
        x.exp()
    }
}

/// The luminance weight's ε: the fixed `LUMINANCE_EPS`, or that plus a variance `floor`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Eps {
    pub(super) relative: bool,
    pub(super) floor: f64,
}

impl Eps {
    /// σ_l √(g₃ₓ₃(Var)) + ε, or σ_l √(g₃ₓ₃(Var) + floor) + ε.
    fn scale(self, sigma_l: f64, gvar: f64) -> f64 {
        if self.relative {
            sigma_l * (gvar + self.floor).sqrt() + LUMINANCE_EPS
        } else {
            sigma_l * gvar.sqrt() + LUMINANCE_EPS
        }
    }
}

/// The mean of `c` over covered pixels (0 with none): the level `RELATIVE_EPS` is relative to.
pub(super) fn level(guide: &Guide, c: &[f64]) -> f64 {
    let (s, k) =
        (0..c.len()).filter(|&p| guide.is_covered(p)).fold((0.0, 0usize), |(s, k), p| (s + c[p], k + 1));
    if k == 0 { 0.0 } else { s / k as f64 }
}

/// À-trous pass `it` of the colour `c` with variance `var` (and the reference's colour `cr` under
/// the same weights): the new colour, variance and reference colour.
pub(super) fn pass(
    guide: &Guide,
    c: &[f64],
    var: &[f64],
    cr: Option<&[f64]>,
    it: u32,
    sigma_l: f64,
    eps: Eps,
) -> Pass {
    let w = guide.width() as usize;
    let gvar = prefilter(guide, var);
    let taps_of = TapPass::new(guide, it);
    let rows: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..guide.height() as usize)
        .into_par_iter()
        .map(|y| {
            let mut taps: Taps = [(0, 0.0); 25];
            let (mut rc, mut rv, mut rr) =
                (vec![0.0; w], vec![0.0; w], vec![0.0; if cr.is_some() { w } else { 0 }]);
            for x in 0..w {
                let p = y * w + x;
                if !guide.is_covered(p) {
                    rc[x] = c[p];
                    if let Some(cr) = cr {
                        rr[x] = cr[p];
                    }
                    continue;
                }
                let k = taps_of.taps(x as i64, y as i64, &mut taps);
                let scale = eps.scale(sigma_l, gvar[p]);
                let (mut s, mut sv, mut sr, mut ws) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
                for &(q, g) in &taps[..k] {
                    let wt = g * luminance_weight(c[p] - c[q], scale, g);
                    s += wt * c[q];
                    sv += wt * wt * var[q];
                    if let Some(cr) = cr {
                        sr += wt * cr[q];
                    }
                    ws += wt;
                }
                // The centre tap has w_l = 1: ws > 0 unless its own normal weight underflows.
                if ws > 0.0 {
                    rc[x] = s / ws;
                    rv[x] = sv / (ws * ws);
                    if cr.is_some() {
                        rr[x] = sr / ws;
                    }
                } else {
                    rc[x] = c[p];
                    rv[x] = var[p];
                    if let Some(cr) = cr {
                        rr[x] = cr[p];
                    }
                }
            }
            (rc, rv, rr)
        })
        .collect();
    let mut out =
        (Vec::with_capacity(c.len()), Vec::with_capacity(c.len()), cr.map(|_| Vec::with_capacity(c.len())));
    for (rc, rv, rr) in rows {
        out.0.extend(rc);
        out.1.extend(rv);
        if let Some(o) = out.2.as_mut() {
            o.extend(rr);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_luminance_weight_times_the_edge_weight_has_exps_bits() {
        let scales = [1e-10, 1e-3, 0.05, 0.4, 4.0];
        let mut d = -2.0f64;
        let mut cases = 0;
        while d <= 2.0 {
            for &scale in &scales {
                for g in [0.0, 1e-300, 0.015625, 0.140625, 1.0] {
                    let exact = g * (-d.abs() / scale).exp();
                    assert_eq!(
                        (g * luminance_weight(d, scale, g)).to_bits(),
                        exact.to_bits(),
                        "{d} {scale} {g}"
                    );
                    cases += 1;
                }
            }
            d += 1.0 / 4096.0 + 1e-9;
        }
        // Around exp's underflow: x from −760 to −700.
        for i in 0..60_000 {
            let x = -760.0 + i as f64 * 1e-3;
            assert_eq!(luminance_weight(x, 1.0, 1.0).to_bits(), x.exp().to_bits(), "{x}");
        }
        assert!(cases > 100_000);
    }
}

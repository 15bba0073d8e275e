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
/// the same weights): the new colour, variance and reference colour. Where the pass's taps are a
/// kept table and the CPU runs `exp4`, four pixels of a row at a time (`row_lanes`): each lane the
/// same operations in the same order as `pixel`'s, so the same bits.
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
    let lanes = taps_of.lanes().filter(|_| super::exp::available());
    let px = Pixels { c, var, cr, gvar: &gvar, sigma_l, eps };
    let rows: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..guide.height() as usize)
        .into_par_iter()
        .map(|y| {
            let mut taps: Taps = [(0, 0.0); 25];
            let mut row = (vec![0.0; w], vec![0.0; w], vec![0.0; if cr.is_some() { w } else { 0 }]);
            let mut done = 0;
            #[cfg(target_arch = "x86_64")]
            if let Some(l) = &lanes {
                // SAFETY: `exp::available` checked AVX2 and FMA.
                done = unsafe { row_lanes(l, &px, y, w, &mut row) };
            }
            for x in done..w {
                let p = y * w + x;
                if !guide.is_covered(p) {
                    row.0[x] = c[p];
                    if let Some(cr) = cr {
                        row.2[x] = cr[p];
                    }
                    continue;
                }
                let k = taps_of.taps(x as i64, y as i64, &mut taps);
                let (rc, rv, rr) = px.pixel(p, &taps[..k]);
                (row.0[x], row.1[x]) = (rc, rv);
                if cr.is_some() {
                    row.2[x] = rr;
                }
            }
            row
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

/// What a pass reads per pixel: the colour, its variance, the reference's colour, the prefiltered
/// variance and the luminance weight's σ_l and ε.
struct Pixels<'a> {
    c: &'a [f64],
    var: &'a [f64],
    cr: Option<&'a [f64]>,
    gvar: &'a [f64],
    sigma_l: f64,
    eps: Eps,
}

impl Pixels<'_> {
    /// Covered pixel `p` under its `taps`: its new colour, variance and reference colour (eq. 6;
    /// the reference's 0 without one).
    fn pixel(&self, p: usize, taps: &[(usize, f64)]) -> (f64, f64, f64) {
        let (c, var) = (self.c, self.var);
        let scale = self.eps.scale(self.sigma_l, self.gvar[p]);
        let (mut s, mut sv, mut sr, mut ws) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for &(q, g) in taps {
            let wt = g * luminance_weight(c[p] - c[q], scale, g);
            s += wt * c[q];
            sv += wt * wt * var[q];
            if let Some(cr) = self.cr {
                sr += wt * cr[q];
            }
            ws += wt;
        }
        // The centre tap has w_l = 1: ws > 0 unless its own normal weight underflows.
        if ws > 0.0 {
            (s / ws, sv / (ws * ws), sr / ws)
        } else {
            (c[p], var[p], self.cr.map_or(0.0, |cr| cr[p]))
        }
    }
}

/// Row `y`'s pixels four at a time (lane i pixel x + i), up to the last whole four: returns how
/// many it filtered. Each lane walks its own taps in kernel order (the table's mask bits), its
/// sums a chain of its own as `Pixels::pixel`'s; a lane without tap j leaves its sums as they were
/// (a blend, not an added 0, which would turn −0 into +0 or a NaN into the sum); the luminance
/// weight by `exp4`, lanes outside its main path by `luminance_weight`. Uncovered pixels (mask 0)
/// keep their colour and reference and a variance of 0, as `pass`'s.
///
/// # Safety
/// The CPU has AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn row_lanes(
    l: &super::taps::Lanes,
    px: &Pixels,
    y: usize,
    w: usize,
    row: &mut (Vec<f64>, Vec<f64>, Vec<f64>),
) -> usize {
    let c = px.c;
    let n4 = w / 4 * 4;
    for x0 in (0..n4).step_by(4) {
        let p0 = y * w + x0;
        let m: [u32; 4] = std::array::from_fn(|i| l.mask[p0 + i]);
        if m == [0; 4] {
            row.0[x0..x0 + 4].copy_from_slice(&c[p0..p0 + 4]);
            if let Some(cr) = px.cr {
                row.2[x0..x0 + 4].copy_from_slice(&cr[p0..p0 + 4]);
            }
            continue;
        }
        // SAFETY: AVX2 and FMA (this function's features).
        unsafe {
            if m == [ALL_TAPS; 4] {
                group::<true>(l, px, (x0, p0), m, row)
            } else {
                group::<false>(l, px, (x0, p0), m, row)
            }
        }
    }
    n4
}

/// Every tap of the 5 × 5 kernel (25 bits).
#[cfg(target_arch = "x86_64")]
const ALL_TAPS: u32 = (1 << 25) - 1;

/// `row_lanes`' four pixels x0.. (p0.. in the image) with tap masks `m`. `FULL`: every lane has
/// every tap (most of a frame), so no lane is masked: the blends and masked loads are plain adds
/// and loads and lane i's weight of tap j is its j-th; the same operations on every lane.
///
/// # Safety
/// The CPU has AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn group<const FULL: bool>(
    l: &super::taps::Lanes,
    px: &Pixels,
    (x0, p0): (usize, usize),
    m: [u32; 4],
    row: &mut (Vec<f64>, Vec<f64>, Vec<f64>),
) {
    use std::arch::x86_64::*;
    let (c, var) = (px.c, px.var);
    let mv = _mm256_setr_epi64x(m[0] as i64, m[1] as i64, m[2] as i64, m[3] as i64);
    // Lane i's next weight; a lane without the tap reads its next one's (or 0 past the end) and
    // drops it.
    let mut cursor: [usize; 4] = std::array::from_fn(|i| l.start[p0 + i] as usize);
    let scales: [f64; 4] = std::array::from_fn(|i| px.eps.scale(px.sigma_l, px.gvar[p0 + i]));
    // SAFETY: p0 + 3 < c.len() (a whole four of row y).
    let (scale, cp) = unsafe { (_mm256_loadu_pd(scales.as_ptr()), _mm256_loadu_pd(c.as_ptr().add(p0))) };
    let z = _mm256_setzero_pd();
    let (mut s, mut sv, mut sr, mut ws) = (z, z, z, z);
    let mut bits = m[0] | m[1] | m[2] | m[3];
    while bits != 0 {
        let j = bits.trailing_zeros() as usize;
        bits &= bits - 1;
        let bit = _mm256_set1_epi64x(1 << j);
        let has =
            if FULL { _mm256_set1_epi64x(-1) } else { _mm256_cmpeq_epi64(_mm256_and_si256(mv, bit), bit) };
        let hasd = _mm256_castsi256_pd(has);
        let lanes = if FULL { 0xf } else { _mm256_movemask_pd(hasd) as u32 };
        // Lane i's tap j is pixel p0 + i + offset[j], inside the image where the lane has it;
        // the masked loads read nothing for the other lanes.
        let q0 = (p0 as i64 + l.offset[j]) as isize;
        let g = if FULL {
            let at = |i: usize| l.weight[cursor[i] + j];
            _mm256_setr_pd(at(0), at(1), at(2), at(3))
        } else {
            let at = |i: usize| l.weight.get(cursor[i]).copied().unwrap_or(0.0);
            let g = _mm256_and_pd(_mm256_setr_pd(at(0), at(1), at(2), at(3)), hasd);
            for (i, k) in cursor.iter_mut().enumerate() {
                *k += ((m[i] >> j) & 1) as usize;
            }
            g
        };
        // SAFETY: the lanes read are pixels of the image.
        let (cq, vq) = unsafe {
            (
                _mm256_maskload_pd(c.as_ptr().wrapping_offset(q0), has),
                _mm256_maskload_pd(var.as_ptr().wrapping_offset(q0), has),
            )
        };
        let d = _mm256_sub_pd(cp, cq);
        // −|d| / scale: the sign bit set.
        let x = _mm256_div_pd(_mm256_or_pd(d, _mm256_set1_pd(-0.0)), scale);
        // SAFETY: AVX2 and FMA (this function's features).
        let (e, special) = unsafe { super::exp::exp4(x) };
        let one = _mm256_or_pd(
            _mm256_cmp_pd::<_CMP_EQ_OQ>(x, z),
            _mm256_and_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(g, z), _mm256_cmp_pd::<_CMP_ORD_Q>(x, x)),
        );
        let under = _mm256_cmp_pd::<_CMP_LT_OQ>(x, _mm256_set1_pd(-746.0));
        let mut lw = _mm256_blendv_pd(_mm256_blendv_pd(e, z, under), _mm256_set1_pd(1.0), one);
        let fix = special & lanes & !(_mm256_movemask_pd(_mm256_or_pd(one, under)) as u32);
        if fix != 0 {
            let mut a = [[0.0f64; 4]; 4];
            for (v, o) in [d, scale, g, lw].into_iter().zip(&mut a) {
                // SAFETY: one register into 4 f64.
                unsafe { _mm256_storeu_pd(o.as_mut_ptr(), v) };
            }
            for i in (0..4).filter(|i| fix & (1 << i) != 0) {
                a[3][i] = luminance_weight(a[0][i], a[1][i], a[2][i]);
            }
            // SAFETY: 4 f64.
            lw = unsafe { _mm256_loadu_pd(a[3].as_ptr()) };
        }
        let wt = _mm256_mul_pd(g, lw);
        s = _mm256_blendv_pd(s, _mm256_add_pd(s, _mm256_mul_pd(wt, cq)), hasd);
        sv = _mm256_blendv_pd(sv, _mm256_add_pd(sv, _mm256_mul_pd(_mm256_mul_pd(wt, wt), vq)), hasd);
        if let Some(cr) = px.cr {
            // SAFETY: as the colour's load.
            let rq = unsafe { _mm256_maskload_pd(cr.as_ptr().wrapping_offset(q0), has) };
            sr = _mm256_blendv_pd(sr, _mm256_add_pd(sr, _mm256_mul_pd(wt, rq)), hasd);
        }
        ws = _mm256_blendv_pd(ws, _mm256_add_pd(ws, wt), hasd);
    }
    let pos = _mm256_cmp_pd::<_CMP_GT_OQ>(ws, z);
    let covered = _mm256_castsi256_pd(_mm256_xor_si256(
        _mm256_cmpeq_epi64(mv, _mm256_setzero_si256()),
        _mm256_set1_epi64x(-1),
    ));
    // SAFETY: p0..p0 + 4 is inside the image and x0..x0 + 4 inside the row.
    unsafe {
        let vp = _mm256_loadu_pd(var.as_ptr().add(p0));
        let rc = _mm256_blendv_pd(cp, _mm256_div_pd(s, ws), pos);
        let rv = _mm256_and_pd(_mm256_blendv_pd(vp, _mm256_div_pd(sv, _mm256_mul_pd(ws, ws)), pos), covered);
        _mm256_storeu_pd(row.0.as_mut_ptr().add(x0), rc);
        _mm256_storeu_pd(row.1.as_mut_ptr().add(x0), rv);
        if let Some(cr) = px.cr {
            let rp = _mm256_loadu_pd(cr.as_ptr().add(p0));
            _mm256_storeu_pd(row.2.as_mut_ptr().add(x0), _mm256_blendv_pd(rp, _mm256_div_pd(sr, ws), pos));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::denoise::taps::{TapCache, with_cache};
    use crate::render::GBuffer;
    use glam::Vec3;
    use std::sync::Arc;

    /// A pass's three images as bits.
    fn bits(p: &Pass) -> Vec<u64> {
        p.0.iter().chain(&p.1).chain(p.2.iter().flatten()).map(|v| v.to_bits()).collect()
    }

    #[test]
    fn four_pixels_at_a_time_give_each_pixels_bits() {
        // 37 wide: a row ends in a part four. Colours with equal and one-ulp-apart neighbours,
        // variances from 1e-12 to 1 (so −|d|/s spans 0, below 2⁻⁵⁴, glibc's 512..746 special case
        // and past exp's underflow), an uncovered pixel every 13th, normals that cut some taps to 0.
        let (w, h) = (37u32, 23u32);
        let n = (w * h) as usize;
        let mut k = 0u64;
        let mut next = move || {
            k += 1;
            (crate::sampling::hash::hash(0x853c49e6748fea9b, k) >> 11) as f64 / (1u64 << 53) as f64
        };
        let depth: Vec<f32> = (0..n).map(|i| 1.0 + 0.02 * (i % 5) as f32).collect();
        let normal: Vec<Vec3> =
            (0..n)
                .map(|i| {
                    if i % 17 == 0 { Vec3::X } else { Vec3::new(0.05 * (i % 3) as f32, 0.0, 1.0).normalize() }
                })
                .collect();
        let coverage: Vec<f32> = (0..n).map(|i| if i % 13 == 5 { 0.0 } else { 1.0 }).collect();
        let gb = GBuffer::synthetic(w, h, depth, normal, coverage);
        let c: Vec<f64> = (0..n)
            .map(|i| match i % 4 {
                0 => 0.5,
                1 => f64::from_bits(0.5f64.to_bits() + 1),
                _ => next(),
            })
            .collect();
        // Rows 0-7 at a variance of 1e-8 (s = 4e-4: a difference of 0.2-0.3 gives −|d|/s in
        // glibc's special case), rows 8-15 at 1 (s = 4: one ulp of 0.5 gives |x| below 2⁻⁵⁴).
        let var: Vec<f64> = (0..n)
            .map(|i| match i / w as usize {
                0..8 => 1e-8,
                8..16 => 1.0,
                _ => 10f64.powf(-12.0 * next()),
            })
            .collect();
        let cr: Vec<f64> = (0..n).map(|_| next()).collect();
        let guide = Guide::new(&gb, 1.0, 128.0);
        // Those cases are there: pass 0's taps (of weight > 0) by −|d|/s.
        let (mut special, mut tiny) = (0, 0);
        let gvar = prefilter(&guide, &var);
        let mut taps: Taps = [(0, 0.0); 25];
        for p in (0..n).filter(|&p| guide.is_covered(p)) {
            let k = guide.atrous_taps((p % w as usize) as i64, (p / w as usize) as i64, 0, &mut taps);
            for &(q, _) in taps[..k].iter().filter(|t| t.1 > 0.0) {
                let x = -(c[p] - c[q]).abs() / (4.0 * gvar[p].sqrt() + LUMINANCE_EPS);
                special += (-746.0..-512.0).contains(&x) as usize;
                tiny += (x != 0.0 && x.abs() < 2f64.powi(-54)) as usize;
            }
        }
        assert!(special > 20 && tiny > 20, "{special} in 512..746, {tiny} below 2^-54");
        for it in 0..3 {
            for eps in [Eps { relative: false, floor: 0.0 }, Eps { relative: true, floor: 1e-9 }] {
                for cr in [None, Some(&cr[..])] {
                    let computed =
                        with_cache(&Arc::new(TapCache::new(0)), || pass(&guide, &c, &var, cr, it, 4.0, eps));
                    let cache = Arc::new(TapCache::new(1 << 30));
                    let kept = with_cache(&cache, || {
                        pass(&guide, &c, &var, cr, it, 4.0, eps);
                        pass(&guide, &c, &var, cr, it, 4.0, eps)
                    });
                    assert_eq!(cache.tables(), 1);
                    assert_eq!(
                        bits(&kept),
                        bits(&computed),
                        "pass {it}, {eps:?}, reference {}",
                        cr.is_some()
                    );
                }
            }
        }
    }

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

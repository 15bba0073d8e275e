//! Spatiotemporal variance-guided filtering (Schied, Kaplanyan, Wyman, Patney, Chaitanya, Burgess,
//! Liu, Dachsbacher, Lefohn & Salvi 2017, "Spatiotemporal Variance-Guided Filtering: Real-Time
//! Reconstruction for Path-Traced Global Illumination", HPG), for a scalar signal (AO: the
//! "luminance" is the value itself, and there is no albedo to demodulate):
//!
//! 1. Temporal accumulation (§4.1) of the value c and of its first two moments μ₁ = E\[l\],
//!    μ₂ = E\[l²\], per pixel through the `Motion`, each with α_eff = max(α, 1/n) for a history of n
//!    frames (`history`; the paper's α = 0.2 for both).
//! 2. Variance (§4.2): μ₂ − μ₁² of the temporal moments once n ≥ 4; for a shorter history the
//!    moments are first averaged over a 7 × 7 neighbourhood by a bilateral filter whose weights
//!    are driven by depth and normal (the à-trous filter's w_z · w_n).
//! 3. Edge-avoiding à-trous passes (§4.3): the 5 × 5 B3 kernel with taps 2^i px apart (`edges`),
//!    each tap weighted by w_z · w_n and the luminance weight
//!    w_l = exp(−|l_p − l_q| / (σ_l √(g₃ₓ₃(Var(l_p))) + ε)),   σ_l = 4,
//!    the variance pre-filtered by a 3 × 3 Gaussian; the variance is filtered along with the value,
//!    by the squared weights: Var_{i+1}(p) = Σ w² Var_i(q) / (Σ w)² (eq. 6).
//! 4. The output of the first à-trous pass is the colour history of the next frame (§4.3); the
//!    moments' history is their temporal accumulation.
//!
//! The paper's 5 iterations are `Some(5)`; the default is `edges::default_iterations` of the image
//! size. On converged input (the same image pushed again and again) the temporal variance is 0,
//! the luminance weight stops at any difference and the filter passes the image through: its
//! floor is that of a converged image. `push_pair` is the joint application of the noise/bias
//! split: every weight computed on the noisy frames is applied to a reference run alongside,
//! with its own colour history (its first pass under the noisy weights).
//!
//! Background pixels (coverage 0) keep the frame's value, have no history and are never read.

use super::edges::{Guide, Taps, default_iterations};
use super::history::{Extra, Reprojected, alpha_eff};
use super::motion::Motion;
use super::taps::Pass as TapPass;
use crate::image::Image;
use crate::render::GBuffer;
use rayon::prelude::*;

/// Below this many frames of history the variance is estimated spatially (the paper's 4).
pub const SPATIAL_VARIANCE_FRAMES: u32 = 4;

/// The half width of the spatial variance estimate's window (7 × 7).
const SPATIAL_RADIUS: i64 = 3;

/// ε of the luminance weight: keeps a zero variance from dividing by zero.
pub const LUMINANCE_EPS: f64 = 1e-10;

/// With `SvgfOptions::relative_eps`, the variance floor of the luminance weight as a share of the
/// frame's mean level squared: σ_l √(g₃ₓ₃(Var) + `RELATIVE_EPS` · l̄²) + `LUMINANCE_EPS`, l̄ the
/// mean of the temporally accumulated colour over covered pixels. 1e-4 is a standard deviation of
/// 1 % of the mean level: where the variance is 0 (a converged or noise-free input) neighbours
/// differing by a few percent of the level are still averaged, instead of none at all.
pub const RELATIVE_EPS: f64 = 1e-4;

/// What a pipeline name (`svgf:5:fallback:id:releps`) chooses of SVGF beyond the paper's α and σ.
/// `Default` is `svgf`: the share-of-image iteration count, and none of the three options, which
/// is bit for bit the filter every committed run measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct SvgfOptions {
    /// À-trous passes (None: `edges::default_iterations`); the paper's 5, Falcor's 4.
    pub iterations: Option<u32>,
    /// Falcor's 3 × 3 cross-bilateral fallback (`Motion::fallback`) before a pixel restarts.
    pub fallback: bool,
    /// The paper's ID test in reprojection, on the G-buffer's primitive (triangle) ids.
    pub id_test: bool,
    /// The luminance weight's ε relative to the frame's level (`RELATIVE_EPS`), not a fixed 1e-10.
    pub relative_eps: bool,
}

/// SVGF's parameters; `Default` is the paper's (α = 0.2, σ_l = 4, σ_z = 1, σ_n = 128) with the
/// share-of-image iteration count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SvgfParams {
    /// α of the colour's temporal accumulation.
    pub alpha_color: f64,
    /// α of the moments' temporal accumulation.
    pub alpha_moments: f64,
    /// The number of à-trous passes; None: `edges::default_iterations` of the image's size.
    pub iterations: Option<u32>,
    pub sigma_luminance: f64,
    pub sigma_depth: f32,
    pub sigma_normal: f32,
    /// Falcor's 3 × 3 fallback in reprojection (`SvgfOptions::fallback`).
    pub fallback: bool,
    /// The primitive-ID test in reprojection (`SvgfOptions::id_test`).
    pub id_test: bool,
    /// ε relative to the level (`SvgfOptions::relative_eps`).
    pub relative_eps: bool,
}

impl SvgfParams {
    /// The paper's parameters with a pipeline name's `options`.
    pub fn of(options: SvgfOptions) -> Self {
        Self {
            iterations: options.iterations,
            fallback: options.fallback,
            id_test: options.id_test,
            relative_eps: options.relative_eps,
            ..Self::default()
        }
    }
}

impl Default for SvgfParams {
    fn default() -> Self {
        Self {
            alpha_color: 0.2,
            alpha_moments: 0.2,
            iterations: None,
            sigma_luminance: 4.0,
            sigma_depth: 1.0,
            sigma_normal: 128.0,
            fallback: false,
            id_test: false,
            relative_eps: false,
        }
    }
}

/// One SVGF run: the per-pixel history and what the last frame computed.
#[derive(Debug, Clone)]
pub struct Svgf {
    pub params: SvgfParams,
    frames: u32,
    length: Vec<u32>,
    /// The colour history: the first à-trous pass of the last frame.
    color: Vec<f64>,
    /// The temporally accumulated moments (μ₁, μ₂).
    moments: Vec<[f64; 2]>,
    /// The reference's colour history, for `push_pair`.
    color_ref: Option<Vec<f64>>,
    /// The last frame's temporally accumulated colour, before the à-trous passes.
    integrated: Vec<f64>,
    /// The last frame's variance estimate, before the à-trous passes.
    variance: Vec<f64>,
    /// The last frame's primitive ids, for the ID test.
    ids: Vec<u32>,
    width: u32,
    height: u32,
}

impl Svgf {
    pub fn new(params: SvgfParams) -> Self {
        Self {
            params,
            frames: 0,
            length: Vec::new(),
            color: Vec::new(),
            moments: Vec::new(),
            color_ref: None,
            integrated: Vec::new(),
            variance: Vec::new(),
            ids: Vec::new(),
            width: 0,
            height: 0,
        }
    }

    /// Frames pushed so far.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Per pixel the history length n after the last frame (0: background).
    pub fn lengths(&self) -> &[u32] {
        &self.length
    }

    /// The colour history the next frame reads: the last frame's first à-trous pass.
    pub fn history(&self) -> Image {
        self.image(&self.color)
    }

    /// The last frame's temporally accumulated colour (before the à-trous passes).
    pub fn integrated(&self) -> Image {
        self.image(&self.integrated)
    }

    /// The last frame's per-pixel variance estimate (before the à-trous passes; 0 on background).
    pub fn variance(&self) -> &[f64] {
        &self.variance
    }

    fn image(&self, v: &[f64]) -> Image {
        Image::from_vec(self.width, self.height, v.iter().map(|&x| x as f32).collect())
    }

    /// The next frame, guided by its G-buffer, its history read through `motion`: the filtered
    /// image (module doc).
    pub fn push(&mut self, frame: &Image, gbuf: &GBuffer, motion: &Motion) -> Image {
        assert!(
            self.color_ref.is_none() || self.frames == 0,
            "svgf: a run pushes pairs from its first frame or never"
        );
        self.step(frame, None, gbuf, motion, true).0
    }

    /// `push` and its joint application to `reference` (module doc): (output, reference's output).
    /// A run pushes pairs from its first frame or never.
    pub fn push_pair(
        &mut self,
        frame: &Image,
        reference: &Image,
        gbuf: &GBuffer,
        motion: &Motion,
    ) -> (Image, Image) {
        assert!(
            self.color_ref.is_some() || self.frames == 0,
            "svgf: a run pushes pairs from its first frame or never"
        );
        let (out, r) = self.step(frame, Some(reference), gbuf, motion, true);
        (out, r.expect("a reference was given"))
    }

    /// `push` (or `push_pair` with `reference`) of a frame whose output nobody looks at: the state
    /// advances exactly as theirs does (the history is the first pass's output), without the
    /// passes after the first, which only the shown image needs.
    pub fn advance(&mut self, frame: &Image, reference: Option<&Image>, gbuf: &GBuffer, motion: &Motion) {
        assert!(
            self.color_ref.is_some() == reference.is_some() || self.frames == 0,
            "svgf: a run pushes pairs from its first frame or never"
        );
        self.step(frame, reference, gbuf, motion, false);
    }

    fn step(
        &mut self,
        frame: &Image,
        reference: Option<&Image>,
        gbuf: &GBuffer,
        motion: &Motion,
        shown: bool,
    ) -> (Image, Option<Image>) {
        assert!(
            frame.width == gbuf.width && frame.height == gbuf.height,
            "svgf: the frame is {}x{}, its G-buffer {}x{}",
            frame.width,
            frame.height,
            gbuf.width,
            gbuf.height
        );
        assert!(
            self.frames == 0 || (frame.width, frame.height) == (self.width, self.height),
            "svgf: the frame's size changed"
        );
        if let Some(r) = reference {
            assert!(r.same_size(frame), "svgf: the reference and the frame differ in size");
        }
        let p = self.params;
        let n = frame.len();
        let ids = p.id_test.then_some((self.ids.as_slice(), gbuf.primitive.as_slice()));
        let r = Reprojected::with(&self.length, &gbuf.coverage, motion, Extra { fallback: p.fallback, ids });
        // 1. Temporal accumulation of the colour, its moments (and the reference's colour).
        let mut color = vec![0.0f64; n];
        let mut moments = vec![[0.0f64; 2]; n];
        let mut color_ref = reference.map(|_| vec![0.0f64; n]);
        for i in 0..n {
            let x = frame.data[i] as f64;
            let xr = reference.map(|rf| rf.data[i] as f64);
            let len = r.length[i];
            let hist = if len > 0 { r.gather(&self.color, i) } else { None };
            match hist {
                None => {
                    color[i] = x;
                    moments[i] = [x, x * x];
                    if let (Some(c), Some(xr)) = (color_ref.as_mut(), xr) {
                        c[i] = xr;
                    }
                }
                Some(h) => {
                    let (ac, am) = (alpha_eff(p.alpha_color, len), alpha_eff(p.alpha_moments, len));
                    color[i] = h + ac * (x - h);
                    let (h1, h2) = gather2(&r, &self.moments, i);
                    moments[i] = [h1 + am * (x - h1), h2 + am * (x * x - h2)];
                    if let (Some(c), Some(xr)) = (color_ref.as_mut(), xr) {
                        let hr = r
                            .gather(self.color_ref.as_deref().expect("pairs from the first frame"), i)
                            .unwrap();
                        c[i] = hr + ac * (xr - hr);
                    }
                }
            }
        }
        let guide = Guide::new(gbuf, p.sigma_depth, p.sigma_normal);
        // 2. The variance: temporal, or spatial while the history is short.
        let variance = estimate_variance(&guide, &moments, &r.length);
        self.integrated = color.clone();
        self.variance = variance.clone();
        // 3. The à-trous passes; 4. the first one's output is the colour history.
        let iterations = p.iterations.unwrap_or_else(|| default_iterations(frame.width, frame.height));
        let run = if shown { iterations } else { iterations.min(1) };
        let floor = if p.relative_eps { RELATIVE_EPS * level(&guide, &color).powi(2) } else { 0.0 };
        let eps = Eps { relative: p.relative_eps, floor };
        let (mut c, mut var, mut cr) = (color, variance, color_ref);
        if iterations == 0 {
            self.color = c.clone();
            self.color_ref = cr.clone();
        }
        for it in 0..run {
            let (c2, var2, cr2) = pass(&guide, &c, &var, cr.as_deref(), it, p.sigma_luminance, eps);
            if it == 0 {
                self.color = c2.clone();
                self.color_ref = cr2.clone();
            }
            (c, var, cr) = (c2, var2, cr2);
        }
        // Background: the frame as it is (the passes copied it through already).
        self.moments = moments;
        self.length = r.length;
        if p.id_test {
            self.ids = gbuf.primitive.clone();
        }
        (self.width, self.height) = (frame.width, frame.height);
        self.frames += 1;
        let out = self.image(&c);
        let out_ref = cr.as_deref().map(|v| self.image(v));
        (out, out_ref)
    }
}

/// The history's two moments resampled at pixel `i` (which has taps).
fn gather2(r: &Reprojected, prev: &[[f64; 2]], i: usize) -> (f64, f64) {
    r.taps(i)
        .iter()
        .fold((0.0, 0.0), |(a, b), &(q, w)| (a + w * prev[q as usize][0], b + w * prev[q as usize][1]))
}

/// Per covered pixel max(0, μ₂ − μ₁²): of its temporal moments once its history has
/// `SPATIAL_VARIANCE_FRAMES` frames, else of its moments averaged over the 7 × 7 window with the
/// depth and normal weights (`Guide::weight`). 0 on background.
fn estimate_variance(guide: &Guide, moments: &[[f64; 2]], length: &[u32]) -> Vec<f64> {
    let (w, h) = (guide.width(), guide.height());
    let mut out = vec![0.0f64; moments.len()];
    out.par_chunks_mut(w.max(1) as usize).enumerate().for_each(|(y, row)| {
        let y = y as i64;
        for (x, o) in row.iter_mut().enumerate() {
            let x = x as i64;
            let p = (y * w + x) as usize;
            if !guide.is_covered(p) {
                continue;
            }
            let [m1, m2] = if length[p] >= SPATIAL_VARIANCE_FRAMES {
                moments[p]
            } else {
                let (mut s1, mut s2, mut ws) = (0.0f64, 0.0f64, 0.0f64);
                for dy in -SPATIAL_RADIUS..=SPATIAL_RADIUS {
                    for dx in -SPATIAL_RADIUS..=SPATIAL_RADIUS {
                        let (qx, qy) = (x + dx, y + dy);
                        if qx < 0 || qy < 0 || qx >= w || qy >= h {
                            continue;
                        }
                        let q = (qy * w + qx) as usize;
                        if !guide.is_covered(q) {
                            continue;
                        }
                        let wt = guide.weight(p, q, dx, dy);
                        s1 += wt * moments[q][0];
                        s2 += wt * moments[q][1];
                        ws += wt;
                    }
                }
                if ws > 0.0 { [s1 / ws, s2 / ws] } else { moments[p] }
            };
            *o = (m2 - m1 * m1).max(0.0);
        }
    });
    out
}

/// The 3 × 3 Gaussian (1/4, 1/2, 1/4)² of the variance over covered pixels, normalized by the
/// covered taps' weight: g₃ₓ₃(Var) of the luminance weight.
fn prefilter(guide: &Guide, var: &[f64]) -> Vec<f64> {
    const G: [f64; 3] = [0.25, 0.5, 0.25];
    let (w, h) = (guide.width(), guide.height());
    let mut out = vec![0.0f64; var.len()];
    out.par_chunks_mut(w.max(1) as usize).enumerate().for_each(|(y, row)| {
        let y = y as i64;
        for (x, o) in row.iter_mut().enumerate() {
            let x = x as i64;
            let p = (y * w + x) as usize;
            if !guide.is_covered(p) {
                continue;
            }
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
            *o = s / ws;
        }
    });
    out
}

type Pass = (Vec<f64>, Vec<f64>, Option<Vec<f64>>);

/// The luminance weight's ε: the fixed `LUMINANCE_EPS`, or that plus a variance `floor`.
#[derive(Debug, Clone, Copy)]
struct Eps {
    relative: bool,
    floor: f64,
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
fn level(guide: &Guide, c: &[f64]) -> f64 {
    let (s, k) =
        (0..c.len()).filter(|&p| guide.is_covered(p)).fold((0.0, 0usize), |(s, k), p| (s + c[p], k + 1));
    if k == 0 { 0.0 } else { s / k as f64 }
}

/// À-trous pass `it` of the colour `c` with variance `var` (and the reference's colour `cr` under
/// the same weights): the new colour, variance and reference colour.
fn pass(guide: &Guide, c: &[f64], var: &[f64], cr: Option<&[f64]>, it: u32, sigma_l: f64, eps: Eps) -> Pass {
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
                    let wl = (-(c[p] - c[q]).abs() / scale).exp();
                    let wt = g * wl;
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

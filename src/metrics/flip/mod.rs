//! LDR-FLIP, the per-pixel perceptual difference of Andersson, Nilsson, Akenine-Möller, Oskarsson,
//! Åström and Fairchild 2020, "FLIP: A Difference Evaluator for Alternating Images" (Proc. ACM
//! Comput. Graph. Interact. Tech. 3(2), article 15): what a viewer flipping between the reference
//! and the test at a given viewing distance notices. Real-time rendering reports it beside RMSE
//! (pbrt-v4's `imgtool diff --metric FLIP`, Falcor's FLIPPass, NVIDIA's flip-evaluator), and the two
//! can rank images differently: FLIP weighs error by the eye's contrast sensitivity and by the
//! edges and points it creates or removes, RMSE weighs every pixel's square alike.
//!
//! The pipeline, as flip-evaluator 1.7 computes it (`FLIP.h`, `LDR_FLIP`), here for AO, a linear grey
//! value v in [0, 1] taken as the linear RGB colour (v, v, v) — the package's
//! `evaluate(ref, test, "LDR", inputsRGB=False)`:
//! 1. clamp to [0, 1]; linear RGB → XYZ → YCxCz;
//! 2. colour: filter each channel by its contrast sensitivity function (separable Gaussians whose
//!    widths scale with the pixels per degree), back to linear RGB clamped to the gamut, to
//!    CIELAB with the Hunt adjustment, HyAB distance to the power 0.7, re-mapped to [0, 1];
//! 3. features: on the achromatic channel, edges (|∇(G∗Y)|) and points (|∇²-like second
//!    derivatives|) of a Gaussian of σ = 0.041° each side; their larger difference Δf, scaled by
//!    1/√2 and raised to 0.5;
//! 4. FLIP = colour error^(1 − Δf).
//!
//! Checked against flip-evaluator 1.7 on committed images (tests/stages/metrics_flip.rs); the
//! arithmetic is f32 in the package's order so that the maps agree to rounding.

mod color;
mod filter;

use crate::image::{Image, covered};
use color::{Color, Remap, clamp01, linear_rgb_to_xyz, xyz_to_ycxcz};
use filter::{FeatureTaps, SpatialTaps, columns, rows};

/// FLIP's default viewing condition: a 0.7 m wide 3840-pixel display seen from 0.7 m is
/// 3840·π/180 ≈ 67.02 pixels per degree, which the FLIP paper and tools call 67. hemilab uses 67
/// exactly (so results do not depend on how a constant was rounded); the committed check passes
/// `ppd = 67` to flip-evaluator explicitly.
pub const DEFAULT_PPD: f64 = 67.0;

/// One image's channels after the conversion to YCxCz (planar), and its normalized achromatic
/// channel (Y + 16)/116, which the feature detectors see.
struct Opponent {
    y: Vec<f32>,
    cx: Vec<f32>,
    cz: Vec<f32>,
    gray: Vec<f32>,
}

impl Opponent {
    fn new(image: &Image) -> Self {
        let n = image.len();
        let (mut y, mut cx, mut cz, mut gray) =
            (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        let (one_over_116, sixteen_over_116) = (1.0f32 / 116.0, 16.0f32 / 116.0);
        for &v in &image.data {
            let v = clamp01(v);
            let c = xyz_to_ycxcz(linear_rgb_to_xyz([v, v, v]));
            y.push(c[0]);
            cx.push(c[1]);
            cz.push(c[2]);
            gray.push(c[0] * one_over_116 + sixteen_over_116);
        }
        Opponent { y, cx, cz, gray }
    }

    /// The spatially filtered YCxCz of every pixel.
    fn filtered(&self, w: usize, taps: &SpatialTaps) -> Vec<Color> {
        let n = self.y.len();
        let mut h = [vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n]];
        let [hy, hcx, hz1, hz2] = &mut h;
        rows(&self.y, w, &[&taps.y], &mut [hy]);
        rows(&self.cx, w, &[&taps.cx], &mut [hcx]);
        rows(&self.cz, w, &[&taps.cz1, &taps.cz2], &mut [hz1, hz2]);
        let mut v = [vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n]];
        columns(&h[0], w, &taps.y, &mut v[0]);
        columns(&h[1], w, &taps.cx, &mut v[1]);
        columns(&h[2], w, &taps.cz1, &mut v[2]);
        columns(&h[3], w, &taps.cz2, &mut v[3]);
        (0..n).map(|i| [v[0][i], v[1][i], v[2][i] + v[3][i]]).collect()
    }

    /// Per pixel: (edge, point) responses, |(G′∗ₓ, G′∗ᵧ)| and |(G″∗ₓ, G″∗ᵧ)| of the grey channel.
    fn features(&self, w: usize, taps: &FeatureTaps) -> Vec<(f32, f32)> {
        let n = self.gray.len();
        let (mut hd, mut hdd, mut hg) = (vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n]);
        rows(&self.gray, w, &[&taps.dg, &taps.ddg, &taps.g], &mut [&mut hd, &mut hdd, &mut hg]);
        let (mut dx, mut ddx, mut dy, mut ddy) =
            (vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n], vec![0.0f32; n]);
        columns(&hd, w, &taps.g, &mut dx);
        columns(&hdd, w, &taps.g, &mut ddx);
        columns(&hg, w, &taps.dg, &mut dy);
        columns(&hg, w, &taps.ddg, &mut ddy);
        (0..n)
            .map(|i| ((dx[i] * dx[i] + dy[i] * dy[i]).sqrt(), (ddx[i] * ddx[i] + ddy[i] * ddy[i]).sqrt()))
            .collect()
    }
}

/// The LDR-FLIP error of every pixel of `test` against `reference` (grey, linear, clamped to
/// [0, 1] first) for a viewer at `ppd` pixels per degree: an image of the same size with values in
/// [0, 1], 0 where the two are indistinguishable. FLIP is symmetric in its two images (every step
/// compares them through absolute differences). Panics when the sizes differ or `ppd` is not a
/// positive finite number (callers validate the setting).
pub fn ldr_flip_map(reference: &Image, test: &Image, ppd: f64) -> Image {
    FlipReference::new(reference, ppd).map(test)
}

/// The half of LDR-FLIP that depends on the reference alone (its filtered colour and its feature
/// responses), made once for every test image measured against it: a real-time run measures
/// thousands of frames against a few references, and this half is about half of a map's time.
/// `map` gives `ldr_flip_map`'s image, bit for bit.
pub struct FlipReference {
    width: u32,
    height: u32,
    ppd: f32,
    /// The reference as given (`is_of` compares against it).
    image: Vec<f32>,
    color: Vec<Color>,
    features: Vec<(f32, f32)>,
}

impl FlipReference {
    /// Panics when `ppd` is not a positive finite number (callers validate the setting).
    pub fn new(reference: &Image, ppd: f64) -> Self {
        assert!(ppd.is_finite() && ppd > 0.0, "pixels per degree must be positive, got {ppd}");
        let (w, ppd) = (reference.width as usize, ppd as f32);
        let (color, features) = if reference.is_empty() {
            (Vec::new(), Vec::new())
        } else {
            let r = Opponent::new(reference);
            (r.filtered(w, &SpatialTaps::new(ppd)), r.features(w, &FeatureTaps::new(ppd)))
        };
        Self {
            width: reference.width,
            height: reference.height,
            ppd,
            image: reference.data.clone(),
            color,
            features,
        }
    }

    /// Whether this is `reference`'s at `ppd` (the same size and bits).
    pub fn is_of(&self, reference: &Image, ppd: f64) -> bool {
        self.ppd == ppd as f32
            && (self.width, self.height) == (reference.width, reference.height)
            && self.image.iter().zip(&reference.data).all(|(a, b)| a.to_bits() == b.to_bits())
    }

    /// Bytes it holds.
    pub fn bytes(&self) -> usize {
        4 * self.image.len() + 12 * self.color.len() + 8 * self.features.len()
    }

    /// The LDR-FLIP map of `test` against the reference (`ldr_flip_map`). Panics when the sizes differ.
    pub fn map(&self, test: &Image) -> Image {
        assert!((self.width, self.height) == (test.width, test.height), "FLIP compares images of one size");
        let (w, n) = (self.width as usize, test.len());
        if n == 0 {
            return Image::new(self.width, self.height);
        }
        let t = Opponent::new(test);
        let tc = t.filtered(w, &SpatialTaps::new(self.ppd));
        let tf = t.features(w, &FeatureTaps::new(self.ppd));
        let (rc, rf) = (&self.color, &self.features);
        let remap = Remap::new();
        let scale = 1.0f32 / 2.0f32.sqrt();
        let data = (0..n)
            .map(|i| {
                let color = remap.color_error(rc[i], tc[i]);
                let edge = (rf[i].0 - tf[i].0).abs();
                let point = (rf[i].1 - tf[i].1).abs();
                let larger = if edge > point { edge } else { point };
                let feature = (scale * larger).powf(0.5);
                color.powf(1.0 - feature)
            })
            .collect();
        Image::from_vec(self.width, self.height, data)
    }
}

/// Mean of a FLIP map over the covered pixels of `coverage` (the mean the FLIP tools report, over
/// the pixels that show a surface); NaN when none is covered. Panics when the sizes differ.
pub fn mean_flip(map: &Image, coverage: &Image) -> f64 {
    assert!(map.same_size(coverage), "the FLIP map and the coverage mask differ in size");
    let (mut n, mut sum) = (0usize, 0.0f64);
    for i in (0..map.len()).filter(|&i| covered(coverage, i)) {
        n += 1;
        sum += map.data[i] as f64;
    }
    if n == 0 { f64::NAN } else { sum / n as f64 }
}

//! The colour side of LDR-FLIP: linear RGB ↔ CIE XYZ ↔ YCxCz / CIELAB (D65), the Hunt
//! adjustment, the HyAB distance and its re-mapping to [0, 1]. Every constant and every operation
//! is in f32 and in the order flip-evaluator 1.7 (`FLIP.h`, `color3`) uses, so that hemilab's maps
//! agree with the package's to rounding: FLIP's colour error rises like d^0.7, and a different
//! rounding order changes small differences by more than the 1e-4 the test allows.

/// The D65 white in XYZ, and its reciprocal (FLIP's `DEFAULT_ILLUMINANT` / `INV_DEFAULT_ILLUMINANT`).
const ILLUMINANT: [f32; 3] = [0.950_428_55, 1.0, 1.088_900_3];
const INV_ILLUMINANT: [f32; 3] = [1.052_156_9, 1.0, 0.918_357_7];

/// Exponent of the colour difference (q_c), the break point (p_c) and the share of [0, 1] below it
/// (p_t), from the paper's Section 4.
const GQC: f32 = 0.7;
const GPC: f32 = 0.4;
const GPT: f32 = 0.95;

pub(super) type Color = [f32; 3];

pub(super) fn linear_rgb_to_xyz(c: Color) -> Color {
    // sRGB primaries, D65 (the fractions FLIP writes out, evaluated in f32 as it does).
    let a11 = 10135552.0f32 / 24577794.0;
    let a12 = 8788810.0f32 / 24577794.0;
    let a13 = 4435075.0f32 / 24577794.0;
    let a21 = 2613072.0f32 / 12288897.0;
    let a22 = 8788810.0f32 / 12288897.0;
    let a23 = 887015.0f32 / 12288897.0;
    let a31 = 1425312.0f32 / 73733382.0;
    let a32 = 8788810.0f32 / 73733382.0;
    let a33 = 70074185.0f32 / 73733382.0;
    [
        a11 * c[0] + a12 * c[1] + a13 * c[2],
        a21 * c[0] + a22 * c[1] + a23 * c[2],
        a31 * c[0] + a32 * c[1] + a33 * c[2],
    ]
}

fn xyz_to_linear_rgb(c: Color) -> Color {
    [
        3.241_003_3 * c[0] + -1.537_398_9 * c[1] + -0.498_615_86 * c[2],
        -0.969_224_33 * c[0] + 1.875_930_1 * c[1] + 0.041_554_224 * c[2],
        0.055_639_423 * c[0] + -0.204_011_2 * c[1] + 1.057_148_9 * c[2],
    ]
}

/// Opponent space in which FLIP filters: Y = 116·y − 16 (lightness-like, but linear in the
/// input), Cx = 500·(x − y) red–green, Cz = 200·(y − z) blue–yellow.
pub(super) fn xyz_to_ycxcz(c: Color) -> Color {
    let (x, y, z) = (c[0] * INV_ILLUMINANT[0], c[1] * INV_ILLUMINANT[1], c[2] * INV_ILLUMINANT[2]);
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

fn ycxcz_to_xyz(c: Color) -> Color {
    let y = (c[0] + 16.0) / 116.0;
    let cx = c[1] / 500.0;
    let cz = c[2] / 200.0;
    [(y + cx) * ILLUMINANT[0], y * ILLUMINANT[1], (y - cz) * ILLUMINANT[2]]
}

fn xyz_to_cielab(c: Color) -> Color {
    let delta = 6.0f32 / 29.0;
    let delta_square = delta * delta;
    let delta_cube = delta * delta_square;
    let factor = 1.0 / (3.0 * delta_square);
    let term = 4.0f32 / 29.0;
    let f = |v: f32| if v > delta_cube { v.powf(1.0 / 3.0) } else { factor * v + term };
    let (x, y, z) = (f(c[0] * INV_ILLUMINANT[0]), f(c[1] * INV_ILLUMINANT[1]), f(c[2] * INV_ILLUMINANT[2]));
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

/// FLIP's clamp: `Min(Max(v, 0), 1)` with its comparison order, so a NaN becomes 0.
pub(super) fn clamp01(v: f32) -> f32 {
    let v = if v > 0.0 { v } else { 0.0 };
    if v > 1.0 { 1.0 } else { v }
}

/// Hunt effect: chroma is perceived weaker at low lightness; FLIP scales a*, b* by L*/100.
fn hunt(c: Color) -> Color {
    [c[0], 0.01 * c[0] * c[1], 0.01 * c[0] * c[2]]
}

/// HyAB (Abasi et al. 2020): city-block distance in L*, Euclidean in (a*, b*).
fn hyab(r: Color, t: Color) -> f32 {
    let dl = (r[0] - t[0]).abs();
    let da = r[1] - t[1];
    let db = r[2] - t[2];
    dl + (da * da + db * db).sqrt()
}

/// The constants of the re-mapping: c_max (the HyAB distance, to the power q_c, between pure green
/// and pure blue, the largest in the sRGB gamut) and p_c·c_max.
#[derive(Clone, Copy)]
pub(super) struct Remap {
    cmax: f32,
    pccmax: f32,
}

impl Remap {
    pub(super) fn new() -> Self {
        let lab = |rgb: Color| hunt(xyz_to_cielab(linear_rgb_to_xyz(rgb)));
        let cmax = hyab(lab([0.0, 1.0, 0.0]), lab([0.0, 0.0, 1.0])).powf(GQC);
        Remap { cmax, pccmax: GPC * cmax }
    }

    /// The colour error of one pixel from the spatially filtered YCxCz of reference and test:
    /// back to linear RGB (clamped to the gamut), CIELAB with the Hunt adjustment, HyAB to the
    /// power q_c, then [0, p_c·c_max] → [0, p_t] and the rest → (p_t, 1].
    pub(super) fn color_error(&self, reference: Color, test: Color) -> f32 {
        let lab = |c: Color| {
            let rgb = xyz_to_linear_rgb(ycxcz_to_xyz(c));
            hunt(xyz_to_cielab(linear_rgb_to_xyz([clamp01(rgb[0]), clamp01(rgb[1]), clamp01(rgb[2])])))
        };
        let d = hyab(lab(reference), lab(test)).powf(GQC);
        if d < self.pccmax {
            d * (GPT / self.pccmax)
        } else {
            GPT + ((d - self.pccmax) / (self.cmax - self.pccmax)) * (1.0 - GPT)
        }
    }
}

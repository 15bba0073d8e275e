//! Colour maps: grey for AO (1 = white = open), a blue–white–red diverging map for signed error,
//! and magma for FLIP maps (the colour map FLIP's own tools draw its error maps in, so a reader who
//! knows them reads ours the same way).

/// Pixels outside the mask (no surface): a slate that is neither a grey AO value nor on the
/// diverging map, so "no data" never reads as "open" or "zero error".
pub const BACKGROUND: [u8; 3] = [96, 112, 128];

/// Blue end of the diverging map (error -scale: too dark, i.e. AO image below the reference).
/// The red end is the same colour with red and blue swapped, which makes the map exactly symmetric.
const BLUE: [f32; 3] = [36.0, 72.0, 204.0];

/// AO value in \[0, 1\] (clamped) as grey; NaN shows as the background colour.
pub fn grey(v: f32) -> [u8; 3] {
    if v.is_nan() {
        return BACKGROUND;
    }
    let g = crate::image::to_u8(v);
    [g, g, g]
}

/// Signed value `t` in [-1,1] (clamped): -1 blue, 0 white, +1 red; NaN is the background.
/// Linear in sRGB from white, so equal |t| are equally far from white on both sides.
pub fn diverging(t: f32) -> [u8; 3] {
    if t.is_nan() {
        return BACKGROUND;
    }
    let t = t.clamp(-1.0, 1.0);
    let a = t.abs();
    let mix = |end: f32| (255.0 + (end - 255.0) * a).round().clamp(0.0, 255.0) as u8;
    let [b0, b1, b2] = BLUE.map(mix);
    if t < 0.0 { [b0, b1, b2] } else { [b2, b1, b0] }
}

/// Magma at nine evenly spaced points (matplotlib's `magma`, sampled at 0, 1/8, …, 1): black
/// through purple and orange to pale yellow, perceptually ordered and readable in greyscale.
const MAGMA: [[f32; 3]; 9] = [
    [0.0, 0.0, 4.0],
    [28.0, 16.0, 68.0],
    [79.0, 18.0, 123.0],
    [129.0, 37.0, 129.0],
    [181.0, 54.0, 122.0],
    [229.0, 80.0, 100.0],
    [251.0, 135.0, 97.0],
    [254.0, 194.0, 135.0],
    [252.0, 253.0, 191.0],
];

/// A FLIP value in \[0, 1\] (clamped): 0 black (no perceived difference), 1 pale yellow; NaN is the
/// background. Linear between magma's nine samples.
pub fn magma(v: f32) -> [u8; 3] {
    if v.is_nan() {
        return BACKGROUND;
    }
    let x = v.clamp(0.0, 1.0) * (MAGMA.len() - 1) as f32;
    let i = (x.floor() as usize).min(MAGMA.len() - 2);
    let t = x - i as f32;
    let (a, b) = (MAGMA[i], MAGMA[i + 1]);
    [0, 1, 2].map(|k| (a[k] + (b[k] - a[k]) * t).round().clamp(0.0, 255.0) as u8)
}

/// The CSS of a left-to-right gradient through `colour` at `stops` points of \[`from`, `to`\]: a
/// colour bar a page draws without an image.
pub fn css_gradient(colour: impl Fn(f32) -> [u8; 3], from: f32, to: f32, stops: usize) -> String {
    let n = stops.max(2);
    let parts: Vec<String> = (0..n)
        .map(|i| {
            let t = i as f32 / (n - 1) as f32;
            let [r, g, b] = colour(from + (to - from) * t);
            format!("rgb({r},{g},{b}) {:.1}%", 100.0 * t)
        })
        .collect();
    format!("linear-gradient(to right,{})", parts.join(","))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diverging_maps_zero_to_white_and_is_symmetric() {
        assert_eq!(diverging(0.0), [255, 255, 255]);
        assert_eq!(diverging(-0.0), [255, 255, 255]);
        let white_dist = |c: [u8; 3]| c.iter().map(|&v| (255 - v as i32).pow(2)).sum::<i32>();
        for k in 1..=20 {
            let t = k as f32 / 20.0;
            let (pos, neg) = (diverging(t), diverging(-t));
            assert_eq!(pos, [neg[2], neg[1], neg[0]], "t = {t}: red side mirrors blue side");
            assert_eq!(white_dist(pos), white_dist(neg));
            assert!(pos[0] > pos[2] && neg[2] > neg[0], "t = {t}: + is red, - is blue: {pos:?} {neg:?}");
            assert!(white_dist(diverging(t)) > white_dist(diverging(t - 0.05)), "monotone away from white");
        }
        assert_eq!(diverging(7.0), diverging(1.0));
        assert_eq!(diverging(-7.0), diverging(-1.0));
        assert_eq!(diverging(f32::NAN), BACKGROUND);
    }

    #[test]
    fn grey_maps_one_to_white_and_clamps() {
        assert_eq!(grey(1.0), [255; 3]);
        assert_eq!(grey(0.0), [0; 3]);
        assert_eq!(grey(2.0), [255; 3]);
        assert_eq!(grey(f32::NAN), BACKGROUND);
    }

    #[test]
    fn magma_runs_dark_to_light_and_hits_its_samples() {
        assert_eq!(magma(0.0), [0, 0, 4]);
        assert_eq!(magma(1.0), [252, 253, 191]);
        assert_eq!(magma(0.5), [181, 54, 122]);
        assert_eq!(magma(-1.0), magma(0.0));
        assert_eq!(magma(f32::NAN), BACKGROUND);
        let lum = |c: [u8; 3]| 0.2126 * c[0] as f32 + 0.7152 * c[1] as f32 + 0.0722 * c[2] as f32;
        for k in 1..=40 {
            let (a, b) = (magma((k - 1) as f32 / 40.0), magma(k as f32 / 40.0));
            assert!(lum(b) >= lum(a), "magma's luminance rises: {a:?} -> {b:?}");
        }
    }

    #[test]
    fn a_css_gradient_names_its_end_colours() {
        let g = css_gradient(diverging, -1.0, 1.0, 3);
        assert!(g.starts_with("linear-gradient(to right,rgb(36,72,204) 0.0%"), "{g}");
        assert!(g.contains("rgb(255,255,255) 50.0%") && g.ends_with("rgb(204,72,36) 100.0%)"), "{g}");
    }
}

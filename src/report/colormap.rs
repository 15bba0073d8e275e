//! Colour maps: grey for AO (1 = white = open) and a blue–white–red diverging map for signed error.

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
}

//! The viewer's three layers of an image as 8-bit PNGs, in the report's tones: AO as linear grey
//! (`colormap::grey`, as the image tables draw it), the signed error image − reference on a
//! symmetric diverging scale (`colormap::diverging`), and a FLIP map in magma. Pixels outside the
//! coverage are transparent in the grey layer (the viewer's slate shows through) and the background
//! slate in the others, so "no surface" never reads as a value. The colour-mapped layers are
//! indexed PNGs of `LEVELS` steps of their map: a byte a pixel, a third of their RGB size (the
//! viewer of experiments/realtime.toml holds thousands of them).

use crate::image::{Image, covered, encode_png_grey_alpha, encode_png_indexed, to_u8};
use crate::report::colormap::{BACKGROUND, diverging, magma};

/// Steps of a colour map in an indexed layer (index `LEVELS` is the background): a step is 1/254
/// of the map's range, below what 8-bit colour shows anyway.
pub const LEVELS: usize = 255;

fn check(image: &Image, coverage: &Image) -> Result<(), String> {
    if !image.same_size(coverage) || image.data.len() != image.width as usize * image.height as usize {
        return Err(format!(
            "a {}x{} layer with a {}x{} coverage cannot be drawn",
            image.width, image.height, coverage.width, coverage.height
        ));
    }
    Ok(())
}

/// `image` through a colour map of `LEVELS` steps: `level` takes a value to \[0, 1\] (clamped),
/// `colour` a level to its colour; uncovered and NaN pixels are the background.
fn indexed(
    image: &Image,
    coverage: &Image,
    level: impl Fn(f32) -> f32,
    colour: impl Fn(f32) -> [u8; 3],
) -> Result<Vec<u8>, String> {
    check(image, coverage)?;
    let top = (LEVELS - 1) as f32;
    let mut palette: Vec<[u8; 3]> = (0..LEVELS).map(|k| colour(k as f32 / top)).collect();
    palette.push(BACKGROUND);
    let indices: Vec<u8> = (0..image.data.len())
        .map(|i| {
            let l = level(image.data[i]);
            if covered(coverage, i) && l.is_finite() {
                (l.clamp(0.0, 1.0) * top).round() as u8
            } else {
                LEVELS as u8
            }
        })
        .collect();
    encode_png_indexed(image.width, image.height, &palette, &indices)
}

/// The AO image: 1 = open = white, exactly as the report's grids; transparent where uncovered.
pub fn image_png(image: &Image, coverage: &Image) -> Result<Vec<u8>, String> {
    check(image, coverage)?;
    let la: Vec<u8> = (0..image.data.len())
        .flat_map(|i| if covered(coverage, i) { [to_u8(image.data[i]), 255] } else { [0, 0] })
        .collect();
    encode_png_grey_alpha(image.width, image.height, &la)
}

/// `image − reference` where `coverage` holds, NaN elsewhere.
pub fn signed_error(image: &Image, reference: &Image, coverage: &Image) -> Image {
    let data = (0..image.data.len())
        .map(|i| if covered(coverage, i) { image.data[i] - reference.data[i] } else { f32::NAN })
        .collect();
    Image::from_vec(image.width, image.height, data)
}

/// A signed error on ± `scale` (blue: the image darker than the reference, red: brighter).
pub fn error_png(error: &Image, coverage: &Image, scale: f32) -> Result<Vec<u8>, String> {
    if !(scale.is_finite() && scale > 0.0) {
        return Err(format!("an error scale must be a positive number, got {scale}"));
    }
    indexed(error, coverage, |e| (e / scale + 1.0) / 2.0, |l| diverging(2.0 * l - 1.0))
}

/// A FLIP map (0 = no perceived difference, 1 = the most).
pub fn flip_png(map: &Image, coverage: &Image) -> Result<Vec<u8>, String> {
    indexed(map, coverage, |v| v, magma)
}

/// One symmetric scale for signed errors shown together: the 99th percentile of |error| over their
/// covered pixels (NaN is uncovered), so a few outliers do not wash out the rest; never 0.
pub fn error_scale<'a>(errors: impl Iterator<Item = &'a Image>) -> f32 {
    crate::report::grid::robust_scale(errors)
}

/// The coverage two masks share.
pub fn both(a: &Image, b: &Image) -> Image {
    let data = (0..a.data.len()).map(|i| if covered(a, i) && covered(b, i) { 1.0 } else { 0.0 }).collect();
    Image::from_vec(a.width, a.height, data)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::backend::decode_png;

    #[test]
    fn layers_colour_covered_pixels_and_leave_the_rest_slate() {
        let img = Image::from_vec(3, 1, vec![1.0, 0.5, 0.0]);
        let reference = Image::from_vec(3, 1, vec![0.5, 0.5, 0.5]);
        let cov = Image::from_vec(3, 1, vec![1.0, 1.0, 0.0]);
        let rgba = ::image::load_from_memory(&image_png(&img, &cov).unwrap()).unwrap().to_rgba8();
        assert_eq!(rgba.dimensions(), (3, 1));
        let px: Vec<[u8; 4]> = rgba.pixels().map(|p| p.0).collect();
        assert_eq!(
            px,
            [[255, 255, 255, 255], [128, 128, 128, 255], [0, 0, 0, 0]],
            "uncovered is transparent"
        );
        let e = signed_error(&img, &reference, &cov);
        assert_eq!(e.data[..2], [0.5, 0.0]);
        assert!(e.data[2].is_nan());
        assert_eq!(error_scale([&e].into_iter()), 0.5);
        let (_, _, px) = decode_png(&error_png(&e, &cov, 0.5).unwrap());
        assert_eq!(px, [diverging(1.0), [255; 3], BACKGROUND]);
        let (_, _, px) = decode_png(&flip_png(&img, &cov).unwrap());
        assert_eq!(px, [magma(1.0), magma(127.0 / 254.0), BACKGROUND]);
        assert!(error_png(&e, &cov, 0.0).is_err() && image_png(&img, &Image::new(2, 1)).is_err());
        assert_eq!(both(&cov, &Image::from_vec(3, 1, vec![0.0, 1.0, 1.0])).data, [0.0, 1.0, 0.0]);
    }

    /// An indexed layer is the colour map to within one of its `LEVELS` steps.
    #[test]
    fn indexed_layers_follow_their_map_within_a_step() {
        let n = 1000;
        let e = Image::from_vec(n, 1, (0..n).map(|i| -1.2 + 2.4 * i as f32 / (n - 1) as f32).collect());
        let cov = Image::from_vec(n, 1, vec![1.0; n as usize]);
        let (_, _, px) = decode_png(&error_png(&e, &cov, 1.0).unwrap());
        // Half a step of the map (1/254 of its range) moves no channel by more than one unit, and the
        // rounding of each by at most one more.
        let far = |a: [u8; 3], b: [u8; 3]| (0..3).map(|k| (a[k] as i32 - b[k] as i32).abs()).max().unwrap();
        for (v, got) in e.data.iter().zip(&px) {
            assert!(far(*got, diverging(*v)) <= 2, "{v}: {got:?} against {:?}", diverging(*v));
        }
    }
}

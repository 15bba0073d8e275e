//! The viewer's three layers of an image as 8-bit PNGs, in the report's tones: AO as linear grey
//! (`colormap::grey`, as the image tables draw it), the signed error image − reference on a
//! symmetric diverging scale (`colormap::diverging`), and a FLIP map in magma. Pixels outside the
//! coverage are the background slate in every layer, so "no surface" never reads as a value.

use crate::image::{Image, covered, encode_png_rgb};
use crate::report::colormap::{BACKGROUND, diverging, grey, magma};

fn png(image: &Image, coverage: &Image, colour: impl Fn(f32) -> [u8; 3]) -> Result<Vec<u8>, String> {
    if !image.same_size(coverage) || image.data.len() != image.width as usize * image.height as usize {
        return Err(format!(
            "a {}x{} layer with a {}x{} coverage cannot be drawn",
            image.width, image.height, coverage.width, coverage.height
        ));
    }
    let rgb: Vec<u8> = (0..image.data.len())
        .flat_map(|i| if covered(coverage, i) { colour(image.data[i]) } else { BACKGROUND })
        .collect();
    encode_png_rgb(image.width, image.height, &rgb)
}

/// The AO image: 1 = open = white.
pub fn image_png(image: &Image, coverage: &Image) -> Result<Vec<u8>, String> {
    png(image, coverage, grey)
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
    png(error, coverage, |e| diverging(e / scale))
}

/// A FLIP map (0 = no perceived difference, 1 = the most).
pub fn flip_png(map: &Image, coverage: &Image) -> Result<Vec<u8>, String> {
    png(map, coverage, magma)
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
        let (w, h, px) = decode_png(&image_png(&img, &cov).unwrap());
        assert_eq!((w, h), (3, 1));
        assert_eq!(px, [[255; 3], grey(0.5), BACKGROUND]);
        let e = signed_error(&img, &reference, &cov);
        assert_eq!(e.data[..2], [0.5, 0.0]);
        assert!(e.data[2].is_nan());
        assert_eq!(error_scale([&e].into_iter()), 0.5);
        let (_, _, px) = decode_png(&error_png(&e, &cov, 0.5).unwrap());
        assert_eq!(px, [diverging(1.0), [255; 3], BACKGROUND]);
        let (_, _, px) = decode_png(&flip_png(&img, &cov).unwrap());
        assert_eq!(px, [magma(1.0), magma(0.5), BACKGROUND]);
        assert!(error_png(&e, &cov, 0.0).is_err() && image_png(&img, &Image::new(2, 1)).is_err());
        assert_eq!(both(&cov, &Image::from_vec(3, 1, vec![0.0, 1.0, 1.0])).data, [0.0, 1.0, 0.0]);
    }
}

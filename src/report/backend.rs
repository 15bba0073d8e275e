//! The one drawing backend every figure shares: the output formats (PNG, SVG), the font every label
//! uses, registered once from the bytes of the `dejavu` crate, and `render!`, which runs one drawing
//! routine on either format and returns the encoded bytes. A leaf of `report`: the figures import
//! it, it imports none of them.

use std::sync::Once;

/// Output format of a plot: PNG for the README and quick viewing, SVG for print-quality figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Png,
    Svg,
}

impl Format {
    /// The format a file name asks for, by its extension (case-insensitive); `None` if neither.
    pub fn from_extension(ext: &str) -> Option<Format> {
        match ext.to_ascii_lowercase().as_str() {
            "png" => Some(Format::Png),
            "svg" => Some(Format::Svg),
            _ => None,
        }
    }
}

/// The font family every label uses; registered once from the bytes of the `dejavu` crate.
pub(crate) const FONT: &str = "sans-serif";

/// Registers DejaVu Sans under [`FONT`]. plotters keeps a process-wide font table, so once is enough;
/// the bytes are compiled in, so this cannot fail at run time except on a corrupt crate.
pub(crate) fn ensure_fonts() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        use plotters::style::{FontStyle, register_font};
        let _ = register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
        let _ = register_font(FONT, FontStyle::Bold, dejavu::sans::bold());
    });
}

/// Runs `$draw(&root)` (generic over the backend) on a PNG or SVG backend of `$w` x `$h` pixels
/// and returns the encoded bytes; one drawing routine serves both formats.
macro_rules! render {
    ($format:expr, $w:expr, $h:expr, $draw:expr) => {{
        use plotters::prelude::*;
        $crate::report::backend::ensure_fonts();
        let (w, h): (u32, u32) = ($w, $h);
        match $format {
            $crate::report::backend::Format::Png => {
                let mut rgb = vec![255u8; w as usize * h as usize * 3];
                {
                    let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
                    root.fill(&WHITE).map_err(|e| e.to_string())?;
                    $draw(&root)?;
                    root.present().map_err(|e| e.to_string())?;
                }
                $crate::image::encode_png_rgb(w, h, &rgb)
            }
            $crate::report::backend::Format::Svg => {
                let mut svg = String::new();
                {
                    let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
                    root.fill(&WHITE).map_err(|e| e.to_string())?;
                    $draw(&root)?;
                    root.present().map_err(|e| e.to_string())?;
                }
                Ok(svg.into_bytes())
            }
        }
    }};
}
pub(crate) use render;

/// Test helper: checks the PNG signature and decodes, returning (width, height, RGB pixels).
#[cfg(test)]
pub(crate) fn decode_png(bytes: &[u8]) -> (u32, u32, Vec<[u8; 3]>) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    let img = ::image::load_from_memory_with_format(bytes, ::image::ImageFormat::Png)
        .expect("PNG decodes")
        .to_rgb8();
    let (w, h) = img.dimensions();
    (w, h, img.pixels().map(|p| p.0).collect())
}

#[cfg(test)]
mod tests {
    use super::Format;

    #[test]
    fn format_follows_the_extension_case_insensitively() {
        assert_eq!(Format::from_extension("PNG"), Some(Format::Png));
        assert_eq!(Format::from_extension("svg"), Some(Format::Svg));
        assert_eq!(Format::from_extension("jpg"), None);
        assert_eq!(Format::from_extension(""), None);
    }
}

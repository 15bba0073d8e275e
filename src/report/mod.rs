//! Turns results into what a reader of the paper looks at: point panels (Table 1, Figures 2-4),
//! AO image tables and their signed-error maps (Tables 2-3), convergence and banding plots, and one
//! offline HTML / Markdown page.
//!
//! Every function takes plain data (the records and `compare`'s comparisons; the drawing kit's own
//! types here) and returns bytes or a `String`: the report does no statistics of its own, never
//! touches the filesystem and never renders AO. `run/` and `advise/` return their files
//! (`outdir::File`), which the command writes through `outdir::write_files`; an image a figure
//! shows is read for it by the command (`outdir::record_image`).
//!
//! Text is drawn with plotters' `ab_glyph` rasterizer and the DejaVu Sans font shipped inside the
//! `dejavu` crate, so no system font library is needed at run time.

pub mod advise;
pub(crate) mod axis;
mod banding;
pub(crate) mod canvas;
pub mod colormap;
mod grid;
mod html;
pub(crate) mod plot;
mod points;
pub mod run;

pub use banding::banding_plot;
pub use grid::{GridCell, error_grid, image_grid};
pub use html::{
    Figure, METHOD_SUMMARY, Opening, Page, Table, html_page, html_page_opened, markdown_page,
    markdown_page_opened, markdown_table, referenced_files,
};
pub use plot::{Guide, Series, convergence_plot};
pub use points::{PointSet, directions, directions_of, figure_rows, point_panels};

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
        $crate::report::ensure_fonts();
        let (w, h): (u32, u32) = ($w, $h);
        match $format {
            $crate::report::Format::Png => {
                let mut rgb = vec![255u8; w as usize * h as usize * 3];
                {
                    let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
                    root.fill(&WHITE).map_err(|e| e.to_string())?;
                    $draw(&root)?;
                    root.present().map_err(|e| e.to_string())?;
                }
                $crate::image::encode_png_rgb(w, h, &rgb)
            }
            $crate::report::Format::Svg => {
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

//! The frame with its tiles outlined (`[tiles]`, `jobs::tiles`): where a run or advise measured a
//! big image. Each tile's window (interior and apron) is outlined in orange, its interior in red,
//! numbered in the order the tiles were chosen (best first), over a small grey image of the frame.

use super::canvas::{Align, Canvas};
use crate::image::Image;
use crate::render::Window;

const BACKGROUND: [u8; 3] = [200, 215, 235];
const INTERIOR: [u8; 3] = [220, 30, 30];
const APRON: [u8; 3] = [245, 150, 30];
/// Each preview pixel is drawn as `ZOOM` × `ZOOM` (nearest neighbour), so a 256 px preview of the
/// frame reads at 768 px.
const ZOOM: u32 = 3;

/// A PNG of `preview` (an image of the whole frame at any size, with its `coverage`; background
/// pixels drawn light blue) with the `interiors` and their `windows` (in the full frame's pixels,
/// `Window::full`) outlined and numbered.
pub fn tiles_png(
    preview: &Image,
    coverage: &Image,
    interiors: &[Window],
    windows: &[Window],
) -> Result<Vec<u8>, String> {
    let (pw, ph) = (preview.width, preview.height);
    let full = interiors.first().map_or([pw, ph], |w| w.full);
    let (w, h) = (pw * ZOOM, ph * ZOOM);
    let mut c = Canvas::new(w, h, BACKGROUND)?;
    for y in 0..ph {
        for x in 0..pw {
            let i = (y * pw + x) as usize;
            if coverage.data[i] > 0.5 {
                let c3 = super::colormap::grey(preview.data[i]);
                c.fill_rect((x * ZOOM) as i64, (y * ZOOM) as i64, ZOOM, ZOOM, c3);
            }
        }
    }
    // Full-frame pixels to canvas pixels.
    let sx = w as f64 / full[0].max(1) as f64;
    let sy = h as f64 / full[1].max(1) as f64;
    let rect = |r: &Window| {
        let (x0, y0) = ((r.x as f64 * sx).round() as i64, (r.y as f64 * sy).round() as i64);
        let x1 = ((r.x + r.width) as f64 * sx).round() as i64;
        let y1 = ((r.y + r.height) as f64 * sy).round() as i64;
        (x0, y0, (x1 - x0).max(1) as u32, (y1 - y0).max(1) as u32)
    };
    for win in windows {
        let (x, y, rw, rh) = rect(win);
        c.outline(x, y, rw, rh, APRON);
    }
    for (k, inner) in interiors.iter().enumerate() {
        let (x, y, rw, rh) = rect(inner);
        c.outline(x, y, rw, rh, INTERIOR);
        c.outline(x + 1, y + 1, rw.saturating_sub(2), rh.saturating_sub(2), INTERIOR);
        c.fill_rect(x + 2, y + 2, 14, 14, [255, 255, 255]);
        c.label(format!("{}", k + 1), x + 9, y + 9, 12.0, Align::Center, true);
    }
    c.into_png()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outlines_are_drawn_where_the_windows_are() {
        let preview = Image::from_vec(32, 18, vec![0.5; 32 * 18]);
        let coverage = Image::from_vec(32, 18, vec![1.0; 32 * 18]);
        let inner = Window::new([320, 180], 100, 60, 40, 40);
        let png = tiles_png(&preview, &coverage, &[inner], &[inner.grown(10)]).unwrap();
        let img = image::load_from_memory(&png).unwrap().to_rgb8();
        assert_eq!(img.dimensions(), (96, 54));
        // The interior's left edge, one canvas pixel outside x = 100 · 96/320 = 30 (rows 18..30).
        assert_eq!(img.get_pixel(29, 24).0, INTERIOR);
        assert_eq!(img.get_pixel(60, 5).0, super::super::colormap::grey(0.5));
    }
}

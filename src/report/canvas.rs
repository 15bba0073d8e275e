//! An RGB pixel buffer that image tables are composed on: pixels are copied in directly (exact,
//! nearest-neighbour) and labels are drawn with plotters' text rasterizer at the end.

use super::backend::{FONT, ensure_fonts};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Horizontal placement of a label relative to its anchor point.
#[derive(Clone, Copy)]
pub(crate) enum Align {
    Left,
    Center,
    Right,
}

struct Label {
    text: String,
    x: i32,
    y: i32,
    size: f64,
    align: Align,
    bold: bool,
}

pub(crate) struct Canvas {
    pub w: u32,
    pub h: u32,
    rgb: Vec<u8>,
    labels: Vec<Label>,
}

/// Width and height in pixels of `text` at `size` px, as plotters will lay it out.
pub(crate) fn text_size(text: &str, size: f64, bold: bool) -> (u32, u32) {
    ensure_fonts();
    let style = if bold { FontStyle::Bold } else { FontStyle::Normal };
    (FONT, size, style)
        .into_font()
        .box_size(text)
        .unwrap_or((text.len() as u32 * size as u32 / 2, size as u32))
}

impl Canvas {
    pub fn new(w: u32, h: u32, fill: [u8; 3]) -> Result<Self, String> {
        if w == 0 || h == 0 || w as u64 * h as u64 > 200_000_000 {
            return Err(format!("canvas of {w}x{h} pixels is empty or too large"));
        }
        let rgb = fill.iter().copied().cycle().take(w as usize * h as usize * 3).collect();
        Ok(Self { w, h, rgb, labels: Vec::new() })
    }

    pub fn put(&mut self, x: i64, y: i64, c: [u8; 3]) {
        if x >= 0 && y >= 0 && (x as u32) < self.w && (y as u32) < self.h {
            let i = (y as usize * self.w as usize + x as usize) * 3;
            self.rgb[i..i + 3].copy_from_slice(&c);
        }
    }

    pub fn fill_rect(&mut self, x: i64, y: i64, w: u32, h: u32, c: [u8; 3]) {
        for yy in y..y + h as i64 {
            for xx in x..x + w as i64 {
                self.put(xx, yy, c);
            }
        }
    }

    /// A 1-px outline just outside the rectangle, so it never covers image pixels.
    pub fn outline(&mut self, x: i64, y: i64, w: u32, h: u32, c: [u8; 3]) {
        self.fill_rect(x - 1, y - 1, w + 2, 1, c);
        self.fill_rect(x - 1, y + h as i64, w + 2, 1, c);
        self.fill_rect(x - 1, y - 1, 1, h + 2, c);
        self.fill_rect(x + w as i64, y - 1, 1, h + 2, c);
    }

    /// Queues a label whose vertical centre is at `y`.
    pub fn label(&mut self, text: impl Into<String>, x: i64, y: i64, size: f64, align: Align, bold: bool) {
        self.labels.push(Label { text: text.into(), x: x as i32, y: y as i32, size, align, bold });
    }

    /// Draws the queued labels and encodes the buffer as PNG.
    pub fn into_png(mut self) -> Result<Vec<u8>, String> {
        ensure_fonts();
        {
            let root = BitMapBackend::with_buffer(&mut self.rgb, (self.w, self.h)).into_drawing_area();
            for l in &self.labels {
                let h = match l.align {
                    Align::Left => HPos::Left,
                    Align::Center => HPos::Center,
                    Align::Right => HPos::Right,
                };
                let style = if l.bold { FontStyle::Bold } else { FontStyle::Normal };
                let font = (FONT, l.size, style).into_font().color(&BLACK).pos(Pos::new(h, VPos::Center));
                root.draw_text(&l.text, &font, (l.x, l.y)).map_err(|e| e.to_string())?;
            }
            root.present().map_err(|e| e.to_string())?;
        }
        crate::image::encode_png_rgb(self.w, self.h, &self.rgb)
    }
}

//! A rectangle of a bigger image: what a render of tiles renders instead of the whole frame.
//!
//! A window's pixels are those of the full image, bit for bit: every primary ray is the full
//! image's (the raster is made for the full width × height) and every sampler reads the pixel's
//! absolute coordinates and index y · full width + x, so that blue-noise and spatiotemporal masks
//! tile by the full image's pixel grid as an engine's would. Only which pixels are rendered
//! changes. Plain data; `Window::full` is the whole image.

use crate::image::Image;

/// A `width` × `height` rectangle at (`x`, `y`) (its top-left pixel) of a `full` image.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Window {
    /// The whole image's [width, height].
    pub full: [u32; 2],
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl Window {
    /// The whole `width` × `height` image.
    pub fn full(width: u32, height: u32) -> Self {
        Window { full: [width, height], x: 0, y: 0, width, height }
    }

    /// The rectangle at (x, y) of `width` × `height` pixels of a `full` image, clipped to the image.
    pub fn new(full: [u32; 2], x: u32, y: u32, width: u32, height: u32) -> Self {
        let x = x.min(full[0]);
        let y = y.min(full[1]);
        Window { full, x, y, width: width.min(full[0] - x), height: height.min(full[1] - y) }
    }

    /// This rectangle grown by `apron` pixels on every side, clipped to the image.
    pub fn grown(&self, apron: u32) -> Self {
        let x = self.x.saturating_sub(apron);
        let y = self.y.saturating_sub(apron);
        let right = (self.x + self.width).saturating_add(apron).min(self.full[0]);
        let bottom = (self.y + self.height).saturating_add(apron).min(self.full[1]);
        Window { full: self.full, x, y, width: right - x, height: bottom - y }
    }

    pub fn is_full(&self) -> bool {
        (self.x, self.y, [self.width, self.height]) == (0, 0, self.full)
    }

    pub fn pixels(&self) -> u64 {
        self.width as u64 * self.height as u64
    }

    /// Whether the absolute pixel (x, y) is inside.
    pub fn contains(&self, x: u32, y: u32) -> bool {
        x >= self.x && y >= self.y && x < self.x + self.width && y < self.y + self.height
    }

    /// Whether `inner` lies wholly inside this window (same full image).
    pub fn covers(&self, inner: &Window) -> bool {
        self.full == inner.full
            && inner.x >= self.x
            && inner.y >= self.y
            && inner.x + inner.width <= self.x + self.width
            && inner.y + inner.height <= self.y + self.height
    }

    /// Whether two rectangles of one image share a pixel.
    pub fn overlaps(&self, other: &Window) -> bool {
        self.x < other.x + other.width
            && other.x < self.x + self.width
            && self.y < other.y + other.height
            && other.y < self.y + self.height
    }

    /// The index in this window's row-major image of the absolute pixel (x, y) (inside).
    pub fn index(&self, x: u32, y: u32) -> usize {
        (y - self.y) as usize * self.width as usize + (x - self.x) as usize
    }

    /// The pixels of `image` (this window's own, `width` × `height`) that `inner` covers, as an
    /// image of `inner`'s size. Panics if `inner` is not inside (a bug).
    pub fn crop<T: Copy>(&self, data: &[T], inner: &Window) -> Vec<T> {
        assert!(self.covers(inner), "crop: {inner:?} is not inside {self:?}");
        assert_eq!(data.len() as u64, self.pixels(), "crop: an image of another size than {self:?}");
        let mut out = Vec::with_capacity(inner.pixels() as usize);
        for y in inner.y..inner.y + inner.height {
            let start = self.index(inner.x, y);
            out.extend_from_slice(&data[start..start + inner.width as usize]);
        }
        out
    }

    /// `crop` of an `Image`.
    pub fn crop_image(&self, image: &Image, inner: &Window) -> Image {
        assert_eq!((image.width, image.height), (self.width, self.height), "crop: image of another size");
        Image::from_vec(inner.width, inner.height, self.crop(&image.data, inner))
    }

    /// `x,y+WxH/FWxFH`: the rectangle and its image, as results and manifests name it.
    pub fn canonical(&self) -> String {
        format!("{},{}+{}x{}/{}x{}", self.x, self.y, self.width, self.height, self.full[0], self.full[1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grown_windows_are_clipped_to_the_image_and_crops_read_rows() {
        let w = Window::new([100, 50], 10, 40, 20, 20);
        assert_eq!((w.width, w.height), (20, 10), "clipped at the bottom");
        let g = w.grown(15);
        assert_eq!((g.x, g.y, g.width, g.height), (0, 25, 45, 25));
        assert!(g.covers(&w) && !w.covers(&g) && g.overlaps(&w));
        assert!(Window::full(100, 50).is_full() && !g.is_full());
        let data: Vec<u32> = (0..g.pixels() as u32).collect();
        let c = g.crop(&data, &w);
        assert_eq!(c.len(), 200);
        assert_eq!(c[0], g.index(10, 40) as u32);
        assert_eq!(c[20], g.index(10, 41) as u32);
        assert_eq!(w.canonical(), "10,40+20x10/100x50");
    }
}

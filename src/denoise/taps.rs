//! A frame's à-trous taps, kept while frames share their G-buffer.
//!
//! Why: a static camera's frames all filter under one G-buffer, and so does every series of it a
//! worker runs after another, yet the edge-stopping weights of every tap (an exp and a 128th power,
//! `Guide::atrous_taps`) were made anew for each frame of each series: about 30 % of the real-time
//! run's time (the kitchen at 320x180, two replicates: 2 min 19 s, 1 min 36 s with the weights
//! stubbed out). A pass's taps are now read from a table made once per G-buffer, σ and pass, kept
//! per thread (a worker runs one series at a time). A table is made on the second request for the
//! same key within the last few, so a moving camera's frames, each asked for once by a series, are
//! not copied into tables nobody reads again. The table is made by `Guide::atrous_taps` itself, so a
//! filtered image is bit for bit what it was.

use super::edges::{Guide, Taps};
use rayon::prelude::*;
use std::cell::RefCell;
use std::sync::Arc;

/// Taps a pixel has at most (the 5 × 5 kernel).
const KERNEL: usize = 25;
/// Tables a thread keeps: SVGF's two passes and another filter's two under other σ.
const TABLES: usize = 4;
/// Recent keys a thread remembers without a table.
const SEEN: usize = 8;

/// One pass's taps of every pixel of a frame: `count[p]` taps at `KERNEL * p ..`.
struct Table {
    key: (u64, u32),
    count: Vec<u8>,
    pixel: Vec<u32>,
    weight: Vec<f64>,
}

#[derive(Default)]
struct Cache {
    tables: Vec<Arc<Table>>,
    seen: Vec<(u64, u32)>,
}

thread_local! {
    static CACHE: RefCell<Cache> = RefCell::new(Cache::default());
}

/// Pass `iteration` of the à-trous filter under `guide`: the taps of any covered pixel, from a kept
/// table where there is one.
pub struct Pass<'g, 'a> {
    guide: &'g Guide<'a>,
    iteration: u32,
    table: Option<Arc<Table>>,
}

impl<'g, 'a> Pass<'g, 'a> {
    pub fn new(guide: &'g Guide<'a>, iteration: u32) -> Self {
        let key = (guide.content_key(), iteration);
        let table = CACHE.with_borrow_mut(|c| {
            if let Some(i) = c.tables.iter().position(|t| t.key == key) {
                let t = c.tables.remove(i);
                c.tables.insert(0, t.clone());
                return Some(t);
            }
            if !c.seen.contains(&key) {
                c.seen.insert(0, key);
                c.seen.truncate(SEEN);
                return None;
            }
            let t = Arc::new(build(guide, key));
            c.tables.insert(0, t.clone());
            c.tables.truncate(TABLES);
            Some(t)
        });
        Self { guide, iteration, table }
    }

    /// `Guide::atrous_taps(x, y, iteration, out)`: the same taps, the same weights, in the same order.
    #[inline]
    pub fn taps(&self, x: i64, y: i64, out: &mut Taps) -> usize {
        let Some(t) = &self.table else { return self.guide.atrous_taps(x, y, self.iteration, out) };
        let p = (y * self.guide.width() + x) as usize;
        let k = t.count[p] as usize;
        let at = KERNEL * p;
        for (o, (&q, &w)) in out.iter_mut().zip(t.pixel[at..at + k].iter().zip(&t.weight[at..at + k])) {
            *o = (q as usize, w);
        }
        k
    }
}

/// The table of `key`'s pass: every covered pixel's taps (uncovered pixels have none).
fn build(guide: &Guide, key: (u64, u32)) -> Table {
    let (w, h) = (guide.width() as usize, guide.height() as usize);
    let mut count = vec![0u8; w * h];
    let mut pixel = vec![0u32; KERNEL * w * h];
    let mut weight = vec![0.0f64; KERNEL * w * h];
    count
        .par_chunks_mut(w.max(1))
        .zip(pixel.par_chunks_mut((KERNEL * w).max(1)))
        .zip(weight.par_chunks_mut((KERNEL * w).max(1)))
        .enumerate()
        .for_each(|(y, ((count, pixel), weight))| {
            let mut taps: Taps = [(0, 0.0); KERNEL];
            for x in 0..w {
                if !guide.is_covered(y * w + x) {
                    continue;
                }
                let k = guide.atrous_taps(x as i64, y as i64, key.1, &mut taps);
                count[x] = k as u8;
                for (j, &(q, g)) in taps[..k].iter().enumerate() {
                    pixel[KERNEL * x + j] = q as u32;
                    weight[KERNEL * x + j] = g;
                }
            }
        });
    Table { key, count, pixel, weight }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::render::GBuffer;
    use glam::Vec3;

    fn gbuffer(w: u32, h: u32, tilt: f32) -> GBuffer {
        let n = (w * h) as usize;
        let depth: Vec<f32> =
            (0..n).map(|i| 1.0 + ((i % 7) as f32) * 0.01 + tilt * (i / w as usize) as f32).collect();
        let normal: Vec<Vec3> =
            (0..n).map(|i| Vec3::new(0.1 * ((i % 5) as f32 - 2.0), 0.0, 1.0).normalize()).collect();
        let coverage: Vec<f32> = (0..n).map(|i| if i % 11 == 3 { 0.0 } else { 1.0 }).collect();
        GBuffer {
            width: w,
            height: h,
            depth: Image::from_vec(w, h, depth),
            normal,
            coverage: Image::from_vec(w, h, coverage),
            primitive: Vec::new(),
        }
    }

    #[test]
    fn a_kept_tables_taps_are_the_guides_bit_for_bit() {
        let (g1, g2) = (gbuffer(23, 17, 0.0), gbuffer(23, 17, 0.05));
        for round in 0..3 {
            for gb in [&g1, &g2] {
                let guide = Guide::new(gb, 1.0, 128.0);
                for it in 0..2 {
                    let pass = Pass::new(&guide, it);
                    // A table from the second request of a key on.
                    assert_eq!(pass.table.is_some(), round > 0, "round {round}, pass {it}");
                    let (mut a, mut b): (Taps, Taps) = ([(0, 0.0); KERNEL], [(0, 0.0); KERNEL]);
                    for y in 0..17 {
                        for x in 0..23 {
                            if !guide.is_covered(y * 23 + x) {
                                continue;
                            }
                            let k = pass.taps(x as i64, y as i64, &mut a);
                            assert_eq!(k, guide.atrous_taps(x as i64, y as i64, it, &mut b));
                            for j in 0..k {
                                assert_eq!(a[j].0, b[j].0);
                                assert_eq!(a[j].1.to_bits(), b[j].1.to_bits());
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn another_sigma_or_g_buffer_is_another_key() {
        let (g1, g2) = (gbuffer(9, 7, 0.0), gbuffer(9, 7, 0.05));
        let key = |g, sd, sn| Guide::new(g, sd, sn).content_key();
        let copy = g1.clone();
        assert_eq!(key(&g1, 1.0, 128.0), key(&copy, 1.0, 128.0));
        assert_ne!(key(&g1, 1.0, 128.0), key(&g2, 1.0, 128.0));
        assert_ne!(key(&g1, 1.0, 128.0), key(&g1, 2.0, 128.0));
        assert_ne!(key(&g1, 1.0, 128.0), key(&g1, 1.0, 64.0));
    }
}

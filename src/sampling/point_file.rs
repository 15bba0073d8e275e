//! A point set the user brings: the loader (`load::points`) reads it — a `.npy` array of
//! shape N × 2 or P × N × 2, or a text file of one `x y` per line as UTK writes — and registers it
//! as a sequence ([`super::register_file`]) that holds the points.
//!
//! Pixel p (its index y · width + x) reads set p mod P (one set: every pixel the same), and its
//! first `count` points. The seed modes act as on R2 ([`super::r2`]), the common way
//! (`PixelSet::keyed`): the set is Cranley–Patterson shifted (Cranley & Patterson 1976) by one
//! offset per run under `static` (so replicates differ), by a fresh one per pixel under `shift`
//! (unbiased per pixel, whatever the set), and `rotation`, the masks, the engine patterns and
//! textures add their offsets to the run's shifted set.

use super::hash::{fix_add, fix_to_f32, hash};
use super::registry::{PixelSet, PointSequence, SequenceInfo};
use glam::Vec2;

/// A file's points on the 24-bit grid: `sets` sets of `per_set` points each.
pub struct PointFile {
    info: SequenceInfo,
    points: Vec<(u32, u32)>,
    per_set: u32,
    sets: u32,
}

impl PointFile {
    /// `name` is its results name (`points:PATH#hash8`), `label` its words in the report;
    /// `points` holds `sets` × `per_set` points, set-major, each in [0, 1)² on the 24-bit grid.
    pub fn new(name: &str, label: &str, points: Vec<(u32, u32)>, per_set: u32) -> Self {
        let sets = (points.len() as u32 / per_set.max(1)).max(1);
        let leak = |s: &str| -> &'static str { Box::leak(s.to_string().into_boxed_str()) };
        let info = SequenceInfo {
            name: leak(name),
            label: leak(label),
            words: &[],
            fresh_per_pixel: false,
            shipped: None,
        };
        Self { info, points, per_set: per_set.max(1), sets }
    }

    pub fn per_set(&self) -> u32 {
        self.per_set
    }

    pub fn sets(&self) -> u32 {
        self.sets
    }
}

impl PointSequence for PointFile {
    fn info(&self) -> &SequenceInfo {
        &self.info
    }

    fn max_count(&self) -> Option<u32> {
        Some(self.per_set)
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        let (key, dx, dy) = set.keyed();
        let (ox, oy) = ((hash(key, 1) >> 40) as u32, (hash(key, 2) >> 40) as u32);
        let base = (set.pixel % self.sets as u64) as usize * self.per_set as usize;
        for (i, p) in out.iter_mut().enumerate() {
            // More points than the set holds is refused where counts are read (spec, command
            // line); here it wraps rather than panics.
            let (x, y) = self.points[base + i % self.per_set as usize];
            let (x, y) = (fix_add(fix_add(x, ox), dx), fix_add(fix_add(y, oy), dy));
            *p = Vec2::new(fix_to_f32(x), fix_to_f32(y));
        }
    }
}

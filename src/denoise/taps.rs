//! A frame's à-trous taps, kept process-wide while they are asked for again.
//!
//! Why: the edge-stopping weights of every tap (an exp and a 128th power, `Guide::atrous_taps`)
//! depend only on the G-buffer, σ and the pass, yet every frame of every series made them anew:
//! about 30 % of the real-time run's time (the kitchen at 320x180, two replicates: 2 min 19 s,
//! 1 min 36 s with the weights stubbed out). A static camera's frames share one G-buffer, and so
//! do a moving camera's: frame f of a camera path has the same G-buffer in every series of that
//! path (`jobs::guides::CameraFrames`), 72 series a path in `experiments/realtime.toml`. A pass's
//! taps are read from a table made once per (G-buffer, σ, pass), kept in one cache that every
//! worker shares. The table is made by `Guide::atrous_taps` itself, so a filtered image is bit
//! for bit what it was.
//!
//! **What is kept.** A table is made on the second request of its key among the last `SEEN` keys
//! asked for, so that frames asked for once (a one-off filter) are not copied into tables nobody
//! reads again. A table holds per pixel a 25-bit mask of its taps (of the 5 × 5 kernel: those
//! inside the image on covered pixels) and where its weights start, then the weights (f64, as
//! made): 8 bytes a pixel and 8 a tap, about 12 MB at 320x180 (a frame at 1080p: 420 MB).
//!
//! **The bound**: at most `DEFAULT_BOUND` bytes of tables (4 GiB). The real-time run's working set
//! is every pass each frame of each path needs: pass 0 of each of the 64 frames (every SVGF run
//! advances through it) and passes 1–4 of the 12 shown frames (`svgf`, `svgf:5`, `atrous`), about
//! 112 tables a path, 1.3 GB at 320x180; three scenes' orbits and their static cameras fit. Once
//! full, a new table is not kept: the run asks for its paths' frames cycle after cycle in a
//! shuffled order (the timing protocol's passes), and evicting the least recently used table of a
//! cycle larger than the cache would evict the very one asked for next, every request a miss;
//! keeping the first tables made serves a fixed share of the requests instead. Nothing is ever
//! evicted: a process filters one run's G-buffers.

use super::edges::{Guide, Taps};
use rayon::prelude::*;
use std::cell::RefCell;
use std::collections::{HashMap, HashSet, VecDeque};
use std::sync::{Arc, Mutex, OnceLock};

/// Taps a pixel has at most (the 5 × 5 kernel).
const KERNEL: usize = 25;
/// Recent keys the cache remembers without a table (a request's key among them makes the table).
const SEEN: usize = 4096;
/// The process-wide cache's bound on the bytes of its tables: 4 GiB (module doc).
pub const DEFAULT_BOUND: usize = 4 << 30;

/// A table's key: the guide's `content_key` and the pass.
type Key = (u64, u32);

/// One pass's taps of every pixel of a frame: pixel p has the taps of the bits of `mask[p]`
/// (bit 5·ky + kx of the 5 × 5 kernel, in the kernel's row-major order, `Guide::atrous_taps`'s),
/// their weights at `weight[start[p]..]`.
struct Table {
    mask: Vec<u32>,
    start: Vec<u32>,
    weight: Vec<f64>,
}

impl Table {
    /// What the table takes in memory.
    fn bytes(&self) -> usize {
        std::mem::size_of::<Self>() + 4 * self.mask.len() + 4 * self.start.len() + 8 * self.weight.len()
    }
}

/// Tables by key, at most `bound` bytes of them (module doc).
pub struct TapCache {
    bound: usize,
    inner: Mutex<Inner>,
}

#[derive(Default)]
struct Inner {
    tables: HashMap<Key, Arc<Table>>,
    bytes: usize,
    seen: HashSet<Key>,
    order: VecDeque<Key>,
}

impl TapCache {
    /// An empty cache that keeps at most `bound` bytes of tables (0: none).
    pub fn new(bound: usize) -> Self {
        Self { bound, inner: Mutex::new(Inner::default()) }
    }

    /// The cache every filter of the process reads (`DEFAULT_BOUND`), unless the thread runs
    /// under `with_cache`.
    fn global() -> Arc<TapCache> {
        static GLOBAL: OnceLock<Arc<TapCache>> = OnceLock::new();
        GLOBAL.get_or_init(|| Arc::new(TapCache::new(DEFAULT_BOUND))).clone()
    }

    /// Bytes of the tables kept.
    pub fn bytes(&self) -> usize {
        self.lock().bytes
    }

    /// Tables kept.
    pub fn tables(&self) -> usize {
        self.lock().tables.len()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Inner> {
        self.inner.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The table of `guide`'s pass `iteration`: kept, or made now if its key was asked for
    /// recently (kept if it fits), or `None` (the caller computes the taps itself).
    fn table(&self, guide: &Guide, iteration: u32) -> Option<Arc<Table>> {
        let key = (guide.content_key(), iteration);
        {
            let mut c = self.lock();
            if let Some(t) = c.tables.get(&key) {
                return Some(t.clone());
            }
            if c.seen.insert(key) {
                c.order.push_back(key);
                if c.order.len() > SEEN {
                    let old = c.order.pop_front().expect("not empty");
                    c.seen.remove(&old);
                }
                return None;
            }
        }
        // Made outside the lock: another worker may make the same table meanwhile; the first kept
        // stays (both are the same bits).
        let t = Arc::new(build(guide, iteration));
        let mut c = self.lock();
        if let Some(kept) = c.tables.get(&key) {
            return Some(kept.clone());
        }
        let bytes = t.bytes();
        if c.bytes + bytes <= self.bound {
            c.bytes += bytes;
            c.tables.insert(key, t.clone());
        }
        Some(t)
    }
}

thread_local! {
    /// The cache this thread's filters read instead of the process's (`with_cache`).
    static SCOPED: RefCell<Option<Arc<TapCache>>> = const { RefCell::new(None) };
}

/// Runs `f` with every filter this thread starts reading `cache` instead of the process's: a test
/// compares filters with a cache of bound 0 (no table kept: every tap computed) and without.
pub fn with_cache<R>(cache: &Arc<TapCache>, f: impl FnOnce() -> R) -> R {
    let before = SCOPED.with_borrow_mut(|s| s.replace(cache.clone()));
    struct Restore(Option<Arc<TapCache>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            SCOPED.with_borrow_mut(|s| *s = self.0.take());
        }
    }
    let _restore = Restore(before);
    f()
}

/// Pass `iteration` of the à-trous filter under `guide`: the taps of any covered pixel, from a kept
/// table where there is one.
pub struct Pass<'g, 'a> {
    guide: &'g Guide<'a>,
    iteration: u32,
    table: Option<Arc<Table>>,
    /// Per kernel position (bit), q − p.
    offset: [i64; KERNEL],
}

impl<'g, 'a> Pass<'g, 'a> {
    pub fn new(guide: &'g Guide<'a>, iteration: u32) -> Self {
        let cache = SCOPED.with_borrow(|s| s.clone()).unwrap_or_else(TapCache::global);
        let table = cache.table(guide, iteration);
        let step = 1i64 << iteration.min(30);
        let offset = std::array::from_fn(|j| {
            let (ky, kx) = ((j / 5) as i64 - 2, (j % 5) as i64 - 2);
            ky * step * guide.width() + kx * step
        });
        Self { guide, iteration, table, offset }
    }

    /// `Guide::atrous_taps(x, y, iteration, out)`: the same taps, the same weights, in the same order.
    #[inline]
    pub fn taps(&self, x: i64, y: i64, out: &mut Taps) -> usize {
        let Some(t) = &self.table else { return self.guide.atrous_taps(x, y, self.iteration, out) };
        let p = y * self.guide.width() + x;
        let (mut m, at) = (t.mask[p as usize], t.start[p as usize] as usize);
        let mut k = 0;
        while m != 0 {
            let j = m.trailing_zeros() as usize;
            out[k] = ((p + self.offset[j]) as usize, t.weight[at + k]);
            k += 1;
            m &= m - 1;
        }
        k
    }
}

/// A kept table as a walk over several pixels at once reads it (`svgf_atrous`'s four lanes): per
/// pixel the mask of its taps (0: uncovered) and where its weights start, the weights, and per
/// kernel position (bit) q − p.
pub struct Lanes<'t> {
    pub mask: &'t [u32],
    pub start: &'t [u32],
    pub weight: &'t [f64],
    pub offset: &'t [i64; KERNEL],
}

impl Pass<'_, '_> {
    /// The kept table's `Lanes`, or `None` where the taps are computed (`taps` computes them).
    pub fn lanes(&self) -> Option<Lanes<'_>> {
        self.table.as_deref().map(|t| Lanes {
            mask: &t.mask,
            start: &t.start,
            weight: &t.weight,
            offset: &self.offset,
        })
    }
}

/// The table of `guide`'s pass `iteration`: every covered pixel's taps (uncovered pixels have none).
fn build(guide: &Guide, iteration: u32) -> Table {
    let (w, h) = (guide.width() as usize, guide.height() as usize);
    let step = 1i64 << iteration.min(30);
    // Per row: each pixel's mask and the row's weights.
    let rows: Vec<(Vec<u32>, Vec<f64>)> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut taps: Taps = [(0, 0.0); KERNEL];
            let (mut mask, mut weight) = (vec![0u32; w], Vec::with_capacity(KERNEL * w));
            for (x, m) in mask.iter_mut().enumerate() {
                if !guide.is_covered(y * w + x) {
                    continue;
                }
                let k = guide.atrous_taps(x as i64, y as i64, iteration, &mut taps);
                for &(q, g) in &taps[..k] {
                    // Back from q to its kernel position.
                    let (qx, qy) = ((q % w) as i64, (q / w) as i64);
                    let (kx, ky) = ((qx - x as i64) / step + 2, (qy - y as i64) / step + 2);
                    *m |= 1 << (5 * ky + kx);
                    weight.push(g);
                }
            }
            (mask, weight)
        })
        .collect();
    let mut table =
        Table { mask: Vec::with_capacity(w * h), start: Vec::with_capacity(w * h), weight: Vec::new() };
    table.weight.reserve_exact(rows.iter().map(|r| r.1.len()).sum());
    for (mask, weight) in rows {
        let mut at = table.weight.len() as u32;
        for m in mask {
            table.start.push(at);
            table.mask.push(m);
            at += m.count_ones();
        }
        table.weight.extend(weight);
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::GBuffer;
    use glam::Vec3;

    fn gbuffer(w: u32, h: u32, tilt: f32) -> GBuffer {
        let n = (w * h) as usize;
        let depth: Vec<f32> =
            (0..n).map(|i| 1.0 + ((i % 7) as f32) * 0.01 + tilt * (i / w as usize) as f32).collect();
        let normal: Vec<Vec3> =
            (0..n).map(|i| Vec3::new(0.1 * ((i % 5) as f32 - 2.0), 0.0, 1.0).normalize()).collect();
        let coverage: Vec<f32> = (0..n).map(|i| if i % 11 == 3 { 0.0 } else { 1.0 }).collect();
        GBuffer::synthetic(w, h, depth, normal, coverage)
    }

    #[test]
    fn a_kept_tables_taps_are_the_guides_bit_for_bit() {
        let (g1, g2) = (gbuffer(23, 17, 0.0), gbuffer(23, 17, 0.05));
        let cache = Arc::new(TapCache::new(1 << 30));
        with_cache(&cache, || {
            for round in 0..3 {
                for gb in [&g1, &g2] {
                    let guide = Guide::new(gb, 1.0, 128.0);
                    for it in 0..4 {
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
        });
        assert_eq!(cache.tables(), 8);
    }

    #[test]
    fn the_cache_keeps_no_more_bytes_than_its_bound() {
        let frames: Vec<GBuffer> = (0..6).map(|i| gbuffer(31, 19, 0.01 * i as f32)).collect();
        let one = {
            let guide = Guide::new(&frames[0], 1.0, 128.0);
            build(&guide, 0).bytes()
        };
        for bound in [0, one - 1, one, 3 * one + one / 2, 100 * one] {
            let cache = Arc::new(TapCache::new(bound));
            with_cache(&cache, || {
                for _ in 0..2 {
                    for gb in &frames {
                        let guide = Guide::new(gb, 1.0, 128.0);
                        // A table is used on the second request even when it is not kept.
                        let _ = Pass::new(&guide, 0);
                    }
                }
            });
            assert!(cache.bytes() <= bound, "bound {bound}: {} bytes kept", cache.bytes());
            assert_eq!(cache.tables(), (bound / one).min(6), "bound {bound}");
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

//! Noise textures the user brings, decoded by the loader (`load::texture`: PNG 8/16 bit,
//! EXR; one file per slice) and held here as a process-wide table, like the built-in masks, so
//! that a seed mode refers to one by a small copyable handle ([`TextureId`]).
//!
//! A texture of W × H texels and D slices is tiled over the screen; frame f reads slice f mod D,
//! and the schedule acts once per full cycle of D frames, exactly as for `stbn`
//! ([`super::schedule`]). What its texels give a pixel (`use`):
//!
//! - `offset`: a 2-D Cranley–Patterson offset of the static set: channels 0 and 1 (R and G; L and A)
//!   are x and y; a one-channel texture gives both, read at two independent per-run shifts, as
//!   hemilab's own two masks are read.
//! - `rotation`: channel 0 is the x offset alone (a rotation about the normal, as `rotation`).
//! - `vector`: NVIDIA's unit-vector form (Wolfe et al. 2022's cosine-weighted "unitvec3" textures):
//!   the RGB texel is the direction itself in the surface frame (z the normal). The sequence is
//!   not read; the direction is handed on as the point the sine-cosine warp maps to it (so the
//!   renderer traces that direction, to f32 rounding and the 24-bit grid), hence `sine-cosine`
//!   only. A pixel's k-th ray in a frame reads the texel R2-offset by k (frac(k/g) W, frac(k/g²)
//!   H): NVIDIA's advice for several samples per pixel from one texture.
//!
//! **Values.** Texel t of a b-bit PNG is the offset t / 2^b, the cell [t/2^b, (t+1)/2^b) (UNORM's
//! t / (2^b − 1) would put 0 and 1, one offset mod 1, in two levels); an EXR's float in [0, 1] is
//! the offset itself (1 is 0). A float outside [0, 1] is refused, naming its texel, not wrapped:
//! such values mean another encoding (signed noise in [−1, 1], an unnormalized 0–255 export), and
//! taken mod 1 they would silently be other offsets than the file's author meant. A PNG vector is UNORM-encoded, c = 2 t / (2^b − 1) − 1 as NVIDIA writes it; an
//! EXR vector holds the components.
//!
//! **A run's seed** ([`TextureShift`]): a toroidal shift of the texture in x, y (and t when D > 1),
//! independent for x and y, plus a jitter uniform within one cell — a texel's share of [0, 1) or one
//! quantization level, whichever is wider — the same for every pixel. That is the built-ins'
//! randomization bit for bit (one slice: `blue_noise::MaskShift`'s hashes; several:
//! `stbn::StbnShift`'s), so hemilab's own masks written to files render the built-in modes' images
//! (tests/stages/sampling_textures.rs). A fixed pixel's offset over runs is then the texture's value
//! distribution smeared over one cell: exactly uniform when every slice's values are equally spaced
//! ranks (what a void-and-cluster mask is), which [`TextureMask::deviation`] measures and the
//! loader warns about otherwise. A vector texture's directions are only shifted (never rotated): a
//! pixel's direction over runs is uniform over the texture's directions, a finite quadrature of the
//! cosine lobe, so it is not unbiased per pixel.

use super::hash::{FIX_BITS, FIX_ONE, fix_add, hash};
use super::schedule::{R2_ALPHA, step};
use super::warp::Distribution;
use glam::{Vec2, Vec3};
use std::sync::{Mutex, OnceLock};

/// What a texture's texels give a pixel (see the module's doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum TextureUse {
    Offset,
    Rotation,
    Vector,
}

impl TextureUse {
    pub const ALL: [TextureUse; 3] = [TextureUse::Offset, TextureUse::Rotation, TextureUse::Vector];

    pub fn name(self) -> &'static str {
        match self {
            TextureUse::Offset => "offset",
            TextureUse::Rotation => "rotation",
            TextureUse::Vector => "vector",
        }
    }

    pub fn parse(s: &str) -> Result<Self, String> {
        Self::ALL.into_iter().find(|u| u.name() == s).ok_or_else(|| {
            format!("unknown texture use '{}'; valid: offset, rotation, vector", s.escape_debug())
        })
    }
}

/// Decoded texels as the loader hands them over: ((t · H + y) · W + x) · channels + c.
#[derive(Debug, Clone, PartialEq)]
pub enum Samples {
    /// A PNG's integers of `bits` bits (8 or 16).
    Int { bits: u32, data: Vec<u16> },
    /// An EXR's floats.
    Float(Vec<f32>),
}

/// A texture's size and layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    pub width: u32,
    pub height: u32,
    pub depth: u32,
    pub channels: u32,
}

/// A texel the texture cannot be made of: which slice, where, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TexelError {
    pub slice: u32,
    pub x: u32,
    pub y: u32,
    pub what: String,
}

/// How far a texture's slices are from giving exactly uniform offsets (see `deviation`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deviation {
    /// The largest distance, over slices and channels, between the distribution of a fixed pixel's
    /// offset over runs and the uniform one: Kuiper's V (the circle's Kolmogorov–Smirnov distance)
    /// for offsets and azimuths, Kolmogorov–Smirnov's D for a vector's sin² θ.
    pub distance: f64,
    pub slice: u32,
    /// "x", "y", "azimuth" or "sin²θ".
    pub channel: &'static str,
    /// Beyond it the texture is reported as not uniform (`TextureMask::uniform`).
    pub tolerance: f64,
}

/// A decoded texture, ready to be read per pixel.
#[derive(Debug)]
pub struct TextureMask {
    name: String,
    label: String,
    use_: TextureUse,
    width: u32,
    height: u32,
    depth: u32,
    /// Jitter width in 24-bit fixed point (offset and rotation).
    cell: u32,
    /// Channel 0 (x) and, for a two-channel offset texture, channel 1 (y; empty: x again).
    x: Vec<u32>,
    y: Vec<u32>,
    /// A vector texture's directions as the sine-cosine square's (u, v) on the 24-bit grid.
    uv: Vec<(u32, u32)>,
    deviation: Deviation,
}

/// A float in [0, 1] to the 24-bit grid mod 1 (1 is 0).
fn fixed(v: f64) -> u32 {
    ((v * FIX_ONE as f64) as u64 % FIX_ONE as u64) as u32
}

impl TextureMask {
    /// Builds the texture `name` (its results name) of `layout` from `samples`, for `use_`.
    /// Refuses a texel that is not a number, an offset outside [0, 1], or a vector that is zero
    /// or points below the horizon; the caller names the file.
    pub fn new(
        name: String,
        label: String,
        use_: TextureUse,
        layout: Layout,
        samples: &Samples,
    ) -> Result<Self, TexelError> {
        let Layout { width, height, depth, channels } = layout;
        let texels = (width * height) as usize;
        let at = |i: usize| {
            let t = i / texels;
            let p = i % texels;
            (t as u32, (p % width as usize) as u32, (p / width as usize) as u32)
        };
        let fail = |i: usize, what: String| {
            let (slice, x, y) = at(i);
            TexelError { slice, x, y, what }
        };
        let n = texels * depth as usize;
        let value = |i: usize, c: usize| -> f64 {
            match samples {
                Samples::Int { bits, data } => match use_ {
                    TextureUse::Vector => {
                        2.0 * data[i * channels as usize + c] as f64 / ((1u32 << bits) - 1) as f64 - 1.0
                    }
                    _ => data[i * channels as usize + c] as f64 / (1u32 << bits) as f64,
                },
                Samples::Float(data) => data[i * channels as usize + c] as f64,
            }
        };
        let levels = match samples {
            Samples::Int { bits, .. } => 1u64 << bits,
            Samples::Float(_) => FIX_ONE as u64,
        };
        let cell = (FIX_ONE as u64 / (texels as u64).min(levels).max(1)) as u32;
        let mut mask = Self {
            name,
            label,
            use_,
            width,
            height,
            depth,
            cell,
            x: Vec::new(),
            y: Vec::new(),
            uv: Vec::new(),
            deviation: Deviation { distance: 0.0, slice: 0, channel: "x", tolerance: 0.0 },
        };
        if use_ == TextureUse::Vector {
            for i in 0..n {
                let d = Vec3::new(value(i, 0) as f32, value(i, 1) as f32, value(i, 2) as f32);
                let len = d.length();
                if !len.is_finite() || len < 1e-3 {
                    return Err(fail(i, format!("direction {d} has no length")));
                }
                let d = d / len;
                if d.z < -2.0 / 255.0 {
                    return Err(fail(i, format!("direction {d} points below the horizon (z < 0)")));
                }
                let d = Vec3::new(d.x, d.y, d.z.max(0.0)).normalize();
                let uv = Distribution::SineCosine.invert(d);
                mask.uv.push((fixed(uv.x as f64), fixed(uv.y as f64)));
            }
        } else {
            let two = use_ == TextureUse::Offset && channels >= 2;
            for i in 0..n {
                for c in 0..(1 + two as usize) {
                    let v = value(i, c);
                    if !(0.0..=1.0).contains(&v) {
                        return Err(fail(i, format!("value {v} outside [0, 1]")));
                    }
                    if c == 0 { mask.x.push(fixed(v)) } else { mask.y.push(fixed(v)) }
                }
            }
        }
        mask.deviation = mask.measure();
        Ok(mask)
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// The person-facing words: "texture masks/x_%d.png (offset)".
    pub fn label(&self) -> &str {
        &self.label
    }

    pub fn use_(&self) -> TextureUse {
        self.use_
    }

    pub fn size(&self) -> (u32, u32, u32) {
        (self.width, self.height, self.depth)
    }

    /// Its measured distance from uniform offsets (see [`Deviation`]).
    pub fn deviation(&self) -> Deviation {
        self.deviation
    }

    /// Whether every slice gives a fixed pixel exactly uniform offsets over runs (to rounding):
    /// then the offset mode is unbiased per pixel. A vector texture never is (its tolerance is the
    /// 5 % Kolmogorov–Smirnov bound of as many independent directions: a warning, not a claim).
    pub fn uniform(&self) -> bool {
        self.use_ != TextureUse::Vector && self.deviation.distance <= self.deviation.tolerance
    }

    fn measure(&self) -> Deviation {
        let texels = (self.width * self.height) as usize;
        let mut worst = Deviation { distance: -1.0, slice: 0, channel: "x", tolerance: 1e-9 };
        let mut take = |d: f64, slice: usize, channel: &'static str| {
            if d > worst.distance {
                worst.distance = d;
                worst.slice = slice as u32;
                worst.channel = channel;
            }
        };
        for t in 0..self.depth as usize {
            let part = |v: &[u32]| v[t * texels..(t + 1) * texels].to_vec();
            if self.use_ == TextureUse::Vector {
                let uv = &self.uv[t * texels..(t + 1) * texels];
                take(kuiper(uv.iter().map(|p| p.0).collect(), 0), t, "azimuth");
                take(kolmogorov(uv.iter().map(|p| p.1).collect()), t, "sin²θ");
            } else {
                take(kuiper(part(&self.x), self.cell), t, "x");
                if !self.y.is_empty() {
                    take(kuiper(part(&self.y), self.cell), t, "y");
                }
            }
        }
        if self.use_ == TextureUse::Vector {
            worst.tolerance = 1.36 / (texels as f64).sqrt();
        }
        worst
    }

    /// Pixel (x, y)'s (x, y) offsets in slice `t` under the run's randomization (`use` offset or
    /// rotation; y is 0 for a rotation).
    #[inline]
    pub fn offsets(&self, run_key: u64, x: u32, y: u32, t: u32) -> (u32, u32) {
        let s = TextureShift::new(run_key, self);
        let (w, h, d) = (self.width, self.height, self.depth);
        let at = |c: usize| {
            let (sx, sy, st) = s.shift[c];
            ((((t % d + st) % d) * h + (y % h + sy) % h) * w + (x % w + sx) % w) as usize
        };
        let ox = fix_add(self.x[at(0)], s.jitter[0]);
        match self.use_ {
            TextureUse::Rotation => (ox, 0),
            _ => {
                let ys = if self.y.is_empty() { &self.x } else { &self.y };
                (ox, fix_add(ys[at(1)], s.jitter[1]))
            }
        }
    }

    /// A vector texture's points for pixel (x, y) in slice `t`: ray k reads the texel R2-offset by
    /// k, the whole texture shifted by the run's shift and by `frame_offsets` (the schedule's R2
    /// step per cycle, as a fraction of the texture's size).
    pub fn fill_vector(
        &self,
        run_key: u64,
        (x, y, t): (u32, u32, u32),
        frame_offsets: (u32, u32),
        out: &mut [Vec2],
    ) {
        let s = TextureShift::new(run_key, self);
        let (w, h, d) = (self.width, self.height, self.depth);
        let frac_of = |f: u32, n: u32| ((f as u64 * n as u64) >> FIX_BITS) as u32;
        let (sx, sy, st) = s.shift[0];
        let bx = x % w + sx + frac_of(frame_offsets.0, w);
        let by = y % h + sy + frac_of(frame_offsets.1, h);
        let slice = ((t % d + st) % d) * h;
        for (k, p) in out.iter_mut().enumerate() {
            let k = k as u64;
            let (ox, oy) = (frac_of(step(k, R2_ALPHA[0]), w), frac_of(step(k, R2_ALPHA[1]), h));
            let i = ((slice + (by + oy) % h) * w + (bx + ox) % w) as usize;
            let (u, v) = self.uv[i];
            *p = Vec2::new(super::hash::fix_to_f32(u), super::hash::fix_to_f32(v));
        }
    }
}

/// Kuiper's V between the mixture of uniform intervals [v, v + cell) mod 1 (one per value, equal
/// weights; point masses when cell is 0) and the uniform distribution on the circle, exactly from
/// the breakpoints (F − t is linear between them, and jumps at point masses).
fn kuiper(mut v: Vec<u32>, cell: u32) -> f64 {
    let n = v.len() as f64;
    v.sort_unstable();
    let one = FIX_ONE as u64;
    if cell == 0 {
        let (mut above, mut below) = (0.0f64, 0.0f64);
        for (i, &x) in v.iter().enumerate() {
            let u = x as f64 / one as f64;
            above = above.max((i + 1) as f64 / n - u);
            below = below.max(u - i as f64 / n);
        }
        return above + below;
    }
    // Events: one more active interval at v, one fewer at v + cell (mod 1); an interval wrapping
    // past 1 is active from 0.
    let mut events: Vec<(u64, i64)> = Vec::with_capacity(2 * v.len());
    let mut active: i64 = 0;
    for &a in &v {
        let (a, b) = (a as u64, a as u64 + cell as u64);
        events.push((a, 1));
        if b >= one {
            active += 1;
            events.push((b - one, -1));
        } else {
            events.push((b, -1));
        }
    }
    events.sort_unstable();
    let rate = 1.0 / (n * cell as f64);
    let (mut lo, mut hi, mut f, mut last) = (0.0f64, 0.0f64, 0.0f64, 0u64);
    for (t, d) in events {
        f += active as f64 * rate * (t - last) as f64;
        last = t;
        let gap = f - t as f64 / one as f64;
        lo = lo.min(gap);
        hi = hi.max(gap);
        active += d;
    }
    hi - lo
}

/// Kolmogorov–Smirnov's D between the values (on the 24-bit grid of [0, 1)) and U[0, 1).
fn kolmogorov(mut v: Vec<u32>) -> f64 {
    v.sort_unstable();
    let n = v.len() as f64;
    let mut d = 0.0f64;
    for (i, &x) in v.iter().enumerate() {
        let u = x as f64 / FIX_ONE as f64;
        d = d.max((i + 1) as f64 / n - u).max(u - i as f64 / n);
    }
    d
}

/// One run's randomization of a texture; see the module's doc. Its hashes and bit fields are
/// `blue_noise::MaskShift`'s for one slice and `stbn::StbnShift`'s for several.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TextureShift {
    shift: [(u32, u32, u32); 2],
    jitter: [u32; 2],
}

impl TextureShift {
    #[inline]
    pub fn new(run_key: u64, mask: &TextureMask) -> Self {
        let (w, h, d, cell) = (mask.width, mask.height, mask.depth, mask.cell.max(1));
        if d == 1 {
            let h2 = [hash(run_key, 0xB1_0E_5E), hash(run_key, 0xB1_0E_5F)];
            let shift = h2.map(|v| ((v as u32 & 0xFFFF) % w, ((v >> 16) as u32 & 0xFFFF) % h, 0));
            Self { shift, jitter: h2.map(|v| (v >> 40) as u32 % cell) }
        } else {
            let h2 = [hash(run_key, 0x057B_0E5E), hash(run_key, 0x057B_0E5F)];
            let shift = h2.map(|v| {
                let f = |k: u32| (v >> (16 * k)) as u32 & 0xFFFF;
                (f(0) % w, f(1) % h, f(2) % d)
            });
            // 16 bits hold the jitter of every cell up to 2^16 (8-bit textures, or 256 texels or
            // more); a wider cell takes its jitter from a further hash.
            let jitter = if cell <= 1 << 16 {
                h2.map(|v| (v >> 48) as u32 % cell)
            } else {
                h2.map(|v| (hash(v, 1) >> 40) as u32 % cell)
            };
            Self { shift, jitter }
        }
    }
}

/// Textures a process may hold at once.
pub const MAX_TEXTURES: usize = 256;

/// The table: written once per slot (lock-free reads from every render thread), in order.
static SLOTS: [OnceLock<TextureMask>; MAX_TEXTURES] = [const { OnceLock::new() }; MAX_TEXTURES];
static TAKEN: Mutex<usize> = Mutex::new(0);

/// A texture: a handle into the process's table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TextureId(u16);

impl TextureId {
    pub fn get(self) -> &'static TextureMask {
        SLOTS[self.0 as usize].get().expect("a TextureId is made only for a filled slot")
    }
}

/// Adds `mask` to the table and returns its handle and whether it is new: a texture of the same
/// name (path, use and content hash) is the one already there.
pub fn register(mask: TextureMask) -> Result<(TextureId, bool), String> {
    let mut taken = TAKEN.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(id) = find_in(*taken, &mask.name) {
        return Ok((id, false));
    }
    if *taken >= MAX_TEXTURES {
        return Err(format!("more than {MAX_TEXTURES} textures in one process"));
    }
    let id = TextureId(*taken as u16);
    SLOTS[*taken].set(mask).map_err(|_| "texture slot taken twice".to_string())?;
    *taken += 1;
    Ok((id, true))
}

fn find_in(n: usize, name: &str) -> Option<TextureId> {
    (0..n).find(|&i| SLOTS[i].get().is_some_and(|m| m.name == name)).map(|i| TextureId(i as u16))
}

/// The registered texture of results name `name`, if any.
pub fn find(name: &str) -> Option<TextureId> {
    let n = *TAKEN.lock().unwrap_or_else(|e| e.into_inner());
    find_in(n, name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kuiper_is_zero_for_tiling_cells_and_positive_otherwise() {
        let cell = FIX_ONE / 16;
        let ranks: Vec<u32> = (0..16).map(|k| k * cell).collect();
        assert!(kuiper(ranks.clone(), cell) < 1e-12);
        // A cyclic shift of the whole comb by half a cell still tiles the circle.
        assert!(kuiper(ranks.iter().map(|&r| fix_add(r, cell / 2)).collect(), cell) < 1e-12);
        // Two values in one cell, none in another: one cell's weight misplaced.
        let mut bad = ranks.clone();
        bad[3] = bad[2];
        assert!((kuiper(bad, cell) - 1.0 / 16.0).abs() < 1e-9);
        let half: Vec<u32> = (0..16).map(|k| k * cell / 2).collect();
        assert!((kuiper(half, cell) - 0.46875).abs() < 1e-9);
    }
}

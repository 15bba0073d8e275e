//! A reference image's content address and its finiteness: what a manifest's `pixels` holds and
//! what every load checks (`store`), so that an image edited after it was made is never used.

use crate::image::Image;

/// The content address of a reference image: FNV-1a (64-bit; Fowler, Noll and Vo, the hash the
/// plan already keys jobs with) over its size and, channel by channel (`Y`, `stderr`, `A`), every
/// value's f32 bits, little-endian; written `fnv1a64:` and 16 hex digits. Any change of any pixel's
/// bits changes it but for a 2^-64 chance: this guards against edits and damage, not adversaries.
pub fn pixel_hash(mean: &Image, stderr: &Image, coverage: &Image) -> String {
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h ^= b as u64;
            h = h.wrapping_mul(PRIME);
        }
    };
    eat(&mean.width.to_le_bytes());
    eat(&mean.height.to_le_bytes());
    for (name, img) in [("Y", mean), ("stderr", stderr), ("A", coverage)] {
        eat(name.as_bytes());
        eat(&(img.data.len() as u64).to_le_bytes());
        for v in &img.data {
            eat(&v.to_bits().to_le_bytes());
        }
    }
    format!("fnv1a64:{h:016x}")
}

/// The first non-finite value of a reference's channels, as "channel C at pixel (x, y) is V": a
/// NaN or infinity in a reference would make every error measured against it empty or infinite.
pub fn first_non_finite(mean: &Image, stderr: &Image, coverage: &Image) -> Option<String> {
    for (name, img) in [("Y", mean), ("stderr", stderr), ("A", coverage)] {
        if let Some(i) = img.data.iter().position(|v| !v.is_finite()) {
            let w = img.width.max(1) as usize;
            return Some(format!("channel {name} at pixel ({}, {}) is {}", i % w, i / w, img.data[i]));
        }
    }
    None
}

//! The references' half of LDR-FLIP (`metrics::flip::FlipReference`), kept while a run measures
//! against them. Why: every recorded job gets a FLIP map against its frame's reference, and a
//! real-time run measures 13,200 jobs against 39 references; the reference's half was recomputed
//! for each, about 5 ms of a 10 ms map at 320x180.
//!
//! Kept process-wide, the most recently used first, at most `BOUND` bytes (a 320x180 reference
//! takes 1.4 MB, a 1080p one 50 MB), found by a hash of the image and confirmed bit for bit
//! (`FlipReference::is_of`), so that a kept half is only ever used for its own reference.

use crate::image::{Image, WordHash};
use crate::metrics::flip::FlipReference;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex, OnceLock};

/// At most this many bytes of kept references: 512 MiB.
const BOUND: usize = 512 << 20;

type Kept = VecDeque<(u64, Arc<FlipReference>)>;

fn kept() -> &'static Mutex<Kept> {
    static KEPT: OnceLock<Mutex<Kept>> = OnceLock::new();
    KEPT.get_or_init(|| Mutex::new(VecDeque::new()))
}

/// A hash of the image's size and bits and of `ppd`.
fn key(image: &Image, ppd: f64) -> u64 {
    let mut h = WordHash::new([image.width as u64, image.height as u64, ppd.to_bits(), 0]);
    h.mix(image.data.iter().map(|v| v.to_bits()));
    h.finish()
}

/// The LDR-FLIP map of `test` against `reference` (`metrics::ldr_flip_map`, the same bits), with the
/// reference's half kept for the next test measured against it.
pub fn flip_map(reference: &Image, test: &Image, ppd: f64) -> Image {
    prepared(reference, ppd).map(test)
}

fn prepared(reference: &Image, ppd: f64) -> Arc<FlipReference> {
    let k = key(reference, ppd);
    let lock = || kept().lock().unwrap_or_else(|e| e.into_inner());
    {
        let mut c = lock();
        if let Some(i) = c.iter().position(|(kk, r)| *kk == k && r.is_of(reference, ppd)) {
            let hit = c.remove(i).expect("found");
            c.push_front(hit.clone());
            return hit.1;
        }
    }
    // Made outside the lock: another worker may make the same one meanwhile (the same bits).
    let made = Arc::new(FlipReference::new(reference, ppd));
    let mut c = lock();
    if !c.iter().any(|(kk, r)| *kk == k && r.is_of(reference, ppd)) {
        c.push_front((k, made.clone()));
        let mut bytes = 0;
        c.retain(|(_, r)| {
            bytes += r.bytes();
            bytes <= BOUND
        });
    }
    made
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::ldr_flip_map;

    fn image(w: u32, h: u32, seed: u32) -> Image {
        Image::from_vec(
            w,
            h,
            (0..w * h)
                .map(|i| ((i.wrapping_mul(2_654_435_761).wrapping_add(seed)) >> 8) as f32 / 16_777_216.0)
                .collect(),
        )
    }

    #[test]
    fn a_kept_references_maps_are_ldr_flips_bit_for_bit() {
        let (r1, r2) = (image(37, 23, 1), image(37, 23, 2));
        for round in 0..2 {
            for (r, t) in [(&r1, image(37, 23, 5)), (&r2, image(37, 23, 6)), (&r1, image(37, 23, 7))] {
                for ppd in [67.0, 30.0] {
                    let (a, b) = (flip_map(r, &t, ppd), ldr_flip_map(r, &t, ppd));
                    assert!(
                        a.data.iter().zip(&b.data).all(|(x, y)| x.to_bits() == y.to_bits()),
                        "round {round}, ppd {ppd}"
                    );
                }
            }
        }
        // Another reference of the same size is never taken for a kept one.
        assert_ne!(key(&r1, 67.0), key(&r2, 67.0));
        assert!(!FlipReference::new(&r1, 67.0).is_of(&r2, 67.0));
        assert!(!FlipReference::new(&r1, 67.0).is_of(&r1, 30.0));
    }
}

//! A sampler written outside the crate, measured by `hemilab run`'s own code path: the Hammersley
//! set, which hemilab does not ship, registered under the name `hammersley` before the library's
//! command line runs on this program's arguments. Everything `hemilab` accepts works here, and a
//! spec or a flag may name the new sequence like any built-in one:
//!
//! ```text
//! cargo run --release --example external_sampler -- run SPEC      # SPEC names sequence "hammersley"
//! cargo run --release --example external_sampler -- render --sequence hammersley --rays 16 ...
//! ```
//!
//! This is the extension point for a sampler no point file can describe (one computed per pixel,
//! per count or per frame); a fixed point set is a file (`docs/textures.md`). The interface is
//! `hemilab::sampling::PointSequence` (see `sampling/registry.rs`): a name, a `fill` that writes
//! one pixel's points from that pixel's keys, and optionally a `prepare` for tables.

use glam::Vec2;
use hemilab::sampling::seed::{fix_add, fix_from_bits, fix_to_f32, hash};
use hemilab::sampling::{PixelSet, PointSequence, SequenceInfo};

/// The Hammersley set of n points (Hammersley & Handscomb 1964): ((i + ½)/n, φ₂(i)), φ₂ the base-2
/// radical inverse (van der Corput), shifted mod 1 (Cranley & Patterson 1976) by the set's key and
/// the seed mode's offsets, in hemilab's 24-bit fixed point so that the shift is exact.
struct Hammersley;

impl PointSequence for Hammersley {
    fn info(&self) -> &SequenceInfo {
        &SequenceInfo {
            name: "hammersley",
            label: "Hammersley",
            words: &[],
            fresh_per_pixel: false,
            shipped: None,
        }
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        // The key is fresh per pixel under `shift`; (dx, dy) are the seed mode's offsets (a
        // rotation's, a mask's) with the frame schedule's.
        let (key, dx, dy) = set.keyed();
        let (kx, ky) = (fix_from_bits(hash(key, 1)), fix_from_bits(hash(key, 2)));
        for (i, p) in out.iter_mut().enumerate() {
            // (2i + 1) / 2n in 24-bit fixed point; φ₂(i) is i's low 24 bits reversed.
            let x = (((2 * i as u64 + 1) << 23) / u64::from(set.count)) as u32;
            let y = (i as u32).reverse_bits() >> 8;
            let (x, y) = (fix_add(fix_add(x, kx), dx), fix_add(fix_add(y, ky), dy));
            *p = Vec2::new(fix_to_f32(x), fix_to_f32(y));
        }
    }
}

fn main() {
    if let Err(e) = hemilab::sampling::register(Box::new(Hammersley)) {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
    std::process::exit(hemilab::main_with(std::env::args_os()));
}

//! Writes hemilab's own blue-noise and spatiotemporal masks as noise textures: the
//! `blue-noise` mode's two masks as `blue_noise.png` / `.exr` (x in channel 0, y in channel 1) and
//! `stbn`'s volumes as `stbn_0.png` … `stbn_31.png` / `.exr`. Read back with
//! `--seed-mode texture:DIR/blue_noise.png` or `texture:DIR/stbn_%d.png`, they render the built-in
//! modes' images bit for bit (tests/stages/sampling_textures.rs); they are also what a published
//! texture is measured against (docs/textures.md):
//! `cargo run --release --example write_masks -- /tmp/masks`.

use hemilab::load::texture::{Own, own_masks};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "/tmp/masks".into()));
    hemilab::io::create_dir_all(&dir)?;
    for which in [Own::BlueNoise, Own::Stbn] {
        for png in [true, false] {
            for (name, bytes) in own_masks(which, png)? {
                hemilab::io::write_atomic(&dir.join(&name), &bytes)?;
            }
        }
    }
    println!("wrote hemilab's masks to {}", dir.display());
    Ok(())
}

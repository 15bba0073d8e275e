//! The G-buffer the edge-aware filter is guided by: from the renderer's own primary rays, so its
//! depth and normal are those of the hits the AO rays start from; and adding it left `render`'s
//! images as they were (fingerprints of main's images, taken before the G-buffer existed).

use hemilab::load::load_scene;
use hemilab::render::{RenderJob, RenderOutput, render};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use std::path::Path;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// FNV-1a (64 bit) over the AO and coverage bits and the ray counts.
fn fingerprint(o: &RenderOutput) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for v in o.ao.data.iter().chain(&o.coverage.data) {
        eat(&v.to_bits().to_le_bytes());
    }
    eat(&o.rays.to_le_bytes());
    eat(&o.occluded_rays.to_le_bytes());
    h
}

fn job(scene: &hemilab::scene::Scene, d: Distribution, q: Sequence, m: SeedMode, res: (u32, u32)) -> RenderJob {
    RenderJob {
        distribution: d,
        sampler: SamplerConfig::new(q, m, 16, 3).unwrap(),
        width: res.0,
        height: res.1,
        ao_distance: scene.ao_distance,
    }
}

/// Images rendered by main's code (commit 321ec7f) before `gbuffer` shared the primary-ray code
/// with `render`: the same bits now.
#[test]
fn render_is_bit_identical_to_mains() {
    let cases = [
        ("scenes/kitchen.toml", (64, 48), Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Rotation),
        ("scenes/cornell-box.toml", (48, 48), Distribution::Uniform, Sequence::Random, SeedMode::Shift),
        ("scenes/floating-rectangle.toml", (40, 30), Distribution::Sine, Sequence::Fibonacci, SeedMode::Rotation),
    ];
    let mut got = Vec::new();
    for (file, res, d, q, m) in cases {
        let scene = load_scene(&root().join(file)).unwrap();
        got.push(fingerprint(&render(&scene, &job(&scene, d, q, m, res), &|_| {})));
    }
    eprintln!("{got:#018x?}");
    assert_eq!(got, [0xabc2_a45f_a21b_1b61u64, 0xf53d_59cf_4207_ec33, 0x8f77_36ff_aa8d_3cc2]);
}

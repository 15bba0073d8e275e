//! The per-frame randomization schedules: frame 0 is today's image bit for bit under every
//! schedule, `r1` moves the offsets by exactly f α mod 1 (R1 for a rotation, R2 for a shift),
//! `independent` draws each frame from a fresh run seed.

use glam::Vec2;
use hemilab::sampling::schedule::{R1_ALPHA, R2_ALPHA, r1, r2};
use hemilab::sampling::seed::fix_add;
use hemilab::sampling::{SamplerConfig, Schedule, SeedMode, Sequence};

/// The seed modes that existed before frames did: their frame-0 points are pinned by `GOLDEN`.
const TODAY: [SeedMode; 4] = [SeedMode::Static, SeedMode::Rotation, SeedMode::Shift, SeedMode::BlueNoise];

fn fill(cfg: SamplerConfig, pixel: u64) -> Vec<Vec2> {
    let mut out = vec![Vec2::splat(-1.0); cfg.count as usize];
    cfg.fill_pixel((pixel % 13) as u32 * 7, (pixel / 13) as u32 * 5, pixel, &mut out);
    out
}

/// FNV-1a over the bits of every point of every sequence × seed mode × count × seed × pixel.
fn digest(make: impl Fn(Sequence, SeedMode, u32, u64) -> SamplerConfig) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    // The sequences main had at 321ec7f (the later ones have their own determinism tests).
    for seq in [Sequence::Random, Sequence::Fibonacci, Sequence::Stratified, Sequence::Sobol] {
        for mode in TODAY {
            for n in [1, 7, 32] {
                for seed in [0, 1, 0xDEAD_BEEF] {
                    for pixel in 0..40 {
                        for p in fill(make(seq, mode, n, seed), pixel) {
                            for b in [p.x.to_bits(), p.y.to_bits()] {
                                h = (h ^ b as u64).wrapping_mul(0x100_0000_01b3);
                            }
                        }
                    }
                }
            }
        }
    }
    h
}

/// The digest of the points before `frame` and `schedule` existed (main at 321ec7f).
const GOLDEN: u64 = 0xc271_80d2_2918_c885;

#[test]
fn frame_zero_is_todays_points_under_every_schedule() {
    for &s in Schedule::ALL {
        let d =
            digest(|q, m, n, seed| SamplerConfig::new(q, m, n, seed).unwrap().with_frame(0).with_schedule(s));
        assert_eq!(d, GOLDEN, "{s}");
    }
}

#[test]
fn r1_steps_are_exactly_f_alpha_mod_one() {
    for f in [0u64, 1, 2, 3, 31, 32, 1000, u32::MAX as u64] {
        assert_eq!(r1(f), (((f as u128 * R1_ALPHA as u128) % (1u128 << 64)) >> 40) as u32);
        let (x, y) = r2(f);
        assert_eq!(x, (((f as u128 * R2_ALPHA[0] as u128) % (1u128 << 64)) >> 40) as u32);
        assert_eq!(y, (((f as u128 * R2_ALPHA[1] as u128) % (1u128 << 64)) >> 40) as u32);
        // Against the real number for small f (f64 holds f / phi to ~1e-16; away from grid edges).
        let phi = (1.0 + 5f64.sqrt()) / 2.0;
        let want = (f as f64 / phi).fract() * (1u64 << 24) as f64;
        if f < 1 << 20 && (want - want.floor()) > 1e-3 && (want - want.floor()) < 1.0 - 1e-3 {
            assert_eq!(r1(f), want.floor() as u32, "{f}");
        }
    }
}

/// Under `r1`, frame f's points are frame 0's moved by f α mod 1: x by R1 for a lattice's rotation,
/// x and y by R2 for every other mode.
#[test]
fn r1_frames_are_frame_zero_moved_by_f_alpha() {
    let to_fix = |v: f32| (v as f64 * (1u64 << 24) as f64) as u32;
    // The sequences main had at 321ec7f (the later ones have their own determinism tests).
    for seq in [Sequence::Random, Sequence::Fibonacci, Sequence::Stratified, Sequence::Sobol] {
        for mode in TODAY {
            let base = SamplerConfig::new(seq, mode, 9, 77).unwrap().with_schedule(Schedule::R1);
            let scalar = mode == SeedMode::Rotation && seq != Sequence::Random;
            for f in [1u32, 2, 5, 40, 1 << 20] {
                let (ox, oy) = if scalar { (r1(f as u64), 0) } else { r2(f as u64) };
                for pixel in [0u64, 3, 57] {
                    let (p0, pf) = (fill(base, pixel), fill(base.with_frame(f), pixel));
                    for (a, b) in p0.iter().zip(&pf) {
                        assert_eq!(to_fix(b.x), fix_add(to_fix(a.x), ox), "{seq:?} {mode:?} {f}");
                        assert_eq!(to_fix(b.y), fix_add(to_fix(a.y), oy), "{seq:?} {mode:?} {f}");
                    }
                }
            }
        }
    }
}

/// Under `independent`, frame f is frame 0 of another run seed: different points, the same
/// structure, and the same for every pixel only where the mode is static.
#[test]
fn independent_frames_draw_fresh_points() {
    // The sequences main had at 321ec7f (the later ones have their own determinism tests).
    for seq in [Sequence::Random, Sequence::Fibonacci, Sequence::Stratified, Sequence::Sobol] {
        for mode in TODAY {
            let base = SamplerConfig::new(seq, mode, 9, 77).unwrap();
            let frames: Vec<Vec<Vec2>> = (0..4).map(|f| fill(base.with_frame(f), 5)).collect();
            for f in 1..4 {
                assert_ne!(frames[0], frames[f], "{seq:?} {mode:?} frame {f}");
                assert_eq!(frames[f], fill(base.with_frame(f as u32), 5), "deterministic");
            }
        }
    }
}

/// `SeedMode::schedule_matters` is what the points say: over the first `depth` frames the two
/// schedules draw the same points for `stbn` (one configuration, which advise sweeps once), and
/// from the next cycle on they differ; for every mode of depth 1 they differ from frame 1.
#[test]
fn the_schedule_matters_exactly_when_the_points_say_so() {
    let modes = [SeedMode::Stbn, SeedMode::BlueNoise, SeedMode::Rotation, SeedMode::Ign, SeedMode::Bayer];
    for mode in modes {
        for seq in [Sequence::Random, Sequence::Fibonacci] {
            let base = SamplerConfig::new(seq, mode, 4, 11).unwrap();
            let differs = |frame: u32| {
                (0..60u64).any(|pixel| {
                    let at = |s: Schedule| fill(base.with_frame(frame).with_schedule(s), pixel);
                    at(Schedule::Independent) != at(Schedule::R1)
                })
            };
            let first = (0..80).find(|&f| differs(f));
            let depth = mode.depth();
            // The first frame the schedules tell apart is the first of the second cycle.
            assert_eq!(first, Some(depth), "{mode:?} {seq:?}");
            for frames in [1, depth, depth + 1, 64] {
                let any = (0..frames).any(differs);
                assert_eq!(mode.schedule_matters(frames), any, "{mode:?} {seq:?} over {frames} frames");
            }
        }
    }
}

//! What a configuration's sampler costs per point on this machine: its points drawn for a block of
//! pixels (`SamplerConfig::fill_pixel`, exactly as a render draws them) and mapped to directions
//! (`Distribution::sample`), no ray traced, on one thread's CPU clock. advise shows it beside each
//! candidate's time per frame: the frame's time is mostly tracing, the same for every sampler,
//! while this is the part a sampler choice changes.

use crate::sampling::{Distribution, SamplerConfig};
use crate::timing::clock;
use glam::Vec2;

/// Pixels per pass (a 64 × 64 block, so that per-pixel masks are read as an image reads them) …
const BLOCK: u32 = 64;
/// … and passes until at least this much CPU time has been measured.
const MIN_S: f64 = 2e-3;

/// Nanoseconds of thread CPU time per point of `config` (its tables made first, as a render's
/// clock does not count them).
pub fn ns_per_point(distribution: Distribution, config: SamplerConfig) -> f64 {
    config.prepare();
    let mut pts = vec![Vec2::ZERO; config.count as usize];
    let (mut points, mut spent) = (0u64, 0.0);
    let mut pass = 0u64;
    while spent < MIN_S && pass < 1000 {
        let c0 = clock::thread_cpu_s();
        for y in 0..BLOCK {
            for x in 0..BLOCK {
                let pixel = (pass * BLOCK as u64 + y as u64) * BLOCK as u64 + x as u64;
                config.fill_pixel(x, y, pixel, &mut pts);
                for &u in &pts {
                    std::hint::black_box(distribution.sample(u));
                }
            }
        }
        spent += clock::thread_cpu_s() - c0;
        points += (BLOCK * BLOCK) as u64 * config.count as u64;
        pass += 1;
    }
    spent * 1e9 / points.max(1) as f64
}

/// `ns_per_point` of every configuration at every ray count.
pub fn of_rows(rows: &[crate::spec::Row], rays: &[u32]) -> Vec<(crate::spec::Row, u32, f64)> {
    let mut out = Vec::new();
    for &row in rows {
        for &n in rays {
            if let Ok(c) = SamplerConfig::new(row.sequence, row.seed_mode, n, 1) {
                out.push((row, n, ns_per_point(row.distribution, c)));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{SeedMode, Sequence};

    #[test]
    fn a_cost_per_point_is_positive_and_finite() {
        let c = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 2, 1).unwrap();
        let ns = ns_per_point(Distribution::SineCosine, c);
        assert!(ns.is_finite() && ns > 0.0, "{ns}");
    }
}

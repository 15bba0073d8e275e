//! Proof of the warps: chi-square goodness of fit with iid input (NOTES.md recipe), the test's
//! power, pdf normalisation, inverses, weights, and extreme inputs. Every test runs over
//! `Distribution::ALL`, so a new warp is covered by adding it to the enum.

use crate::support::stats::{Chi2, chi2_test, sidak_threshold};
use glam::{Vec2, Vec3};
use hemilab::sampling::Distribution;
use hemilab::sampling::seed::hash;
use std::f64::consts::{FRAC_PI_2, TAU};

const SAMPLES: usize = 1_000_000;
pub(crate) const PHI_BINS: usize = 50;
pub(crate) const THETA_BINS: usize = 101;
/// Sub-cell midpoint quadrature per axis for the expected counts.
const QUAD: usize = 8;

/// Bin in (phi, cos theta), area-preserving; uniform-in-angles, whose pdf has a 1/sin pole,
/// in (phi, theta). A new warp defaults to cos theta.
#[derive(Clone, Copy)]
pub(crate) enum Space {
    CosTheta,
    Theta,
}

pub(crate) fn space(d: Distribution) -> Space {
    match d {
        Distribution::Uniform => Space::Theta,
        _ => Space::CosTheta,
    }
}

/// iid uniform input from a seeded counter-based PRNG (the test, not the lattice).
fn iid(key: u64, i: u64) -> Vec2 {
    let h = hash(key, i);
    Vec2::new((h >> 40) as f32 / 16_777_216.0, ((h >> 16) & 0xFF_FFFF) as f32 / 16_777_216.0)
}

fn dir_of(phi: f64, t: f64, s: Space) -> Vec3 {
    let (sin_t, cos_t) = match s {
        Space::CosTheta => ((1.0 - t * t).max(0.0).sqrt(), t),
        Space::Theta => t.sin_cos(),
    };
    Vec3::new((sin_t * phi.cos()) as f32, (sin_t * phi.sin()) as f32, cos_t as f32)
}

pub(crate) fn cell_of(d: Vec3, s: Space) -> usize {
    let (x, y, z) = (d.x as f64, d.y as f64, d.z as f64);
    let phi = y.atan2(x).rem_euclid(TAU);
    let ip = ((phi / TAU * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
    let t = match s {
        Space::CosTheta => z,
        Space::Theta => (x * x + y * y).sqrt().atan2(z) / FRAC_PI_2,
    };
    let it = ((t * THETA_BINS as f64) as usize).min(THETA_BINS - 1);
    ip * THETA_BINS + it
}

/// n * integral of `pdf` over each cell, by midpoint quadrature of the code's own pdf.
pub(crate) fn expected_counts(pdf: impl Fn(Vec3) -> f32, s: Space, n: usize) -> Vec<f64> {
    let t_max = match s {
        Space::CosTheta => 1.0,
        Space::Theta => FRAC_PI_2,
    };
    let (dp, dt) = (TAU / PHI_BINS as f64, t_max / THETA_BINS as f64);
    let (hp, ht) = (dp / QUAD as f64, dt / QUAD as f64);
    let mut e = vec![0.0; PHI_BINS * THETA_BINS];
    for ip in 0..PHI_BINS {
        for it in 0..THETA_BINS {
            let mut sum = 0.0;
            for a in 0..QUAD {
                for b in 0..QUAD {
                    let phi = ip as f64 * dp + (a as f64 + 0.5) * hp;
                    let t = it as f64 * dt + (b as f64 + 0.5) * ht;
                    let jac = match s {
                        Space::CosTheta => 1.0,
                        Space::Theta => t.sin(),
                    };
                    sum += pdf(dir_of(phi, t, s)) as f64 * jac;
                }
            }
            e[ip * THETA_BINS + it] = sum * hp * ht * n as f64;
        }
    }
    e
}

/// Histogram of `SAMPLES` iid samples of `d` tested against `pdf`; fails outright on any
/// sample off the hemisphere or non-finite.
fn chi2_of(d: Distribution, pdf: impl Fn(Vec3) -> f32) -> Chi2 {
    let s = space(d);
    let mut observed = vec![0.0; PHI_BINS * THETA_BINS];
    let key = 0x0C41_5175 ^ d as u64;
    for i in 0..SAMPLES as u64 {
        let dir = d.sample(iid(key, i)).dir;
        assert!(dir.is_finite() && dir.z >= 0.0, "{d}: sample {i} off the hemisphere: {dir}");
        assert!((dir.length() - 1.0).abs() < 1e-5, "{d}: sample {i} not unit: {dir}");
        observed[cell_of(dir, s)] += 1.0;
    }
    let expected = expected_counts(pdf, s, SAMPLES);
    chi2_test(&observed, &expected, 5.0).unwrap_or_else(|e| panic!("{d}: chi2 cannot run: {e}"))
}

fn threshold() -> f64 {
    sidak_threshold(0.01, Distribution::ALL.len())
}

fn assert_matches_pdf(d: Distribution) {
    let r = chi2_of(d, |w| d.pdf(w));
    eprintln!("chi2 {d}: statistic {:.1}, dof {}, p = {:.4}", r.statistic, r.dof, r.p_value);
    assert!(r.p_value >= threshold(), "{d}: chi2 rejects its own pdf: {r:?}");
}

#[test]
fn chi2_uniform_matches_pdf() {
    assert_matches_pdf(Distribution::Uniform);
}

#[test]
fn chi2_sine_matches_pdf() {
    assert_matches_pdf(Distribution::Sine);
}

#[test]
fn chi2_sine_cosine_matches_pdf() {
    assert_matches_pdf(Distribution::SineCosine);
}

#[test]
fn chi2_concentric_cosine_matches_pdf() {
    assert_matches_pdf(Distribution::ConcentricCosine);
}

#[test]
fn chi2_every_distribution_in_all_matches_pdf() {
    for &d in Distribution::ALL {
        assert_matches_pdf(d);
    }
}

#[test]
fn chi2_rejects_wrong_pdf() {
    // Sine-cosine samples judged against sine's pdf, and uniform-in-angles against sine's.
    let r = chi2_of(Distribution::SineCosine, |w| Distribution::Sine.pdf(w));
    eprintln!("chi2 sine-cosine vs sine pdf: p = {:.3e}", r.p_value);
    assert!(r.p_value < threshold(), "wrong pdf accepted: {r:?}");
    let r = chi2_of(Distribution::Sine, |w| Distribution::SineCosine.pdf(w));
    eprintln!("chi2 sine vs sine-cosine pdf: p = {:.3e}", r.p_value);
    assert!(r.p_value < threshold(), "wrong pdf accepted: {r:?}");
    // A subtle error: cos^1.1 instead of cos (normalised) must still be caught with 10^6 samples.
    let r = chi2_of(Distribution::SineCosine, |w| w.z.max(0.0).powf(1.1) * 2.1 / std::f32::consts::TAU);
    eprintln!("chi2 sine-cosine vs cos^1.1 pdf: p = {:.3e}", r.p_value);
    assert!(r.p_value < threshold(), "2 % wrong pdf accepted: {r:?}");
}

#[test]
fn pdf_integrates_to_one_for_every_distribution() {
    let (np, nt) = (128, 8192);
    for &d in Distribution::ALL {
        let mut sum = 0.0;
        for ip in 0..np {
            let phi = (ip as f64 + 0.5) / np as f64 * TAU;
            for it in 0..nt {
                let theta = (it as f64 + 0.5) / nt as f64 * FRAC_PI_2;
                sum += d.pdf(dir_of(phi, theta, Space::Theta)) as f64 * theta.sin();
            }
        }
        let integral = sum * (TAU / np as f64) * (FRAC_PI_2 / nt as f64);
        assert!((integral - 1.0).abs() < 1e-3, "{d}: pdf integrates to {integral}");
    }
}

fn wrap_dist(a: f32, b: f32) -> f32 {
    let d = (a - b).abs();
    d.min(1.0 - d)
}

#[test]
fn warp_inverse_round_trip_on_grid_for_every_distribution() {
    let n = 200;
    for &d in Distribution::ALL {
        for i in 0..n {
            for j in 0..n {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let dir = d.sample(u).dir;
                let back = d.invert(dir);
                assert!(
                    wrap_dist(back.x, u.x) < 1e-4 && (back.y - u.y).abs() < 1e-4,
                    "{d}: invert(sample({u})) = {back}"
                );
                assert!((0.0..1.0).contains(&back.x) && (0.0..1.0).contains(&back.y));
                let again = d.sample(back).dir;
                assert!((again - dir).length() < 1e-4, "{d}: sample(invert({dir})) = {again}");
            }
        }
    }
}

#[test]
fn weight_is_cos_over_pi_pdf_for_every_distribution() {
    for &d in Distribution::ALL {
        for i in 0..100_000u64 {
            let s = d.sample(iid(77, i));
            assert_eq!(s.weight, d.ao_weight(s.dir));
            let pdf = d.pdf(s.dir);
            if pdf > 1e-3 && pdf.is_finite() {
                let w = s.dir.z / (std::f32::consts::PI * pdf);
                assert!((w - s.weight).abs() <= 1e-4 * w.max(1.0), "{d}: {} vs {w} at {}", s.weight, s.dir);
            }
        }
    }
}

#[test]
fn extreme_inputs_give_finite_unit_upper_directions_and_weights() {
    let below_one = f32::from_bits(1.0f32.to_bits() - 1);
    let values = [0.0, 2f32.powi(-24), 0.5, 1.0 - 2f32.powi(-24), below_one, 1.0];
    // Out-of-contract inputs are clamped rather than turned into NaN.
    let hostile = [-0.0, -1.0, 1.5, f32::NAN, f32::INFINITY];
    for &d in Distribution::ALL {
        for &a in values.iter().chain(&hostile) {
            for &b in values.iter().chain(&hostile) {
                let s = d.sample(Vec2::new(a, b));
                let v = s.dir;
                let ctx = format!("{d} at ({a}, {b}): {v} w {}", s.weight);
                assert!(v.is_finite() && (v.length() - 1.0).abs() < 1e-6, "{ctx}");
                assert!(v.z >= 0.0, "{ctx}");
                assert!(v.to_array().iter().all(|c| c.to_bits() != (-0.0f32).to_bits()), "-0.0: {ctx}");
                assert!(s.weight.is_finite() && s.weight >= 0.0, "{ctx}");
                let pdf = d.pdf(v);
                assert!(pdf >= 0.0, "{ctx}: pdf {pdf}");
                if s.weight > 0.0 {
                    assert!(pdf.is_finite(), "{ctx}: pdf {pdf} where the weight is used");
                }
                let back = d.invert(v);
                assert!((0.0..1.0).contains(&back.x) && (0.0..1.0).contains(&back.y), "{ctx}: {back}");
            }
        }
    }
}

#[test]
fn concentric_cosine_is_the_shirley_chiu_map_not_the_polar_one() {
    // The concentric map sends the square's edge midpoint (1, 0.5) to phi = 0 on the rim and
    // the square's corner to the diagonal; the polar map would send (u, 0.5) to theta = 45 deg.
    let d = Distribution::ConcentricCosine.sample(Vec2::new(1.0, 0.5)).dir;
    assert!((d - Vec3::X).length() < 1e-6, "{d}");
    let c = Distribution::ConcentricCosine.sample(Vec2::new(0.75, 0.75)).dir;
    assert!((c.x - c.y).abs() < 1e-6 && (c.x - 0.5f32.sqrt() * 0.5).abs() < 1e-6, "{c}");
    assert_eq!(Distribution::ConcentricCosine.sample(Vec2::splat(0.5)).dir, Vec3::Z);
}

/// `unit_weight` holds exactly where every sampled weight is 1.0 (a grid of 257² points and the
/// corners), and nowhere else: the renderer counts blocked rays instead of summing for those.
#[test]
fn unit_weight_means_every_weight_is_exactly_one() {
    for d in Distribution::ALL {
        let grid =
            (0..=256u32).flat_map(|i| (0..=256u32).map(move |j| Vec2::new(i as f32, j as f32) / 256.0));
        let all_one = grid.map(|u| d.sample(u).weight).all(|w| w == 1.0);
        assert_eq!(d.unit_weight(), all_one, "{d:?}");
    }
}

//! What the hemisphere points integrate: the integrand f, normalized so that the whole
//! hemisphere gives 1, and the per-ray weight f(ω)/p(ω) of every distribution, in closed form.
//!
//! Three integrands, after the paper's theory section (`../shared/PAPER.md`): each of its three
//! statements names a distribution matched to one of them.
//! - `Ao`: (1/π) ∫ V cos θ dω, today's, matched by sine-cosine (cosine-weighted) sampling;
//! - `Visibility`: (1/2π) ∫ V dω, unweighted (the "sky-view factor"), matched by sine (uniform
//!   over solid angle);
//! - `CosLobe(n)`: ((n+1)/2π) ∫ V cosⁿθ dω, n ≥ 2, a lobe about the normal (a glossy BRDF, a cone),
//!   which uniform-in-the-angles sampling, crowding points at the pole, suits best for sharp lobes.
//!
//! The estimator of the occlusion is the mean of w = f/p over the blocked rays, so in a closed room
//! (every ray blocked) it is the mean of w, whose expectation is 1 and whose per-ray variance is
//! ∫ f²/p dω − 1 (`closed_room_variance`): 0 exactly for the matched pairs, infinite for
//! sine-cosine on unweighted visibility (p → 0 at the horizon while f does not).

use super::warp::Distribution;
use glam::Vec3;
use std::f64::consts::PI;

/// The integrand axis (see the module's doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Integrand {
    /// Cosine-weighted visibility, (1/π) ∫ V cos θ dω (the default, and Tables 2–3's).
    Ao,
    /// Unweighted visibility, (1/2π) ∫ V dω.
    Visibility,
    /// ((n+1)/2π) ∫ V cosⁿθ dω, n ≥ 2 (n = 1 is `Ao`, n = 0 `Visibility`).
    CosLobe(u32),
}

impl Integrand {
    /// Parses `ao`, `visibility` or `cos-lobe-N` (N ≥ 2); the error says what is allowed.
    pub fn parse(s: &str) -> Result<Self, String> {
        let allowed = "allowed: ao, visibility, cos-lobe-N with an integer N >= 2";
        match s {
            "ao" => Ok(Integrand::Ao),
            "visibility" => Ok(Integrand::Visibility),
            _ => match s.strip_prefix("cos-lobe-").map(str::parse::<u32>) {
                Some(Ok(n)) if n >= 2 => Ok(Integrand::CosLobe(n)),
                _ => Err(format!("unknown integrand '{s}' ({allowed})")),
            },
        }
    }

    /// The exponent n of cosⁿθ: 1 for `Ao`, 0 for `Visibility`.
    pub fn exponent(self) -> u32 {
        match self {
            Integrand::Ao => 1,
            Integrand::Visibility => 0,
            Integrand::CosLobe(n) => n,
        }
    }

    /// f(ω) = ((n+1)/2π) cosⁿθ, normalized over the hemisphere (0 below it).
    pub fn density(self, dir: Vec3) -> f64 {
        let c = (dir.z as f64).max(0.0);
        let n = self.exponent();
        (n as f64 + 1.0) / (2.0 * PI) * c.powi(n as i32)
    }

    /// The per-ray weight f(ω)/p(ω) of `dist`, in closed form (no division by a vanishing pdf
    /// except where the weight itself is unbounded: sine-cosine on `Visibility`, 1/(2 cos θ),
    /// infinite on the horizon). For `Ao` it is `Distribution::ao_weight`, bit for bit.
    #[inline]
    pub fn weight(self, dist: Distribution, dir: Vec3) -> f32 {
        if self == Integrand::Ao {
            return dist.ao_weight(dir);
        }
        let n = self.exponent();
        let c = dir.z.max(0.0);
        let s = (dir.x * dir.x + dir.y * dir.y).sqrt().min(1.0);
        let k = n as f32 + 1.0;
        // f/p with p = 1/(2π) (sine), cos/π (cosine-weighted), 1/(π² sin θ) (uniform in angles).
        match dist {
            Distribution::Sine => k * c.powi(n as i32),
            Distribution::SineCosine | Distribution::ConcentricCosine => 0.5 * k * c.powi(n as i32 - 1),
            Distribution::Uniform => 0.5 * std::f32::consts::PI * k * s * c.powi(n as i32),
        }
    }

    /// The largest weight f/p of `dist` for this integrand over the hemisphere, +∞ where it is
    /// unbounded (sine-cosine on `Visibility`, the one infinite-variance cell): what tells a heavy
    /// tail apart from noise in a measurement (a single-ray weight above it cannot be finite-variance
    /// noise of this cell). With k = n+1: sine k; cosine-weighted k/2 (n ≥ 1); uniform in angles
    /// (π/2) k max sin θ cosⁿθ = (π/2) k √(1/(n+1)) (n/(n+1))^(n/2).
    pub fn weight_bound(self, dist: Distribution) -> f64 {
        let n = self.exponent() as f64;
        let k = n + 1.0;
        match dist {
            Distribution::Sine => k,
            Distribution::SineCosine | Distribution::ConcentricCosine => {
                if n == 0.0 {
                    f64::INFINITY
                } else {
                    k / 2.0
                }
            }
            Distribution::Uniform => PI / 2.0 * k * (1.0 / k).sqrt() * (n / k).powf(n / 2.0),
        }
    }

    /// Whether every weight of `dist` for this integrand is exactly 1 (the matched pairs).
    pub fn unit_weight(self, dist: Distribution) -> bool {
        match self {
            Integrand::Ao => dist.unit_weight(),
            Integrand::Visibility => dist == Distribution::Sine,
            Integrand::CosLobe(_) => false,
        }
    }

    /// The per-ray variance of the estimator where every ray is blocked: ∫ f²/p dω − 1, in closed
    /// form (+∞ for sine-cosine on unweighted visibility). With f = ((n+1)/2π) cosⁿθ:
    /// - sine, p = 1/(2π): (n+1)²/(2n+1) − 1 = n²/(2n+1);
    /// - cosine-weighted, p = cos θ/π: (n+1)²/(4n) − 1 = (n−1)²/(4n) (n ≥ 1; ∞ for n = 0);
    /// - uniform in angles, p = 1/(π² sin θ): (n+1)² (π/2) ∫₀^{π/2} cos²ⁿθ sin²θ dθ − 1, the
    ///   integral being B(n+½, 3/2)/2 = Γ(n+½) Γ(3/2) / (2 Γ(n+2)) (π²/8 − 1 for n = 0 and 1).
    pub fn closed_room_variance(self, dist: Distribution) -> f64 {
        let n = self.exponent() as f64;
        match dist {
            Distribution::Sine => n * n / (2.0 * n + 1.0),
            Distribution::SineCosine | Distribution::ConcentricCosine => {
                if n == 0.0 {
                    f64::INFINITY
                } else {
                    (n - 1.0) * (n - 1.0) / (4.0 * n)
                }
            }
            Distribution::Uniform => {
                // Γ(n+½)/Γ(n+2) by the recurrences from Γ(½) = √π and Γ(2) = 1, exact enough.
                let mut ratio = PI.sqrt();
                for k in 0..self.exponent() {
                    ratio *= k as f64 + 0.5;
                    ratio /= k as f64 + 2.0;
                }
                let integral = ratio * (0.5 * PI.sqrt()) / 2.0;
                (n + 1.0) * (n + 1.0) * (PI / 2.0) * integral - 1.0
            }
        }
    }
}

impl std::str::FromStr for Integrand {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Integrand::parse(s)
    }
}

impl Integrand {
    /// The distribution of the paper's three with the least closed-room variance for this
    /// integrand (sine for `Visibility`, sine-cosine for `Ao` and wide lobes, uniform in the angles
    /// for sharp ones: the crossover is between n = 5 and 6). What its references are built with.
    pub fn matched_distribution(self) -> Distribution {
        [Distribution::Sine, Distribution::SineCosine, Distribution::Uniform]
            .into_iter()
            .min_by(|a, b| self.closed_room_variance(*a).total_cmp(&self.closed_room_variance(*b)))
            .unwrap_or(Distribution::SineCosine)
    }
}

impl std::fmt::Display for Integrand {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Integrand::Ao => f.write_str("ao"),
            Integrand::Visibility => f.write_str("visibility"),
            Integrand::CosLobe(n) => write!(f, "cos-lobe-{n}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    const ALL: [Distribution; 4] =
        [Distribution::Uniform, Distribution::Sine, Distribution::SineCosine, Distribution::ConcentricCosine];

    fn integrands() -> [Integrand; 6] {
        [
            Integrand::Visibility,
            Integrand::Ao,
            Integrand::CosLobe(4),
            Integrand::CosLobe(8),
            Integrand::CosLobe(32),
            Integrand::CosLobe(128),
        ]
    }

    /// SplitMix64 (Steele, Lea, Flood 2014): independent uniforms for the variance test.
    fn uniforms(seed: u64) -> impl FnMut() -> f32 {
        let mut s = seed;
        move || {
            s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 40) as f32 / 16_777_216.0
        }
    }

    /// The crossover of the issue: sine-cosine up to n = 5 (variance 0.80 against 0.82), uniform
    /// in the angles from n = 6 (0.95 against 1.04).
    #[test]
    fn matched_distributions_cross_over_between_five_and_six() {
        use Distribution::*;
        assert_eq!(Integrand::Visibility.matched_distribution(), Sine);
        assert_eq!(Integrand::Ao.matched_distribution(), SineCosine);
        assert_eq!(Integrand::CosLobe(5).matched_distribution(), SineCosine);
        assert_eq!(Integrand::CosLobe(6).matched_distribution(), Uniform);
        assert_eq!(Integrand::CosLobe(32).matched_distribution(), Uniform);
    }

    #[test]
    fn names_round_trip_and_bad_ones_say_what_is_allowed() {
        for i in integrands() {
            assert_eq!(Integrand::parse(&i.to_string()), Ok(i));
        }
        for bad in ["cos-lobe-1", "cos-lobe-0", "cos-lobe-x", "AO", "lobe-4", ""] {
            let e = Integrand::parse(bad).unwrap_err();
            assert!(e.contains(bad) && e.contains("cos-lobe-N"), "{e}");
        }
    }

    /// The weight is f/p, checked against the pdfs of `warp` away from pole and horizon, and is
    /// the AO weight for `Ao`.
    #[test]
    fn weight_is_density_over_pdf() {
        let mut u = uniforms(1);
        for d in ALL {
            for i in integrands() {
                for _ in 0..2000 {
                    let s = d.sample(Vec2::new(u(), u()));
                    if s.dir.z < 1e-3 || s.dir.z > 1.0 - 1e-3 {
                        continue;
                    }
                    let want = i.density(s.dir) / d.pdf(s.dir) as f64;
                    let got = i.weight(d, s.dir) as f64;
                    assert!((got - want).abs() <= 1e-4 * want.max(1.0), "{d} {i} {}: {got} vs {want}", s.dir);
                    if i == Integrand::Ao {
                        assert_eq!(i.weight(d, s.dir), s.weight);
                    }
                    if i.unit_weight(d) {
                        assert_eq!(i.weight(d, s.dir), 1.0);
                    }
                }
            }
        }
    }

    /// The issue's table, re-derived: the closed forms against its rounded values.
    #[test]
    fn closed_forms_give_the_issues_table() {
        use Distribution::*;
        let table: [(Integrand, [f64; 3]); 6] = [
            (Integrand::Visibility, [0.0, f64::INFINITY, 0.234]),
            (Integrand::Ao, [1.0 / 3.0, 0.0, 0.234]),
            (Integrand::CosLobe(4), [1.78, 0.56, 0.69]),
            (Integrand::CosLobe(8), [3.76, 1.53, 1.18]),
            (Integrand::CosLobe(32), [15.8, 7.51, 3.04]),
            (Integrand::CosLobe(128), [63.8, 31.5, 6.93]),
        ];
        for (i, row) in table {
            for (d, want) in [Sine, SineCosine, Uniform].into_iter().zip(row) {
                let got = i.closed_room_variance(d);
                let ok = if want.is_infinite() {
                    got.is_infinite()
                } else {
                    (got - want).abs() <= 0.006 * want.max(1.0)
                };
                assert!(ok, "{i} {d}: {got} vs the issue's {want}");
            }
        }
        assert!((Integrand::Ao.closed_room_variance(Uniform) - (PI * PI / 8.0 - 1.0)).abs() < 1e-12);
        assert!((Integrand::Visibility.closed_room_variance(Uniform) - (PI * PI / 8.0 - 1.0)).abs() < 1e-12);
    }

    /// Per cell, the sample mean and variance of 2^18 weights (every ray blocked, so the closed
    /// room's estimator) against the closed forms: the mean within 5 standard errors of 1, the
    /// variance within 5 standard errors of the closed form, the standard error of the sample
    /// variance estimated from the sample's fourth central moment, √((m4 − s⁴)/N). The infinite
    /// cell is told apart by its largest weights: 1/(2 cos θ) with cos θ = √(1−v) exceeds 100 in
    /// 2^18 draws (it does so with probability 1 − (1 − 2.5e-5)^N ≈ 0.999), where every finite cell's
    /// weights stay under (n+1)π/2 · max(sin θ cosⁿθ) or (n+1).
    #[test]
    fn per_ray_variance_matches_the_closed_form_per_cell() {
        let n = 1usize << 18;
        for d in ALL {
            for i in integrands() {
                let mut u = uniforms(7);
                let w: Vec<f64> =
                    (0..n).map(|_| i.weight(d, d.sample(Vec2::new(u(), u())).dir) as f64).collect();
                let mean = w.iter().sum::<f64>() / n as f64;
                let m2 = w.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
                let m4 = w.iter().map(|x| (x - mean).powi(4)).sum::<f64>() / n as f64;
                let max = w.iter().cloned().fold(0.0, f64::max);
                let want = i.closed_room_variance(d);
                if want.is_infinite() {
                    assert!(max > 100.0, "{d} {i}: largest weight {max} (infinite variance expected)");
                    continue;
                }
                assert!(
                    max <= i.weight_bound(d) * (1.0 + 1e-5),
                    "{d} {i}: weight {max} > {}",
                    i.weight_bound(d)
                );
                assert!(max >= 0.95 * i.weight_bound(d), "{d} {i}: weight {max} << {}", i.weight_bound(d));
                let se_mean = (m2 / n as f64).sqrt();
                assert!((mean - 1.0).abs() <= 5.0 * se_mean + 1e-6, "{d} {i}: mean {mean} ± {se_mean}");
                let se_var = ((m4 - m2 * m2).max(0.0) / n as f64).sqrt();
                assert!(
                    (m2 - want).abs() <= 5.0 * se_var + 1e-6,
                    "{d} {i}: variance {m2} vs {want} ± {se_var}"
                );
            }
        }
    }
}

//! Does each of the paper's claims hold on each scene? Pure: records in, verdicts out; the page
//! (`report::run::verdicts`) prints them as the report's first table and `tests/claims/scenes.rs` asserts them.
//!
//! Every margin is in standard errors of a *paired* difference (`margin::paired`): replicate r of
//! every configuration uses the same seed, so configurations are compared replicate by replicate,
//! d_r = worse_r − better_r, with the standard error sd(d) / √n.
//!
//! A claim *holds* when its margin is at least the two-sided 1 % quantile of Student's t with n − 1
//! degrees of freedom at every ray count it is checked at, *fails* when the opposite is that
//! significant at any ray count, and is *not significant* otherwise: that is the per-cell verdict.
//!
//! A table of 42 cells each tested at 1 % would show a false "holds" or "fails" somewhere far more
//! often than 1 % of the time, so the table's verdicts are also stated **family-wise**
//! (`family_wise`): each cell has one p-value — the largest over its ray counts when every margin
//! is positive (it holds only if all do: an intersection–union test), or its most negative
//! margin's times the ray counts checked when one is negative (it fails if any does: Bonferroni
//! within the cell) — and Holm's step-down procedure over the table's measured cells
//! (`stats::holm_adjusted`) keeps the chance of any false verdict in the table at most `ALPHA`.

use crate::compare::margin::{self, Margin, paired};
use crate::compare::structure::{equally, is_structured};
use crate::metrics::STRUCTURED_RATIO;
use crate::results::JobResult;
use crate::sampling::{Distribution, SeedMode, Sequence};
use crate::spec::Row;

/// Two-sided significance level of a verdict: per cell, and family-wise over a table's cells.
pub const ALPHA: f64 = 0.01;

/// A configuration the claims name.
pub type Config = Row;

const fn row(distribution: Distribution, sequence: Sequence, seed_mode: SeedMode) -> Row {
    Row { distribution, sequence, seed_mode }
}

pub const UNIFORM_RANDOM: Config = row(Distribution::Uniform, Sequence::Random, SeedMode::Rotation);
pub const SINE_RANDOM: Config = row(Distribution::Sine, Sequence::Random, SeedMode::Rotation);
pub const COSINE_RANDOM: Config = row(Distribution::SineCosine, Sequence::Random, SeedMode::Rotation);
/// The paper's "random seed per pixel": the lattice rotated about the normal per pixel.
pub const COSINE_FIB_PIXEL: Config = row(Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Rotation);
pub const COSINE_FIB_STATIC: Config = row(Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Static);

/// The claims, as the report words them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Claim {
    /// Table 2: with pseudo-random numbers, sine-cosine has lower RMSE than uniform.
    CosineBeatsUniform,
    /// Table 2: … and lower than sine.
    CosineBeatsSine,
    /// Table 3: the Fibonacci lattice with a per-pixel seed has lower RMSE than pseudo-random numbers.
    FibonacciBeatsRandom,
    /// Table 3: the static seed's error is structured: its low-frequency ratio above the per-pixel
    /// seed's and structured by `structure::is_structured` (mean ratio above `STRUCTURED_RATIO`, the
    /// verdict the report and `advise` use; the whiteness z would flag blue noise too).
    StaticSeedStructured,
    /// Convergence: pseudo-random RMSE falls as rays^−½ (slope within ±`SLOPE_TOLERANCE` of −0.5).
    RandomSlopeHalf,
    /// Convergence: the lattice with a per-pixel seed converges faster (steeper slope) than pseudo-random.
    FibonacciSteeper,
    /// Equal time: the lattice with a per-pixel seed has less MSE than each sampler a
    /// renderer would ship instead (sine-cosine, randomized per pixel by `shift`), at every time
    /// budget both were measured at (`compare::equal_time`). Fails where that sampler wins.
    FibonacciBeatsAtEqualTime(Sequence),
}

/// How far a pseudo-random slope may sit from −0.5 and still "hold": the reference's noise floor
/// (≤ 1/10 of the smallest RMSE) flattens the end of the curve by up to ~0.01.
pub const SLOPE_TOLERANCE: f64 = 0.05;

impl Claim {
    /// The paper's six claims, then one equal-time claim per sampler renderers ship
    /// (`Sequence::shipped`, in its order).
    pub fn all() -> Vec<Claim> {
        let mut v = vec![
            Claim::CosineBeatsUniform,
            Claim::CosineBeatsSine,
            Claim::FibonacciBeatsRandom,
            Claim::StaticSeedStructured,
            Claim::RandomSlopeHalf,
            Claim::FibonacciSteeper,
        ];
        v.extend(Sequence::shipped().into_iter().map(Claim::FibonacciBeatsAtEqualTime));
        v
    }

    pub fn label(self) -> String {
        let text = match self {
            Claim::CosineBeatsUniform => "sine-cosine < uniform (pseudo-random)",
            Claim::CosineBeatsSine => "sine-cosine < sine (pseudo-random)",
            Claim::FibonacciBeatsRandom => "Fibonacci, per-pixel seed < pseudo-random",
            Claim::StaticSeedStructured => "static seed's error is structured",
            Claim::RandomSlopeHalf => "pseudo-random slope = −0.5",
            Claim::FibonacciSteeper => "Fibonacci slope steeper than pseudo-random",
            Claim::FibonacciBeatsAtEqualTime(s) => {
                return format!("Fibonacci per-pixel beats {} at equal time", s.name());
            }
        };
        text.to_string()
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    Holds,
    Fails,
    NotSignificant,
    /// The run did not measure what the claim needs.
    NotMeasured,
}

impl Outcome {
    pub fn label(self) -> &'static str {
        match self {
            Outcome::Holds => "holds",
            Outcome::Fails => "fails",
            Outcome::NotSignificant => "not significant",
            Outcome::NotMeasured => "not measured",
        }
    }
}

/// The margin (in SE) a paired comparison of `n` pairs needs to be significant at `ALPHA`
/// (`margin::critical_se`).
pub fn critical_se(n: usize) -> f64 {
    margin::critical_se(ALPHA, n)
}

/// `b − a` where it can carry a verdict: `margin::paired` over at least two pairs.
fn measured(a: &[(u32, f64)], b: &[(u32, f64)]) -> Option<Margin> {
    paired(a, b).measured()
}

/// One cell of the verdict table.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    pub scene: String,
    pub claim: Claim,
    pub outcome: Outcome,
    /// The weakest margin over the ray counts checked, in standard errors (NaN if not measured).
    pub margin_se: f64,
    /// The numbers behind it, e.g. "8: +19.1, 16: +25.3, 32: +27.0 SE".
    pub detail: String,
    /// The cell's p-value (see the module's text; NaN if not measured).
    pub p_value: f64,
    /// Whether every condition besides the margins holds (the static seed's mean structure
    /// measure above the threshold): without it the cell cannot hold, per cell or family-wise.
    pub extra: bool,
    /// Holm's adjusted p-value over the table's cells and the verdict at family-wise `ALPHA`
    /// (`family_wise`; until then, the per-cell ones).
    pub holm_p: f64,
    pub family: Outcome,
}

/// `(replicate, value)` of one configuration at one ray count on one scene.
fn values(rs: &[JobResult], scene: &str, c: Config, rays: u32, f: fn(&JobResult) -> f64) -> Vec<(u32, f64)> {
    rs.iter().filter(|r| r.is(scene, c, rays)).map(|r| (r.replicate, f(r))).collect()
}

/// Per replicate: the least-squares log-log slope of RMSE against rays over `rays`.
pub fn replicate_slopes(rs: &[JobResult], scene: &str, c: Config, rays: &[u32]) -> Vec<(u32, f64)> {
    let mut reps: Vec<u32> = rs.iter().filter(|r| r.scene == scene).map(|r| r.replicate).collect();
    reps.sort_unstable();
    reps.dedup();
    reps.into_iter()
        .filter_map(|rep| {
            let pts: Vec<(f64, f64)> = rays
                .iter()
                .filter_map(|&n| {
                    values(rs, scene, c, n, |r| r.rmse)
                        .into_iter()
                        .find(|v| v.0 == rep)
                        .map(|v| (n as f64, v.1))
                })
                .collect();
            if pts.len() < rays.len() || pts.len() < 2 {
                return None;
            }
            let (x, y): (Vec<f64>, Vec<f64>) = pts.into_iter().unzip();
            crate::stats::loglog_fit(&x, &y).map(|f| (rep, f.slope))
        })
        .collect()
}

/// A cell's p-value from its margins: the largest when every one is positive (all must be
/// significant for it to hold), else the most significant negative one's times the number of
/// margins (any one significant makes it fail), capped at 1.
fn cell_p(margins: &[Margin]) -> f64 {
    if margins.iter().all(|m| m.in_se() > 0.0) {
        margins.iter().map(Margin::p_two_sided).fold(0.0, f64::max)
    } else {
        let least = margins.iter().filter(|m| m.in_se() <= 0.0).map(Margin::p_two_sided).fold(1.0, f64::min);
        (least * margins.len() as f64).min(1.0)
    }
}

/// Combines per-ray-count margins: holds if every one is significantly positive (and `extra` holds),
/// fails if any is significantly negative.
fn judge(scene: &str, claim: Claim, margins: Vec<(String, Option<Margin>)>, extra: bool) -> Verdict {
    let measured: Vec<(String, Margin)> =
        margins.into_iter().filter_map(|(k, m)| m.map(|m| (k, m))).collect();
    if measured.is_empty() {
        return Verdict {
            scene: scene.into(),
            claim,
            outcome: Outcome::NotMeasured,
            margin_se: f64::NAN,
            detail: "–".into(),
            p_value: f64::NAN,
            extra,
            holm_p: f64::NAN,
            family: Outcome::NotMeasured,
        };
    }
    let sig = |m: &Margin| critical_se(m.n);
    let weakest = measured.iter().map(|(_, m)| m.in_se()).fold(f64::INFINITY, f64::min);
    let outcome = if measured.iter().any(|(_, m)| m.in_se() <= -sig(m)) {
        Outcome::Fails
    } else if extra && measured.iter().all(|(_, m)| m.in_se() >= sig(m)) {
        Outcome::Holds
    } else {
        Outcome::NotSignificant
    };
    let detail =
        measured.iter().map(|(k, m)| format!("{k}: {}", fmt_se(m.in_se()))).collect::<Vec<_>>().join(", ");
    let p_value = cell_p(&measured.iter().map(|(_, m)| *m).collect::<Vec<_>>());
    Verdict {
        scene: scene.into(),
        claim,
        outcome,
        margin_se: weakest,
        detail,
        p_value,
        extra,
        holm_p: p_value,
        family: outcome,
    }
}

/// The table's verdicts family-wise: Holm's adjusted p-value over every measured cell of
/// `verdicts` (the family is the slice), and the verdict at family-wise level `ALPHA` — holds or
/// fails, by the sign of the weakest margin, where the adjusted p-value is at most `ALPHA` (holds
/// only with `extra`), not significant elsewhere. The per-cell verdicts are left as they are.
pub fn family_wise(verdicts: &mut [Verdict]) {
    let p: Vec<f64> = verdicts.iter().map(|v| v.p_value).collect();
    for (v, q) in verdicts.iter_mut().zip(crate::stats::holm_adjusted(&p)) {
        v.holm_p = q;
        v.family = if v.outcome == Outcome::NotMeasured {
            Outcome::NotMeasured
        } else if q <= ALPHA && v.margin_se < 0.0 {
            Outcome::Fails
        } else if q <= ALPHA && v.margin_se > 0.0 && v.extra {
            Outcome::Holds
        } else {
            Outcome::NotSignificant
        };
    }
}

/// How many cells of `verdicts` hold (per cell, family-wise).
pub fn holding(verdicts: &[Verdict]) -> (usize, usize) {
    let count = |f: fn(&Verdict) -> Outcome| verdicts.iter().filter(|v| f(v) == Outcome::Holds).count();
    (count(|v| v.outcome), count(|v| v.family))
}

/// "+12.3 SE", "+∞ SE".
pub fn fmt_se(x: f64) -> String {
    if x.is_infinite() {
        format!("{}∞ SE", if x > 0.0 { "+" } else { "−" })
    } else {
        format!("{x:+.1} SE")
    }
}

/// Every claim on `scene`: the RMSE comparisons at each of `rays`, the slopes over `sweep`.
pub fn scene_verdicts(rs: &[JobResult], scene: &str, rays: &[u32], sweep: &[u32]) -> Vec<Verdict> {
    let rmse = |c: Config, n: u32| values(rs, scene, c, n, |r| r.rmse);
    let ratio = |c: Config, n: u32| values(rs, scene, c, n, |r| r.lowfreq_ratio);
    let lower = |better: Config, worse: Config| -> Vec<(String, Option<Margin>)> {
        rays.iter().map(|&n| (n.to_string(), measured(&rmse(better, n), &rmse(worse, n)))).collect()
    };
    let mut out = vec![
        judge(scene, Claim::CosineBeatsUniform, lower(COSINE_RANDOM, UNIFORM_RANDOM), true),
        judge(scene, Claim::CosineBeatsSine, lower(COSINE_RANDOM, SINE_RANDOM), true),
        judge(scene, Claim::FibonacciBeatsRandom, lower(COSINE_FIB_PIXEL, COSINE_RANDOM), true),
    ];
    let structured: Vec<(String, Option<Margin>)> = rays
        .iter()
        .map(|&n| (n.to_string(), measured(&ratio(COSINE_FIB_PIXEL, n), &ratio(COSINE_FIB_STATIC, n))))
        .collect();
    let above = rays
        .iter()
        .all(|&n| is_structured(&equally(rs.iter().filter(|r| r.is(scene, COSINE_FIB_STATIC, n)))));
    let mut v = judge(scene, Claim::StaticSeedStructured, structured, above);
    if v.outcome == Outcome::NotSignificant && !above {
        v.detail += &format!(
            " (the static seed's mean low-frequency ratio is not above {STRUCTURED_RATIO} at every ray count)"
        );
    }
    out.push(v);

    let random = replicate_slopes(rs, scene, COSINE_RANDOM, sweep);
    // |slope + 0.5| below the tolerance: the margin is tolerance − |deviation|, in SE of the mean slope.
    let half = measured(&random.iter().map(|&(r, _)| (r, 0.0)).collect::<Vec<_>>(), &random)
        .map(|m| Margin { mean: SLOPE_TOLERANCE - (m.mean + 0.5).abs(), ..m });
    let mut v = judge(scene, Claim::RandomSlopeHalf, vec![("slope".into(), half)], true);
    if let Some(m) = measured(&random.iter().map(|&(r, _)| (r, 0.0)).collect::<Vec<_>>(), &random) {
        v.detail =
            format!("slope {:+.3} ± {:.3} (SE); margin to ±{SLOPE_TOLERANCE}: {}", m.mean, m.se, v.detail);
    }
    out.push(v);
    let fib = replicate_slopes(rs, scene, COSINE_FIB_PIXEL, sweep);
    // Steeper = more negative: the margin is random − fibonacci.
    let steeper = measured(&fib, &random);
    let mut v = judge(scene, Claim::FibonacciSteeper, vec![("slopes".into(), steeper)], true);
    if let (Some(a), Some(b)) = (mean(&random), mean(&fib)) {
        v.detail = format!("{a:+.3} vs {b:+.3}: {}", v.detail);
    }
    out.push(v);
    for claim in Claim::all() {
        if let Claim::FibonacciBeatsAtEqualTime(seq) = claim {
            out.push(equal_time_claim(
                rs,
                scene,
                claim,
                row(Distribution::SineCosine, seq, SeedMode::Shift),
                sweep,
            ));
        }
    }
    out
}

/// `claim` = the lattice with a per-pixel seed has less MSE than `other` at equal time: one
/// margin per time budget (one to each doubling of time, over the times both were measured at
/// across `sweep`), ln(MSE other / MSE lattice) in its standard errors (`equal_time::Ratio`,
/// paired by replicate), over the replicates of the lattice's first ray count.
fn equal_time_claim(rs: &[JobResult], scene: &str, claim: Claim, other: Config, sweep: &[u32]) -> Verdict {
    use crate::compare::equal_time::{TimeView, equal_time};
    let swept = |c: Config| sweep.iter().any(|&n| rs.iter().any(|r| r.is(scene, c, n)));
    let mut margins: Vec<(String, Option<Margin>)> = Vec::new();
    if swept(other) && swept(COSINE_FIB_PIXEL) {
        let n = values(rs, scene, COSINE_FIB_PIXEL, sweep[0], |r| r.rmse).len();
        let et = equal_time(rs, scene, &[COSINE_FIB_PIXEL, other], sweep, TimeView::Total, 1);
        for at in &et.at {
            if let (Some(a), Some(b)) = (at.entry(other), at.entry(COSINE_FIB_PIXEL)) {
                let r = crate::compare::equal_time::Ratio::of(&a.at, &b.at);
                let m = Margin { mean: r.value.ln(), se: r.se / r.value, n, base: f64::NAN };
                margins.push((format!("{:.3} ms (MSE ×{:.2})", at.budget_s * 1e3, r.value), Some(m)));
            }
        }
    }
    judge(scene, claim, margins, true)
}

fn mean(v: &[(u32, f64)]) -> Option<f64> {
    (!v.is_empty()).then(|| v.iter().map(|x| x.1).sum::<f64>() / v.len() as f64)
}

#[cfg(test)]
mod tests;

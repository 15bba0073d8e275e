//! `hemilab advise`'s arithmetic (pure: no IO, no rendering): which configuration gives the least
//! error **at equal time**, from each configuration's measured ladder of ray counts.
//!
//! - **Equal time**: a configuration's points (median time per image, error) are joined by straight
//!   lines in log time and log error, so a budget between two measured ray counts gets the error
//!   the configuration would have there (`locate`, `at_budget`). Error falls as a power of time to
//!   a good approximation between neighbouring ray counts a factor 2 apart, so the line is nearly
//!   exact; a budget outside a configuration's measured times is never extrapolated, only reported
//!   as outside (`Place::Below` / `Place::Above`).
//! - **Replicates**: each replicate's MSE is interpolated on its own (the same weight for all), so
//!   a configuration's mean MSE at the budget has a σ from their spread; replicate r has the same
//!   seed in every configuration, so two configurations are compared replicate by replicate. Every
//!   ± and margin is 1 σ of the one error model of `advice/model.rs` (replicates and times).
//! - **Which configurations**: every distribution × sequence × seed mode that is a distinct,
//!   sensible estimator (`sensible_rows`), or the subset `--only` patterns select (`select`).
//!
//! What is shipped — each budget's finalists measured at the integer ray count that fits it — is in
//! `advice/answer.rs`; whether an error is structured in `advice/structure.rs`; the per-pixel winner
//! map in `advice/winner.rs`.

pub mod analysis;
pub mod answer;
pub mod model;
pub mod pipeline;
pub mod setup;
pub mod structure;
pub mod winner;

use crate::sampling::{Distribution, SeedMode, Sequence};
use crate::spec::Row;

/// The paper's default estimator, the baseline of every gain: sine-cosine with pseudo-random
/// numbers, fresh in every pixel (its "random seed per pixel").
pub const PAPER_DEFAULT: Row =
    Row { distribution: Distribution::SineCosine, sequence: Sequence::Random, seed_mode: SeedMode::Rotation };

/// Why a row is left out of the default set, or `None` if it is a distinct, sensible estimator.
/// (`random` × `shift` is `random` × `rotation` by `Row::canonical` and never reaches here.)
pub fn not_sensible(row: Row) -> Option<&'static str> {
    match (row.distribution, row.sequence, row.seed_mode) {
        (_, Sequence::Random, SeedMode::Static) => {
            Some("one set of pseudo-random numbers in every pixel: the static seed without the lattice")
        }
        // One frame of it is a 2-D blue-noise mask, what `blue-noise` already is; it differs only
        // over frames, which a single image does not see. Asked for by name, it is measured.
        (_, _, SeedMode::Stbn) => {
            Some("for one frame, a spatiotemporal mask's slice is a 2-D blue-noise mask like `blue-noise`'s")
        }
        // The samplers renderers ship beside the paper's (`SequenceInfo::shipped`) are measured
        // as they ship: randomized per pixel, and ZSobol also unscrambled per pixel (its Morton
        // blocks are what spreads its error as blue noise). Their other seed modes run when named
        // with --only; all of them would double the sweep.
        (_, s, m) if s.info().shipped.is_some_and(|sh| !sh.modes.contains(&m)) => {
            s.info().shipped.map(|sh| sh.why)
        }
        (Distribution::ConcentricCosine, s, SeedMode::Rotation) if s != Sequence::Random => {
            Some("through the concentric map an x offset is not a rotation about the normal")
        }
        // The engines' patterns rotate the static set by a fixed, tiled pattern (docs/textures.md):
        // one image of it is a structured x offset between `rotation` (white) and `blue-noise`
        // (blue, and 2-D); they are built for frames accumulated and filtered, where `--pipeline`
        // with --only `*/*/ign` (or bayer, magic-square, r2-dither) measures them. In the default
        // sweep they would add 4 × 4 × 5 rows of one kind.
        (_, _, m) if m.pattern().is_some() => {
            Some("an engine's rotation pattern (ign, bayer, magic-square, r2-dither): name it with --only")
        }
        // A file's texture (`advise --texture`) is measured as its use says: an offset texture as
        // `blue-noise` is, a rotation texture as `rotation`, a vector texture only with sine-cosine.
        (d, _, m) if m.texture_use() == Some(crate::sampling::texture::TextureUse::Vector) => (d
            != Distribution::SineCosine)
            .then_some("a vector texture holds cosine-weighted directions: sine-cosine only"),
        (Distribution::ConcentricCosine, s, m)
            if m.texture_use() == Some(crate::sampling::texture::TextureUse::Rotation)
                && s != Sequence::Random =>
        {
            Some("through the concentric map an x offset is not a rotation about the normal")
        }
        _ => None,
    }
}

/// The sensible rows that name at least one of the `sequences` or `modes` a command line added
/// (point files, textures: `advise --points`, `--texture`), over every distribution, built-in or
/// added sequence and seed mode, canonical and in that order.
pub fn sensible_rows_with(sequences: &[Sequence], modes: &[SeedMode]) -> Vec<Row> {
    let builtin: Vec<Sequence> =
        Sequence::all().into_iter().filter(|s| !s.name().starts_with("points:")).collect();
    let all_s: Vec<Sequence> = builtin.iter().chain(sequences).copied().collect();
    let all_m: Vec<SeedMode> = SeedMode::ALL.iter().chain(modes).copied().collect();
    let mut rows = Vec::new();
    for &d in Distribution::ALL {
        for &s in &all_s {
            for &m in &all_m {
                if !sequences.contains(&s) && !modes.contains(&m) {
                    continue;
                }
                let r = Row::new(d, s, m).canonical();
                if not_sensible(r).is_none() && r.invalid().is_none() && !rows.contains(&r) {
                    rows.push(r);
                }
            }
        }
    }
    rows
}

/// Every distribution × sequence × seed mode that `advise` runs by default: canonical (duplicates
/// such as `random` × `shift` = `random` × `rotation` merged) and sensible (`not_sensible`), in the
/// order of `Distribution::ALL`, `Sequence::all()`, `SeedMode::ALL`.
pub fn sensible_rows() -> Vec<Row> {
    let mut rows = Vec::new();
    for &d in Distribution::ALL {
        for s in Sequence::all() {
            for &m in SeedMode::ALL {
                let r = Row::new(d, s, m).canonical();
                if not_sensible(r).is_none() && !rows.contains(&r) {
                    rows.push(r);
                }
            }
        }
    }
    rows
}

/// One `--only` item, `distribution/sequence/seed_mode`, each part a name or `*` (any).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pattern {
    pub distribution: Option<Distribution>,
    pub sequence: Option<Sequence>,
    pub seed_mode: Option<SeedMode>,
}

impl Pattern {
    /// `sine-cosine/fibonacci/*`, `*/*/blue-noise`, …; the message names the item and what is allowed.
    pub fn parse(s: &str) -> Result<Self, String> {
        let parts: Vec<&str> = s.trim().split('/').map(str::trim).collect();
        let [d, q, m] = parts[..] else {
            return Err(format!(
                "'{s}' must be distribution/sequence/seed_mode, each a name or *, e.g. sine-cosine/fibonacci/*"
            ));
        };
        fn part<T: std::str::FromStr<Err = String>>(p: &str) -> Result<Option<T>, String> {
            if p == "*" { Ok(None) } else { p.parse().map(Some) }
        }
        let at = |e: String| format!("'{s}': {e}");
        Ok(Self {
            distribution: part(d).map_err(at)?,
            sequence: part(q).map_err(at)?,
            seed_mode: part(m).map_err(at)?,
        })
    }

    /// The pattern as `parse` reads it back.
    pub fn to_text(&self) -> String {
        let show = |o: Option<&str>| o.unwrap_or("*").to_string();
        format!(
            "{}/{}/{}",
            show(self.distribution.map(|d| d.name())),
            show(self.sequence.map(|s| s.name())),
            show(self.seed_mode.map(|m| m.name()))
        )
    }

    fn exact(&self) -> Option<Row> {
        Some(Row::new(self.distribution?, self.sequence?, self.seed_mode?).canonical())
    }

    fn matches(&self, r: Row) -> bool {
        self.distribution.is_none_or(|d| d == r.distribution)
            && self.sequence.is_none_or(|s| s == r.sequence)
            && self.seed_mode.is_none_or(|m| m == r.seed_mode)
    }
}

/// The configurations to run: all sensible rows (no patterns), else those the patterns match — a
/// fully named pattern is taken as asked even if not in the default set — and always the paper's
/// default (every gain is against it), first. A pattern that matches nothing is an error.
pub fn select(patterns: &[Pattern]) -> Result<Vec<Row>, String> {
    select_with(patterns, &[])
}

/// `select` over the sensible rows and `added` (the rows of `advise --texture`, `--points`:
/// `sensible_rows_with`), which patterns select as they select the built-ins'.
pub fn select_with(patterns: &[Pattern], added: &[Row]) -> Result<Vec<Row>, String> {
    let mut all = sensible_rows();
    all.extend(added.iter().filter(|r| !all.contains(r)).copied().collect::<Vec<_>>());
    let mut rows = vec![PAPER_DEFAULT];
    if patterns.is_empty() {
        rows.extend(all.into_iter().filter(|r| *r != PAPER_DEFAULT));
        return Ok(rows);
    }
    for p in patterns {
        let hits: Vec<Row> = match p.exact() {
            Some(r) => vec![r],
            None => all.iter().copied().filter(|r| p.matches(*r)).collect(),
        };
        if hits.is_empty() {
            return Err(format!(
                "'{}' matches no configuration of the default set (which leaves out random × static \
                 and concentric-cosine × rotation of a lattice, scramble or jitter, and stbn, whose single \
                 frame is a 2-D blue-noise mask; name one in full to run it)",
                p.to_text()
            ));
        }
        for r in hits {
            if !rows.contains(&r) {
                rows.push(r);
            }
        }
    }
    Ok(rows)
}

/// One measured ray count of one configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub rays: u32,
    /// Median time per image (seconds, the timing protocol's), the σ of its ln within the session
    /// (`model::median_sigma_ln`) and how many timed renders it is the median of.
    pub time_s: f64,
    pub time_sigma_ln: f64,
    pub timings: usize,
    /// Replicate ids and, for each, the image's MSE and low-pass MSE (squared low-pass RMSE).
    pub replicates: Vec<u32>,
    pub mse: Vec<f64>,
    pub lowpass_mse: Vec<f64>,
    /// Each replicate's value of the structure measure (`structure::of`).
    pub structure: Vec<f64>,
}

/// A configuration's ladder, points in increasing ray count.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    pub row: Row,
    pub points: Vec<Point>,
}

/// Which error a ranking is by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Metric {
    Rmse,
    /// RMSE of the error after the σ = 1.5 px Gaussian blur: what a blur or denoiser leaves.
    Lowpass,
}

/// Where a budget falls on a configuration's measured times.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Place {
    /// Cheaper than its cheapest measured render, which takes `fastest_s`.
    Below { fastest_s: f64 },
    /// Dearer than its dearest measured render, which takes `slowest_s`.
    Above { slowest_s: f64 },
    /// Between points `lo` and `lo + 1`, at weight `w` in [0, 1] along log time.
    Inside { lo: usize, w: f64 },
}

/// Log times made non-decreasing in ray count (pool-adjacent-violators, equal weights): more rays
/// never cost less, so a median that came out below its cheaper neighbour's is timing noise, and
/// the two are replaced by their mean.
pub fn monotone_log_times(points: &[Point]) -> Vec<f64> {
    let mut blocks: Vec<(f64, usize)> = Vec::new(); // (mean, size)
    for p in points {
        blocks.push((p.time_s.ln(), 1));
        while blocks.len() > 1 && blocks[blocks.len() - 2].0 > blocks[blocks.len() - 1].0 {
            let (b, nb) = blocks.pop().expect("two blocks");
            let (a, na) = blocks.pop().expect("two blocks");
            blocks.push(((a * na as f64 + b * nb as f64) / (na + nb) as f64, na + nb));
        }
    }
    blocks.into_iter().flat_map(|(m, n)| std::iter::repeat_n(m, n)).collect()
}

/// Where `budget_s` falls on `curve`. At a time shared by several points (flattened by
/// `monotone_log_times`) the one with the most rays is taken: same time, more rays.
pub fn locate(curve: &Curve, budget_s: f64) -> Place {
    let lt = monotone_log_times(&curve.points);
    let (Some(&first), Some(&last)) = (lt.first(), lt.last()) else {
        return Place::Below { fastest_s: f64::NAN };
    };
    let lb = budget_s.ln();
    if lt.len() < 2 || lb < first || !lb.is_finite() {
        return Place::Below { fastest_s: first.exp() };
    }
    if lb > last {
        return Place::Above { slowest_s: last.exp() };
    }
    let i = lt.iter().rposition(|&t| t <= lb).expect("lb >= first");
    if i == lt.len() - 1 {
        return Place::Inside { lo: i - 1, w: 1.0 };
    }
    Place::Inside { lo: i, w: (lb - lt[i]) / (lt[i + 1] - lt[i]) }
}

/// Geometric interpolation, exact at the ends (so a zero end needs no logarithm there).
fn geo(a: f64, b: f64, w: f64) -> f64 {
    if w <= 0.0 {
        a
    } else if w >= 1.0 {
        b
    } else {
        (a.ln() * (1.0 - w) + b.ln() * w).exp()
    }
}

/// Mean and its standard error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub value: f64,
    pub se: f64,
}

/// A configuration at a budget, interpolated.
#[derive(Debug, Clone, PartialEq)]
pub struct AtBudget {
    pub row: Row,
    /// Rays per pixel the budget buys (geometric interpolation between the two ray counts).
    pub rays: f64,
    pub replicates: Vec<u32>,
    /// Per replicate: MSE and low-pass MSE at the budget.
    pub mse: Vec<f64>,
    pub lowpass_mse: Vec<f64>,
    /// d ln(mean MSE) / d ln(time) on the segment, and the same for the low-pass MSE.
    pub slope: f64,
    pub lowpass_slope: f64,
    /// σ of ln(time) within the session there (the two points' `time_sigma_ln`, interpolated).
    pub time_sigma_ln: f64,
    /// Mean of the structure measure over the replicates, interpolated linearly between the points.
    pub structure: f64,
    /// The two measured points the budget lies between, and the weight; the ray count of the
    /// first (the sweep measured it within the budget).
    pub lo: usize,
    pub w: f64,
    pub lo_rays: u32,
}

impl AtBudget {
    /// Whether its error is structured (bands, moiré) rather than noise (`structure::structured`).
    pub fn structured(&self) -> bool {
        structure::structured(self.structure)
    }

    /// What a comparison under the error model needs of it.
    pub fn side(&self, m: Metric) -> model::Side<'_> {
        let (values, slope) = match m {
            Metric::Rmse => (&self.mse, self.slope),
            Metric::Lowpass => (&self.lowpass_mse, self.lowpass_slope),
        };
        model::Side {
            row: self.row,
            replicates: &self.replicates,
            values,
            slope,
            time_sigma_ln: self.time_sigma_ln,
        }
    }

    /// Mean MSE (or low-pass MSE) at the budget ± 1 σ (replicates and time, `model::mean_mse`).
    pub fn mean_mse(&self, m: Metric) -> Estimate {
        model::mean_mse(&self.side(m), true)
    }

    /// √(mean MSE) ± 1 σ.
    pub fn rmse(&self, m: Metric) -> Estimate {
        model::rmse(self.mean_mse(m))
    }
}

/// `curve` at `budget_s`, or where the budget lies outside its measured times.
pub fn at_budget(curve: &Curve, budget_s: f64) -> Result<AtBudget, Place> {
    let (lo, w) = match locate(curve, budget_s) {
        Place::Inside { lo, w } => (lo, w),
        outside => return Err(outside),
    };
    let (a, b) = (&curve.points[lo], &curve.points[lo + 1]);
    let mut replicates = Vec::new();
    let (mut mse, mut lowpass_mse) = (Vec::new(), Vec::new());
    for (i, r) in a.replicates.iter().enumerate() {
        if let Some(j) = b.replicates.iter().position(|x| x == r) {
            replicates.push(*r);
            mse.push(geo(a.mse[i], b.mse[j], w));
            lowpass_mse.push(geo(a.lowpass_mse[i], b.lowpass_mse[j], w));
        }
    }
    let lt = monotone_log_times(&curve.points);
    let dt = lt[lo + 1] - lt[lo];
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let slope = |fa: f64, fb: f64| if dt > 0.0 { (fb.ln() - fa.ln()) / dt } else { 0.0 };
    Ok(AtBudget {
        row: curve.row,
        rays: geo(a.rays as f64, b.rays as f64, w),
        replicates,
        mse,
        lowpass_mse,
        slope: slope(mean(&a.mse), mean(&b.mse)),
        lowpass_slope: slope(mean(&a.lowpass_mse), mean(&b.lowpass_mse)),
        time_sigma_ln: (1.0 - w) * a.time_sigma_ln + w * b.time_sigma_ln,
        structure: (1.0 - w) * mean(&a.structure) + w * mean(&b.structure),
        lo,
        w,
        lo_rays: a.rays,
    })
}

/// Every configuration at one budget: those inside their measured times, least error first, and
/// the others with where the budget fell.
#[derive(Debug, Clone, PartialEq)]
pub struct Ranking {
    pub budget_s: f64,
    pub metric: Metric,
    pub ranked: Vec<AtBudget>,
    pub outside: Vec<(Row, Place)>,
}

/// What the sweep alone would ship at a budget: the best-ranked configuration whose error is not
/// structured (`structure::structured`), because a sampler with visible bands or moiré is not an
/// answer a renderer can ship however low its RMSE; the best overall when every one is structured.
pub fn recommended(r: &Ranking) -> Option<&AtBudget> {
    r.ranked.iter().find(|a| !a.structured()).or_else(|| r.ranked.first())
}

pub fn rank(curves: &[Curve], budget_s: f64, metric: Metric) -> Ranking {
    let (mut ranked, mut outside) = (Vec::new(), Vec::new());
    for c in curves {
        match at_budget(c, budget_s) {
            Ok(a) => ranked.push(a),
            Err(p) => outside.push((c.row, p)),
        }
    }
    ranked.sort_by(|a, b| a.mean_mse(metric).value.total_cmp(&b.mean_mse(metric).value));
    Ranking { budget_s, metric, ranked, outside }
}

/// Default budgets when none are given: three times spread over the paper default's measured
/// range — a quarter, half and three quarters of the way in log time from its cheapest to its
/// dearest render — rounded to two significant digits (and kept inside the range). On a narrow
/// range (a tiny image) two of them can round to the same number: then more digits are kept, so
/// there are always three distinct budgets when the range is not a single time.
pub fn default_budgets(paper_default: &Curve) -> Vec<f64> {
    let lt = monotone_log_times(&paper_default.points);
    let (Some(&a), Some(&b)) = (lt.first(), lt.last()) else { return Vec::new() };
    let spread = |digits: usize| {
        let mut out: Vec<f64> = Vec::new();
        for q in [0.25, 0.5, 0.75] {
            let t = round_significant((a + q * (b - a)).exp(), digits).clamp(a.exp(), b.exp());
            if !out.contains(&t) {
                out.push(t);
            }
        }
        out
    };
    (2..=6).map(spread).find(|b| b.len() == 3).unwrap_or_else(|| spread(2))
}

/// How far below the calibrated cheapest render (`jobs::calibrate::cheapest`) a budget must be to
/// be refused before the sweep. The calibration is a fraction of a second of renders with a short
/// warm-up and over-predicts: the sweep's measured cheapest render was 1.17× below it on the
/// kitchen (1.37 against 1.6 ms at 64x48) and 1.33× on the Cornell box (0.21 against 0.28 ms at
/// 32x32), 2026-12-01 at load 9. A budget between this and the cheapest render is swept, and
/// where it is below every measured time the answer says so.
pub const REFUSE_BELOW: f64 = 0.5;

/// The budgets (seconds) no configuration can render an image in: below [`REFUSE_BELOW`] × the
/// calibrated cheapest render.
pub fn impossible(budgets_s: &[f64], cheapest_s: f64) -> Vec<f64> {
    budgets_s.iter().copied().filter(|&b| b < REFUSE_BELOW * cheapest_s).collect()
}

/// `x` rounded to `digits` (≥ 1) significant digits, as the nearest double to that decimal (so
/// 5.1 prints as 5.1, not 5.1000000000000005).
pub fn round_significant(x: f64, digits: usize) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    format!("{:.*e}", digits.max(1) - 1, x).parse().unwrap_or(x)
}

#[cfg(test)]
mod tests;

//! Statistics on records, below `advice` and the report: every comparison, margin and verdict the
//! report's answer and advise's rankings rest on, computed here once (pure: no IO), so that `run`
//! and `advise` answer the same question the same way and the report only formats.
//!
//! - **One paired margin** (`margin`): replicate r uses the same seed in every configuration, so
//!   two configurations are compared replicate by replicate; every verdict of the crate pairs there.
//! - **Equal time** (`budget`, `model`, `equal_time`): each configuration's measured ladder
//!   interpolated at a time budget, ranked by MSE there, with one error model for every ± and
//!   margin; `advise` ranks with the same functions.
//! - **Structure** (`structure`): whether an error is bands or moiré rather than noise, the one
//!   rule every answer applies.
//! - **Verdicts**: the paper's claims (`claims`), the real-time questions (`realtime`), the
//!   integrand statements (`integrands`), as plain data the report words.
//! - **Efficiency** (`efficiency`): the most efficient configuration per ray count and the rank
//!   agreement of two runs; the pooled cost of two configurations (`cost`).
//!
//! Here: which rows are unbiased per pixel, the paper's default, the rows' one-factor pairs, and
//! the paired RMSE of two rows at equal rays.

pub mod budget;
pub mod claims;
pub mod cost;
pub mod efficiency;
pub mod equal_time;
pub mod integrands;
pub mod margin;
pub mod model;
pub mod per_ray;
pub mod realtime;
pub mod structure;

use crate::results::{Aggregate, JobResult};
use crate::sampling::texture::TextureUse;
use crate::sampling::{Distribution, SeedMode, Sequence};
use crate::spec::Row;
use margin::Margin;

/// The paper's default estimator, the baseline of every gain at equal time: sine-cosine with
/// pseudo-random numbers, fresh in every pixel (its "random seed per pixel").
pub const PAPER_DEFAULT: Row =
    Row { distribution: Distribution::SineCosine, sequence: Sequence::Random, seed_mode: SeedMode::Rotation };

/// Whether every pixel's estimate is unbiased: fresh pseudo-random numbers per pixel, or a
/// per-pixel shift (Cranley–Patterson for the lattice, fresh jitter, per-pixel Owen scrambling).
/// A static seed or a rotation keeps part of the point set fixed, so a pixel's error has a mean.
pub fn per_pixel_unbiased(row: Row) -> bool {
    let row = row.canonical();
    match row.seed_mode {
        // A blue-noise mask (2-D or spatiotemporal) shifts every pixel's set by an offset uniform over
        // runs (docs/estimators.md).
        SeedMode::Shift | SeedMode::BlueNoise | SeedMode::Stbn => true,
        // An engine pattern or a rotation texture moves x alone, as `rotation` does: unbiased only
        // where the static set itself is random over runs (docs/estimators.md).
        SeedMode::Rotation | SeedMode::Ign | SeedMode::Bayer | SeedMode::MagicSquare | SeedMode::R2Dither => {
            row.sequence.info().fresh_per_pixel
        }
        // An offset texture is unbiased when its slices are exactly uniform (measured at load); a
        // vector texture's directions are a finite set, never.
        SeedMode::Texture(t) => match t.get().use_() {
            TextureUse::Offset => t.get().uniform(),
            TextureUse::Rotation => row.sequence.info().fresh_per_pixel,
            TextureUse::Vector => false,
        },
        SeedMode::Static => false,
    }
}

/// The row of an aggregate, if its names parse.
pub fn row_of(a: &Aggregate) -> Option<Row> {
    row_of_names(&a.distribution, &a.sequence, &a.seed_mode)
}

/// The row the results' names `distribution`, `sequence`, `seed_mode` denote, if they parse.
pub fn row_of_names(distribution: &str, sequence: &str, seed_mode: &str) -> Option<Row> {
    Some(Row::new(distribution.parse().ok()?, sequence.parse().ok()?, seed_mode.parse().ok()?))
}

fn rmse_by_replicate(results: &[JobResult], scene: &str, row: Row, rays: u32) -> Vec<(u32, f64)> {
    let row = row.canonical();
    let mut v: Vec<(u32, f64)> =
        results.iter().filter(|r| r.is(scene, row, rays)).map(|r| (r.replicate, r.rmse)).collect();
    v.sort_by_key(|x| x.0);
    v
}

/// `b − a` in RMSE (same scene and ray count), paired by replicate (`margin::paired`); its
/// `relative()` is the difference over a's mean RMSE. `None` when they share fewer than two
/// replicates.
pub fn paired_rmse(results: &[JobResult], scene: &str, a: Row, b: Row, rays: u32) -> Option<Margin> {
    let (ra, rb) = (rmse_by_replicate(results, scene, a, rays), rmse_by_replicate(results, scene, b, rays));
    margin::paired(&ra, &rb).measured()
}

/// Pairs of rows that differ in exactly one of distribution, sequence and seed mode, in the
/// order the rows are given: the comparisons that isolate one choice.
pub fn one_factor_pairs(rows: &[Row]) -> Vec<(Row, Row)> {
    let mut out = Vec::new();
    for (i, a) in rows.iter().enumerate() {
        for b in &rows[i + 1..] {
            let differ = (a.distribution != b.distribution) as u8
                + (a.sequence != b.sequence) as u8
                + (a.seed_mode != b.seed_mode) as u8;
            if differ == 1 {
                out.push((*a, *b));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(d: Distribution, s: Sequence, m: SeedMode) -> Row {
        Row::new(d, s, m)
    }

    const SC: Distribution = Distribution::SineCosine;

    #[test]
    fn unbiased_rows_are_random_or_shifted() {
        assert!(per_pixel_unbiased(row(SC, Sequence::Random, SeedMode::Rotation)));
        assert!(per_pixel_unbiased(row(SC, Sequence::Random, SeedMode::Shift)));
        assert!(per_pixel_unbiased(row(SC, Sequence::Fibonacci, SeedMode::Shift)));
        assert!(per_pixel_unbiased(row(SC, Sequence::Sobol, SeedMode::Shift)));
        assert!(!per_pixel_unbiased(row(SC, Sequence::Fibonacci, SeedMode::Rotation)));
        assert!(!per_pixel_unbiased(row(SC, Sequence::Random, SeedMode::Static)));
        assert!(!per_pixel_unbiased(row(SC, Sequence::Stratified, SeedMode::Rotation)));
    }

    #[test]
    fn one_factor_pairs_isolate_one_choice() {
        let a = row(SC, Sequence::Fibonacci, SeedMode::Rotation);
        let b = row(SC, Sequence::Fibonacci, SeedMode::Shift);
        let c = row(Distribution::ConcentricCosine, Sequence::Fibonacci, SeedMode::Shift);
        let d = row(Distribution::Uniform, Sequence::Random, SeedMode::Rotation);
        assert_eq!(one_factor_pairs(&[a, b, c, d]), vec![(a, b), (b, c)]);
    }

    #[test]
    fn paired_rmse_matches_replicates_by_index() {
        let a = row(SC, Sequence::Fibonacci, SeedMode::Rotation);
        let b = row(SC, Sequence::Fibonacci, SeedMode::Shift);
        let mk = |r: Row, rep: u32, rmse: f64| JobResult::for_test("k", r, 8, rep, rmse, 0.0);
        // Replicate noise ±0.02 shared by both; b is 0.005 above a in every replicate.
        let results = vec![
            mk(a, 0, 0.10),
            mk(a, 1, 0.12),
            mk(a, 2, 0.08),
            mk(b, 2, 0.085),
            mk(b, 0, 0.105),
            mk(b, 1, 0.125),
        ];
        let p = paired_rmse(&results, "k", a, b, 8).unwrap();
        assert_eq!(p.n, 3);
        assert!((p.mean - 0.005).abs() < 1e-12 && p.se < 1e-12, "{p:?}");
        assert!((p.relative() - 0.05).abs() < 1e-9);
        assert!(p.in_se() > 1e6, "the same difference in every replicate: {}", p.in_se());
        assert!(paired_rmse(&results, "k", a, b, 16).is_none());
    }
}

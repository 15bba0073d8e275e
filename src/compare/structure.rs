//! Whether a configuration's error is *structured* (bands, moiré: a pattern fixed to the screen
//! that more frames or a denoiser do not remove) rather than noise: the one rule `run`'s answer,
//! its equal-time tables, the claims and `advise` all apply, so the measure is switched here alone.
//! Neither `run` nor `advise` names a structured configuration as the answer while an unstructured
//! one is measured, however low its RMSE.
//!
//! The measure is the low-frequency ratio (`metrics::lowfreq`): the error's low-pass energy over
//! what independent per-pixel errors of the same sizes would keep — 1 for white noise at any image
//! size, below 1 for blue noise (shippable: a blur or the eye removes it), above 1 for blotches and
//! bands. Not the whiteness z, which flags any correlation, blue noise's negative one included, and
//! grows with the pixel count. Everything reads a replicate's value through [`of`], decides through
//! [`structured`] (or [`is_structured`] on records), and names the measure with [`MEASURE`] and
//! [`THRESHOLD`].

use crate::results::JobResult;

/// The measure's name, as advice.json and the page give it.
pub const MEASURE: &str = "lowfreq_ratio";

/// The error is structured when the measure's mean over the replicates is above this
/// (`metrics::STRUCTURED_RATIO`).
pub const THRESHOLD: f64 = crate::metrics::STRUCTURED_RATIO;

/// One image's value of the measure.
pub fn of(r: &JobResult) -> f64 {
    r.lowfreq_ratio
}

/// The rule, applied to the measure's mean over a configuration's replicates.
pub fn structured(mean: f64) -> bool {
    mean > THRESHOLD
}

/// The rule on records, each with a weight (the replicates of one ray count at 1/n each; at a
/// budget between two ray counts, the interpolation's (1 − w)/n and w/n): on the weighted mean of
/// the measure, as `AtBudget::structured` applies it to the same numbers. False with no weight.
pub fn is_structured(records: &[(f64, &JobResult)]) -> bool {
    let total: f64 = records.iter().map(|(w, _)| w).sum();
    let sum: f64 = records.iter().map(|(w, r)| w * of(r)).sum();
    total > 0.0 && structured(sum / total)
}

/// `records` at equal weights: the structure test of one configuration at one ray count.
pub fn equally<'a>(records: impl IntoIterator<Item = &'a JobResult>) -> Vec<(f64, &'a JobResult)> {
    records.into_iter().map(|r| (1.0, r)).collect()
}

/// How the rule reads, for advice.json and the page.
pub fn rule() -> String {
    format!("structured when the mean {MEASURE} over the replicates is above {THRESHOLD}")
}

//! Whether a configuration's error is *structured* (bands, moiré: a pattern fixed to the screen
//! that more frames or a denoiser do not remove) rather than noise. advise never recommends a
//! structured configuration while an unstructured one is measured, however low its RMSE.
//!
//! The measure and its threshold are here and nowhere else, so that they can be switched in one
//! place (a low-frequency share of the error, `lowfreq_ratio`, is to replace the whiteness
//! z-score): everything in advise reads a replicate's value through [`of`], decides through
//! [`structured`], and names the measure with [`MEASURE`] and [`THRESHOLD`].

use crate::results::JobResult;

/// The measure's name, as advice.json and the page give it.
pub const MEASURE: &str = "whiteness_z";

/// The error is structured when the measure's mean over the replicates is above this
/// (`metrics::whiteness::STRUCTURED_Z`: one-sided p ≈ 3e-7 for white noise).
pub const THRESHOLD: f64 = crate::metrics::whiteness::STRUCTURED_Z;

/// One image's value of the measure.
pub fn of(r: &JobResult) -> f64 {
    r.whiteness_z
}

/// The rule, applied to the measure's mean over a configuration's replicates.
pub fn structured(mean: f64) -> bool {
    mean > THRESHOLD
}

/// How the rule reads, for advice.json and the page.
pub fn rule() -> String {
    format!("structured when the mean {MEASURE} over the replicates is above {THRESHOLD}")
}

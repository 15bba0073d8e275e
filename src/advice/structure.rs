//! Whether a configuration's error is *structured* (bands, moiré: a pattern fixed to the screen
//! that more frames or a denoiser do not remove) rather than noise. advise never recommends a
//! structured configuration while an unstructured one is measured, however low its RMSE.
//!
//! The measure is the low-frequency ratio (`metrics::lowfreq`): the error's low-pass energy over
//! what independent per-pixel errors of the same sizes would keep — 1 for white noise at any image
//! size, below 1 for blue noise (shippable: a blur or the eye removes it), above 1 for blotches and
//! bands. Not the whiteness z, which flags any correlation, blue noise's negative one included, and
//! grows with the pixel count. The measure and its threshold are here and nowhere else in advise:
//! everything reads a replicate's value through [`of`], decides through [`structured`], and names
//! the measure with [`MEASURE`] and [`THRESHOLD`].

use crate::results::JobResult;

/// The measure's name, as advice.json and the page give it.
pub const MEASURE: &str = "lowfreq_ratio";

/// The error is structured when the measure's mean over the replicates is above this
/// (`metrics::STRUCTURED_RATIO`, the report's threshold too).
pub const THRESHOLD: f64 = crate::metrics::STRUCTURED_RATIO;

/// One image's value of the measure.
pub fn of(r: &JobResult) -> f64 {
    r.lowfreq_ratio
}

/// The rule, applied to the measure's mean over a configuration's replicates.
pub fn structured(mean: f64) -> bool {
    mean > THRESHOLD
}

/// How the rule reads, for advice.json and the page.
pub fn rule() -> String {
    format!("structured when the mean {MEASURE} over the replicates is above {THRESHOLD}")
}

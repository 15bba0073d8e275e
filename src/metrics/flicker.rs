//! Temporal stability: how much a filtered sequence changes from frame to frame beyond what the
//! reference itself changes. A static-camera EMA's output can have a small RMSE at every frame and
//! still shimmer; a clipped (TAA) or variance-guided (SVGF) history trades some of that. The
//! flicker of outputs o_t against references r_t is the RMS over covered pixels (and over the
//! consecutive pairs of a sequence) of (o_t − o_{t−1}) − (r_t − r_{t−1}): 0 when the output moves
//! exactly as the reference does (for a static camera, r_t = r_{t−1} and it is the RMS of the
//! output's frame-to-frame change). For outputs of independent noise of variance σ² about the
//! reference it is √2 σ; a temporal filter that keeps history brings it below that.

use super::{MetricsError, check, covered};
use crate::image::Image;

/// Σ over covered pixels of ((o − o_prev) − (r − r_prev))², and the number of covered pixels.
fn sums(
    prev: &Image,
    out: &Image,
    ref_prev: &Image,
    reference: &Image,
    mask: &Image,
) -> Result<(f64, usize), MetricsError> {
    check(out, prev, "the previous output")?;
    check(out, ref_prev, "the previous reference")?;
    check(out, reference, "the reference")?;
    check(out, mask, "the coverage mask")?;
    let (mut sq, mut n) = (0.0f64, 0usize);
    for i in (0..out.len()).filter(|&i| covered(mask, i)) {
        let d =
            (out.data[i] as f64 - prev.data[i] as f64) - (reference.data[i] as f64 - ref_prev.data[i] as f64);
        sq += d * d;
        n += 1;
    }
    Ok((sq, n))
}

/// The flicker of output `out` after `prev` against reference `reference` after `ref_prev`, over
/// the pixels `mask` covers (for a moving camera: those covered in both frames).
pub fn flicker(
    prev: &Image,
    out: &Image,
    ref_prev: &Image,
    reference: &Image,
    mask: &Image,
) -> Result<f64, MetricsError> {
    let (sq, n) = sums(prev, out, ref_prev, reference, mask)?;
    if n == 0 {
        return Err(MetricsError::NoCoveredPixels);
    }
    Ok((sq / n as f64).sqrt())
}

/// The flicker of a sequence of outputs against its references (equal lengths, at least two
/// frames): the RMS pooled over every consecutive pair and covered pixel.
pub fn flicker_sequence(outputs: &[Image], references: &[Image], mask: &Image) -> Result<f64, MetricsError> {
    assert_eq!(
        outputs.len(),
        references.len(),
        "flicker: {} outputs, {} references",
        outputs.len(),
        references.len()
    );
    let (mut sq, mut n) = (0.0f64, 0usize);
    for t in 1..outputs.len() {
        let (s, k) = sums(&outputs[t - 1], &outputs[t], &references[t - 1], &references[t], mask)?;
        sq += s;
        n += k;
    }
    if n == 0 {
        return Err(MetricsError::NoCoveredPixels);
    }
    Ok((sq / n as f64).sqrt())
}

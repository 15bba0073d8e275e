//! What advise measures with when the user does not say: its replicates and the reference it
//! builds, chosen by what it ranks (a raw frame or a filtered one) and where (a whole frame or
//! tiles of an engine's image). Pure: nothing is read or written here.

use crate::spec::{ReferenceRays, ReferenceSpec, Row};

/// Rays per pixel of each of the 4 replicates of the reference advise builds after a real-time
/// pipeline: `experiments/realtime.toml`'s. The raw sweep's rule (`ReferenceRays::Auto`: a tenth
/// of the error of the largest ray count's raw frame) gives 64 at 2 rays, a noise floor of about
/// 0.02 at 1920x1080, as large as half of what SVGF leaves; 4 × 1024 puts it near 0.005.
pub const PIPELINE_REFERENCE_RAYS: u32 = 1024;

/// Replicates when `--replicates` is not given: 4, or 2 when the image is measured on tiles
/// (`plan::tiles::auto`: above 320 × 180): each replicate then holds 4 tiles of 128² measured
/// pixels, its RMSE varies by a fraction of a percent from seed to seed, and at 1080 lines two
/// replicates are what keeps a 260k-triangle scene's advice within 20 minutes here
/// (docs/advise.md). More with `--replicates`.
pub fn replicates(resolution: Option<(u32, u32)>) -> u32 {
    match resolution {
        Some((w, h)) if crate::plan::tiles::auto([w, h]).is_some() => 2,
        _ => 4,
    }
}

/// The reference advise builds when none is stored: `ReferenceRays::Auto` for the raw sweep,
/// `PIPELINE_REFERENCE_RAYS` after a pipeline.
pub fn reference(pipeline: crate::denoise::Pipeline) -> ReferenceSpec {
    ReferenceSpec {
        rays: if pipeline == crate::denoise::Pipeline::RAW {
            ReferenceRays::Auto
        } else {
            ReferenceRays::Fixed(PIPELINE_REFERENCE_RAYS)
        },
        replicates: 4,
        seed: 1,
        estimator: Row::new(
            crate::sampling::Distribution::SineCosine,
            crate::sampling::Sequence::Fibonacci,
            crate::sampling::SeedMode::Shift,
        ),
        adaptive: false,
    }
}

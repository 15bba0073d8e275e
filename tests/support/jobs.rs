//! The one place the tests make a `RenderJob` (the library has no constructor: its fields are the
//! job), so a field added to it is added here once, not at every test's literal.

use hemilab::render::RenderJob;
use hemilab::sampling::{Distribution, SamplerConfig};

/// A job of `distribution` through `sampler` at `width` × `height` with AO distance `ao_distance`
/// (`f32::INFINITY` for none).
pub fn render_job(
    distribution: Distribution,
    sampler: SamplerConfig,
    (width, height): (u32, u32),
    ao_distance: f32,
) -> RenderJob {
    RenderJob { distribution, sampler, width, height, ao_distance }
}

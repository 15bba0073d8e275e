//! A camera whose every visible surface is open all round: its images would be all white.

use crate::render;
use crate::sampling::{SeedMode, Sequence};
use crate::scene::Scene;
use std::path::Path;

/// Pixels of `all_open_warning`'s preview render (about 64 × 48, the scene's aspect).
const OPEN_PREVIEW_PIXELS: f64 = 3072.0;

/// The warning for a camera whose every visible surface is open within d — behind a wall, looking
/// at its back, or outside the room, at its outside: its images would be all white (AO 1), so every
/// estimator's error would be zero and nothing would be measured. Found by a 16-ray render of a
/// small preview (milliseconds) in which no AO ray meets anything. A warning, as the camera under
/// the floor is (`facing_warning`), not a refusal: a surface open all round is a (dull) view all
/// the same, unlike a camera that sees no triangle (`check_view`, refused).
pub fn all_open_warning(path: &Path, scene: &Scene, camera: &str) -> Option<String> {
    let (w, h) = scene.resolution;
    let s = (OPEN_PREVIEW_PIXELS / (w as f64 * h as f64)).sqrt().min(1.0);
    let (pw, ph) = (((w as f64 * s).round() as u32).max(1), ((h as f64 * s).round() as u32).max(1));
    let sampler = crate::sampling::SamplerConfig::new(Sequence::Random, SeedMode::Shift, 16, 1).ok()?;
    let job = render::RenderJob {
        distribution: crate::sampling::Distribution::SineCosine,
        sampler,
        width: pw,
        height: ph,
        ao_distance: scene.ao_distance,
    };
    let out = render::render(scene, &job, &|_| {});
    if out.rays == 0 || out.occluded_rays > 0 {
        return None;
    }
    Some(format!(
        "warning: {}: {camera}: every surface the camera sees is open all round within d = {}: none of \
         {} AO rays from its surfaces meets the mesh, so its images would be all white (AO 1) and every \
         estimator's error zero; is the eye behind a wall or outside the room? {}",
        path.display(),
        scene.ao_distance,
        out.rays,
        super::where_is_the_mesh(scene)
    ))
}

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
/// the same, unlike a camera that sees no triangle (`check_view`, refused). Said only of a mesh that
/// encloses a space (`enclosed`): a lone quad or triangle is open all round from any eye.
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
    if out.rays == 0 || out.occluded_rays > 0 || enclosed(scene) < 0.5 {
        return None;
    }
    Some(format!(
        "warning: {}: {camera}: every surface the camera sees is open all round within d = {}: none of \
         {} AO rays from its surfaces meets the mesh, so its images would be all white (AO 1) and every \
         estimator's error zero; is the eye behind a wall or outside the room? {}",
        path.display(),
        scene.ao_distance,
        out.rays,
        super::describe::where_is_the_mesh(scene)
    ))
}

/// Directions from the mesh's bounding-box centre (`ENCLOSED_RAYS`, a Fibonacci sphere).
const ENCLOSED_RAYS: u32 = 256;

/// The fraction of directions from the centre of the mesh's bounding box that meet the mesh: near
/// 1 inside a room, near 0 for a lone quad, whose surfaces are open from anywhere.
fn enclosed(scene: &Scene) -> f64 {
    let (lo, hi) = super::describe::bounds(scene);
    let centre = ((lo + hi) * 0.5 - scene.origin).as_vec3();
    let mut hits = 0u32;
    for i in 0..ENCLOSED_RAYS {
        let z = 1.0 - (2 * i + 1) as f32 / ENCLOSED_RAYS as f32;
        let phi = i as f32 * std::f32::consts::PI * (3.0 - 5f32.sqrt());
        let r = (1.0 - z * z).max(0.0).sqrt();
        let d = glam::Vec3::new(r * phi.cos(), r * phi.sin(), z);
        hits +=
            scene.accel.closest(&crate::scene::accel::Ray::new(centre, d, f32::INFINITY)).is_some() as u32;
    }
    hits as f64 / ENCLOSED_RAYS as f64
}

//! What a loaded scene looks like from its camera, said in words: the one-line summary `render`
//! and `advise` print, the refusal of a camera that sees nothing and the warning for one under the
//! floor, each saying where the mesh is.

use crate::error::{Error, Result};
use crate::render;
use crate::scene::{Camera, Scene};
use glam::DVec3;
use std::path::Path;

/// Refuses a camera that sees no triangle at `width` x `height`: every image of it would be
/// background, with nothing to measure, and a run would find out only after building a reference.
/// The primary rays are traced once (milliseconds, against the seconds of any real work), and the
/// message says where the mesh is. Returns what the camera sees, for `facing_warning`.
pub fn check_view(path: &Path, scene: &Scene, width: u32, height: u32) -> Result<render::Sight> {
    let sight = render::sight(scene, width, height);
    if sight.hits > 0 {
        return Ok(sight);
    }
    Err(Error::input(
        path,
        format!(
            "camera: sees no triangle of the mesh (none of the {width}x{height} primary rays hits it): {}",
            where_is_the_mesh(scene)
        ),
    ))
}

/// The warning for a camera under the floor (`render::Sight::under_the_floor`: nothing below
/// the eye, the mesh above it), naming the scene file and where its camera is written (`camera`:
/// "key `camera.perspective.eye`", or a glTF file's camera). A warning, not a refusal: an eye
/// below a ceiling-only mesh is a (strange) view all the same.
pub fn facing_warning(path: &Path, scene: &Scene, sight: &render::Sight, camera: &str) -> Option<String> {
    if !sight.under_the_floor() {
        return None;
    }
    Some(format!(
        "warning: {}: {camera}: the eye looks to be under the floor or behind the geometry: {:.0} % of \
         the directions below it meet nothing and {:.0} % of those above it meet the mesh, and {:.0} % of \
         the pixels see no surface (the preview draws them as a blue checkerboard); {}",
        path.display(),
        sight.below_open * 100.0,
        sight.above_closed * 100.0,
        (1.0 - sight.coverage()) * 100.0,
        where_is_the_mesh(scene)
    ))
}

/// The mesh's bounding box in world coordinates.
pub(super) fn bounds(scene: &Scene) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for prim in 0..scene.accel.len() as u32 {
        for v in scene.accel.triangle(prim) {
            let w = scene.origin + v.as_dvec3();
            (lo, hi) = (lo.min(w), hi.max(w));
        }
    }
    (lo, hi)
}

/// One line on what was loaded, printed by `render` and `advise` before they work: the triangles,
/// the materials with alpha masks (and the triangles they cut), the bounds, and the coverage (the
/// fraction of pixels that see the mesh) at the size rendered — so a wrong file, a lost mask or a
/// camera that sees little shows before the numbers do.
pub fn summary(scene: &Scene, width: u32, height: u32) -> String {
    let sight = render::sight(scene, width, height);
    let (lo, hi) = bounds(scene);
    let p = |v: DVec3| format!("[{}, {}, {}]", num(v.x), num(v.y), num(v.z));
    let masks = match scene.masked_materials {
        0 => "no alpha masks".to_string(),
        n => format!(
            "{n} material{} with alpha masks ({} triangles)",
            if n == 1 { "" } else { "s" },
            thousands(scene.masked_triangles)
        ),
    };
    format!(
        "scene '{}': {} triangles, {masks}, bounds {} to {}, coverage {:.0} % at {width}x{height}",
        scene.name,
        thousands(scene.triangle_count),
        p(lo),
        p(hi),
        100.0 * sight.coverage()
    )
}

/// 262087 as "262,087".
fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// Where the mesh is from the camera, and what to change: its extent, and how far and how many
/// degrees off the view direction its centre is.
pub(super) fn where_is_the_mesh(scene: &Scene) -> String {
    let (lo, hi) = bounds(scene);
    let centre = (lo + hi) * 0.5;
    let (eye, target) = match scene.view {
        Camera::Perspective { eye, target, .. } | Camera::Orthographic { eye, target, .. } => (eye, target),
    };
    let (to_mesh, view) = (centre - eye, target - eye);
    let angle = to_mesh.angle_between(view).to_degrees();
    let p = |v: DVec3| format!("[{}, {}, {}]", num(v.x), num(v.y), num(v.z));
    format!(
        "the mesh spans {} to {}; its centre {} is {} from the eye {} and {angle:.0}° off the view toward \
         target {}; aim `target` at the mesh (e.g. its centre), or move `eye`",
        p(lo),
        p(hi),
        p(centre),
        num(to_mesh.length()),
        p(eye),
        p(target)
    )
}

/// A coordinate for a message: 4 significant digits, in the notation that reads best.
fn num(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else if (1e-3..1e6).contains(&x.abs()) {
        let decimals = (3 - x.abs().log10().floor() as i32).clamp(0, 6) as usize;
        let s = format!("{x:.decimals$}");
        let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.') } else { &s };
        if s == "-0" { "0".into() } else { s.into() }
    } else {
        format!("{x:.3e}")
    }
}

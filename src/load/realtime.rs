//! The real-time axes of a spec checked at load, before any work: each camera path over every
//! frame of each scene it is measured on, and each user's denoiser command tried on a tiny frame.

use crate::error::{Error, Result};
use crate::io;
use crate::scene::Scene;
use crate::spec::Spec;
use std::sync::Arc;

/// Every camera path a group names, over each of its scenes' cameras and for its frames: a path
/// that would take a frame's camera somewhere no image can be made from is the spec's error, and so
/// is a frame that sees no triangle of the mesh (a dolly through a wall, a 180° pan, keyframes
/// looking away), as the scene's own camera is (`load::check_view`): its image and its reference
/// would be all background, and a run would find out only after building references and rendering,
/// naming a job instead of the camera. The frames' primary rays are traced once here (without
/// jitter), milliseconds per frame.
pub(super) fn check_cameras(spec: &Spec, scenes: &[Arc<Scene>]) -> Result<()> {
    let mut seen: Vec<(String, usize, u32)> = Vec::new();
    for g in &spec.groups {
        for run in g.cameras.iter().filter_map(|c| c.run()) {
            for &si in &g.scenes {
                let frames = run.frames.max(1);
                let at = |e: String| {
                    Error::input(
                        &spec.path,
                        format!(
                            "key `cameras.{}.path`: over scene '{}': {e}",
                            run.name, spec.scenes[si].name
                        ),
                    )
                };
                run.path.validate(&scenes[si].view, frames).map_err(at)?;
                if seen.contains(&(run.name.clone(), si, frames)) {
                    continue;
                }
                seen.push((run.name.clone(), si, frames));
                let scene = &scenes[si];
                let g = crate::plan::Geometry::of(spec.resolution, spec.ao_distance, scene);
                for f in 0..frames {
                    let camera = run.path.camera(&scene.view, f, frames);
                    let view = crate::render::View::new(camera, glam::Vec2::ZERO);
                    if crate::render::primary_hits(scene, &view, g.width, g.height) == 0 {
                        return Err(at(format!(
                            "the camera of frame {f} (of 0 to {}) sees no triangle of the mesh (none of the \
                             {}x{} primary rays hits it): its image would be all background, with nothing \
                             to measure; keep every frame's camera looking at the scene",
                            frames - 1,
                            g.width,
                            g.height
                        )));
                    }
                }
            }
        }
    }
    Ok(())
}

/// Every denoiser command a group names, tried on a tiny generated frame (`DenoiseCommand::probe`)
/// in a directory of the system's temporary one: a command that cannot run, fails or writes
/// nothing usable is refused before any rendering, and nothing is written where the run writes.
pub(super) fn probe_denoisers(spec: &Spec) -> Result<()> {
    let mut seen = Vec::new();
    for d in spec.groups.iter().flat_map(|g| &g.denoisers).filter_map(|d| d.get()) {
        if seen.contains(&d.name) {
            continue;
        }
        seen.push(d.name.clone());
        let dir = std::env::temp_dir().join(format!("hemilab-probe-{}-{}", std::process::id(), d.name));
        let tried = d.command.probe(&dir).map_err(|e| {
            Error::input(
                &spec.path,
                format!("key `denoisers.{}`: the command failed on a test frame: {e}", d.name),
            )
        });
        // Removed whatever the outcome: the message keeps what the command said.
        io::remove_dir_all_if_exists(&dir)?;
        tried?;
    }
    Ok(())
}

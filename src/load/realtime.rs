//! The real-time axes of a spec checked at load, before any work: each camera path over every
//! frame of each scene it is measured on, and each user's denoiser command tried on a tiny frame.

use crate::error::{Error, Result};
use crate::io;
use crate::scene::Scene;
use crate::spec::Spec;
use std::sync::Arc;

/// Every camera path a group names, over each of its scenes' cameras and for its frames: a path
/// that would take a frame's camera somewhere no image can be made from is the spec's error.
pub(super) fn check_cameras(spec: &Spec, scenes: &[Arc<Scene>]) -> Result<()> {
    for g in &spec.groups {
        for run in g.cameras.iter().filter_map(|c| c.run()) {
            for &si in &g.scenes {
                run.path.validate(&scenes[si].view, run.frames.max(1)).map_err(|e| {
                    Error::input(
                        &spec.path,
                        format!(
                            "key `cameras.{}.path`: over scene '{}': {e}",
                            run.name, spec.scenes[si].name
                        ),
                    )
                })?;
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
        if tried.is_ok() {
            io::remove_dir_all_if_exists(&dir)?;
        }
        tried?;
    }
    Ok(())
}

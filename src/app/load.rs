//! A spec with every scene it names, loaded and validated before any work: every command that
//! takes a spec (`run`, `plan`, `reference`) starts here, and the report reads the same `Loaded`.

use super::jobs::Geometry;
use crate::app::render::{MAX_PIXELS, dropped_warning, load_scene};
use crate::error::{Error, Result};
use crate::io;
use crate::plan::Job;
use crate::scene::Scene;
use crate::spec::{self, SceneRef, Spec};
use std::path::Path;

/// A spec with every scene it names loaded: all bad input is found here, before any work.
pub struct Loaded {
    pub spec: Spec,
    pub scenes: Vec<Scene>,
}

impl Loaded {
    pub fn scene_of(&self, job: &Job) -> (usize, &Scene) {
        let i =
            self.spec.scenes.iter().position(|s| s.id == job.scene_id).expect("planned scene is in the spec");
        (i, &self.scenes[i])
    }
}

pub fn load(spec_path: &Path) -> Result<Loaded> {
    let text = io::read_string(spec_path)?;
    let spec = spec::parse_spec(&text, spec_path)?;
    let scenes = spec.scenes.iter().map(|s| load_named_scene(&spec, s)).collect::<Result<Vec<_>>>()?;
    for w in scenes.iter().filter_map(dropped_warning) {
        eprintln!("{w}");
    }
    Ok(Loaded { spec, scenes })
}

/// A scene the spec names: a missing file is the spec's mistake, so the message points at its key;
/// an image too large to hold in memory is refused here rather than by the allocator mid-run.
fn load_named_scene(spec: &Spec, s: &SceneRef) -> Result<Scene> {
    if !io::exists(&s.path) {
        // The full path: the scene is looked for relative to the spec, which may not be where the
        // user is.
        let looked =
            std::path::absolute(&s.path).map_or(s.id.clone(), |p| spec::normalize(&p.to_string_lossy()));
        return Err(Error::input(
            &spec.path,
            format!(
                "line {}, key `scenes`: scene file '{}' not found (looked for {looked}); scene paths are \
                 relative to the spec file",
                s.line, s.id
            ),
        ));
    }
    let scene = load_scene(&s.path)?;
    let g = Geometry::of(spec.resolution, spec.ao_distance, &scene);
    if g.pixels() > MAX_PIXELS {
        return Err(Error::input(
            &spec.path,
            format!(
                "key `resolution`: {}x{} for scene '{}' is too large to hold in memory; {}",
                g.width,
                g.height,
                s.name,
                crate::spec::RESOLUTION_RULE
            ),
        ));
    }
    Ok(scene)
}

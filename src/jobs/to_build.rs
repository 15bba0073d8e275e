//! The references a run of a plan would build, found before any work (`reference::store`'s
//! lookups): what a forecast (`calibrate::references_s`) counts and calibrates the estimator of.

use crate::error::Result;
use crate::load::Loaded;
use crate::plan::Job;
use crate::plan::Plan;
use crate::reference::Manifest;
use crate::reference::store as refs;

/// A reference a run of the plan would build: the scene's own, or a camera path frame's.
pub struct Build {
    pub scene: usize,
    pub manifest: Manifest,
    /// `None`: the scene's own view; else the camera and frame (from 0) it is of.
    pub view: Option<(crate::plan::CameraId, u32)>,
    /// Renders per replicate: 1, or the jitter cycle a jittered camera's reference averages.
    pub views: u32,
}

/// The references a run of `selected` would build in `dir` (`reference::store::missing`,
/// `missing_view`): each scene's own that a job of the plan uses, then every camera path frame's
/// the jobs read (`jobs::reference::needed_views`), a moving camera's one per measured frame and
/// the frame before it.
pub fn builds(loaded: &Loaded, selected: &Plan, dir: &std::path::Path) -> Result<Vec<Build>> {
    let spec = &loaded.spec;
    let mut out: Vec<Build> = Vec::new();
    // Under `[tiles]` every reference is one per tile interior (`jobs::reference::obtain_measured`).
    let tiles: Vec<Option<super::tiles::TileSet>> =
        (0..loaded.scenes.len()).map(|si| super::tiles::of_spec(spec, si, &loaded.scenes[si])).collect();
    let windows = |si: usize| -> Vec<Option<crate::render::Window>> {
        match &tiles[si] {
            Some(t) => t.interiors.iter().copied().map(Some).collect(),
            None => vec![None],
        }
    };
    let add = |out: &mut Vec<Build>,
               si: usize,
               view: &refs::ReferenceView,
               at: Option<(crate::plan::CameraId, u32)>|
     -> Result<()> {
        for w in windows(si) {
            let v = refs::ReferenceView { window: w, ..*view };
            if let Some(manifest) = refs::missing_view(spec, si, &loaded.scenes[si], dir, &v)? {
                // A frame seen from the scene's own camera (an orbit's frame 0) is the scene's reference.
                if out.iter().any(|b: &Build| b.manifest.file_stem() == manifest.file_stem()) {
                    continue;
                }
                let views = if v.jitter_average { crate::scene::camera_path::JITTER_CYCLE } else { 1 };
                out.push(Build { scene: si, manifest, view: at, views });
            }
        }
        Ok(())
    };
    for (si, scene) in loaded.scenes.iter().enumerate() {
        if !selected.jobs.iter().any(|j| loaded.scene_of(j).0 == si) {
            continue;
        }
        if tiles[si].is_none() {
            if let Some(manifest) = refs::missing(spec, si, scene, dir)? {
                out.push(Build { scene: si, manifest, view: None, views: 1 });
            }
            continue;
        }
        add(&mut out, si, &refs::ReferenceView::of_scene(scene), None)?;
    }
    let si_of = |j: &Job| loaded.scene_of(j).0;
    for n in crate::jobs::reference::needed_views(selected, &loaded.scenes, si_of) {
        add(&mut out, n.scene, &n.view, Some((n.camera, n.frame)))?;
    }
    Ok(out)
}

/// Per scene, a reference it must build, if any: what `calibrate` adds the reference's estimator
/// for.
pub fn by_scene(loaded: &Loaded, builds: &[Build]) -> Vec<Option<Manifest>> {
    (0..loaded.scenes.len())
        .map(|si| builds.iter().find(|b| b.scene == si).map(|b| b.manifest.clone()))
        .collect()
}

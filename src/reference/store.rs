//! Reference images: reuse a stored one only when its manifest matches what the run needs,
//! otherwise render it (unless told not to; `jobs::reference` renders, this module finds and
//! stores). A reference is the mean of independent renders with
//! an unbiased estimator; their spread gives the per-pixel standard error and so the noise floor.

use crate::error::{Error, Result};
use crate::image::{Channel, Image, Provenance};
use crate::io;
use crate::plan::Geometry;
use crate::reference::{self, Adaptive, Manifest};
use crate::scene::Scene;
use crate::spec::{ReferenceRays, Spec};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub struct Reference {
    pub mean: Image,
    pub stderr: Image,
    pub coverage: Image,
    pub manifest: Manifest,
    pub exr: PathBuf,
}

impl Reference {
    pub fn noise_floor(&self) -> f64 {
        reference::noise_floor(&self.stderr, &self.coverage)
    }
}

/// Where a command finds the spec's references: `--reference-dir`, else the spec's own
/// (`[reference] dir` relative to the spec file, or `reference/` beside it), never the current
/// directory's.
pub fn dir(flag: Option<&Path>, spec: &Spec) -> PathBuf {
    flag.map_or_else(|| spec.reference_dir.clone(), Path::to_path_buf)
}

/// Where `advise` finds a scene file's references: `--reference-dir` (`flag`), else `reference/`
/// beside the scene file, or the scene folder's parent's `reference/` when that one holds a
/// reference of this scene (this repository's layout: the committed references of `scenes/*.toml`
/// are in `reference/`). Like a spec's references, never relative to the current directory, so the
/// committed ones are found from anywhere and a user's own scene keeps its references beside it.
pub fn dir_of_scene(flag: Option<&Path>, scene_file: &Path, scene: &Scene) -> Result<PathBuf> {
    if let Some(dir) = flag {
        return Ok(dir.to_path_buf());
    }
    let folder = scene_file.parent().unwrap_or(Path::new(""));
    let beside = folder.join("reference");
    let parent = folder.join("..").join("reference");
    if stored_of_scene(&beside, scene)?.is_empty() && !stored_of_scene(&parent, scene)?.is_empty() {
        return Ok(parent);
    }
    Ok(beside)
}

/// Manifests in `dir` of this scene's content (scene and mesh hash), camera and hemilab version
/// whose image is there, with their image's path: the references `advise` may reuse. Unreadable or
/// foreign JSON files are skipped: they are not this scene's references.
pub fn stored_of_scene(dir: &Path, scene: &Scene) -> Result<Vec<(Manifest, PathBuf)>> {
    let mut out = Vec::new();
    for json in io::list_dir(dir)?.into_iter().filter(|p| p.extension().is_some_and(|e| e == "json")) {
        let Ok(m) = io::read_string(&json).and_then(|t| Manifest::from_json(&t).map_err(Error::Refused))
        else {
            continue;
        };
        let exr = json.with_extension("exr");
        if m.scene_hash == scene.content_hash
            && m.camera == scene.camera_description()
            && m.hemilab_version == env!("CARGO_PKG_VERSION")
            && io::exists(&exr)
        {
            out.push((m, exr));
        }
    }
    Ok(out)
}

/// What to do when the stored reference is missing or does not match.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Policy {
    /// Reuse a matching one, else render.
    ReuseOrBuild,
    /// Reuse a matching one, else stop with an error.
    ReuseOnly,
    /// Always render.
    Rebuild,
}

/// Rays per reference replicate for `rays = "auto"`. The smallest RMSE a spec measures is about the
/// single-render error of the best estimator at the largest ray count N; the floor of K replicates
/// at R rays is about err(R)/√K, and err falls at least as 1/√rays, so R = 100·N/K puts the floor at
/// or below a tenth of it. The run checks the claim against the measured RMSEs afterwards.
pub fn auto_rays(spec: &Spec, scene: usize) -> u32 {
    let n = spec.groups.iter().filter(|g| g.scenes.contains(&scene)).flat_map(|g| g.rays.iter()).max();
    let n = *n.unwrap_or(&64) as u64;
    let r = (100 * n).div_ceil(spec.reference.replicates.max(1) as u64);
    r.next_power_of_two().min(1 << 22) as u32
}

/// Most rays of a pilot pass under a fixed budget: enough to see each pixel's spread, a small part of
/// the budget.
pub const MAX_PILOT_RAYS: u32 = 256;

/// An adaptive reference's pilot rays per pixel: under `rays = "auto"` the largest ray count the spec
/// measures on the scene (so the pilot's spread is the single-render error the floor is set against),
/// else the budget, up to `MAX_PILOT_RAYS`.
pub fn pilot_rays(spec: &Spec, scene: usize) -> u32 {
    match spec.reference.rays {
        ReferenceRays::Fixed(r) => r.min(MAX_PILOT_RAYS),
        ReferenceRays::Auto => {
            let n =
                spec.groups.iter().filter(|g| g.scenes.contains(&scene)).flat_map(|g| g.rays.iter()).max();
            *n.unwrap_or(&64)
        }
    }
}

/// A reference's view: the camera it is rendered from (a camera path's frame, or the scene's) and
/// whether it averages a jittered camera's offsets (`Manifest::jitter_average`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceView {
    pub camera: crate::scene::WorldCamera,
    pub jitter_average: bool,
    /// A rectangle of the image alone (a tile's interior, `Manifest::window`); None: all of it.
    pub window: Option<crate::render::Window>,
}

impl ReferenceView {
    /// The scene's own camera, unjittered: every reference before camera paths.
    pub fn of_scene(scene: &Scene) -> Self {
        Self { camera: scene.view, jitter_average: false, window: None }
    }

    /// The same view of the rectangle `window` alone.
    pub fn of_window(self, window: crate::render::Window) -> Self {
        Self { window: Some(window), ..self }
    }
}

pub fn wanted_manifest(spec: &Spec, si: usize, scene: &Scene, geometry: Geometry) -> Manifest {
    wanted_view(spec, si, scene, geometry, &ReferenceView::of_scene(scene))
}

/// `wanted_manifest` of another view of the scene.
pub fn wanted_view(
    spec: &Spec,
    si: usize,
    scene: &Scene,
    geometry: Geometry,
    view: &ReferenceView,
) -> Manifest {
    let rays = match (spec.reference.adaptive, spec.reference.rays) {
        (true, _) => pilot_rays(spec, si),
        (false, ReferenceRays::Fixed(r)) => r,
        (false, ReferenceRays::Auto) => auto_rays(spec, si),
    };
    let mut m = Manifest::wanted(
        &spec.scenes[si],
        &scene.content_hash,
        reference::CameraRecord::of(&view.camera),
        [geometry.width, geometry.height],
        geometry.distance,
        crate::plan::reference_estimator(spec, si),
        rays,
        spec.reference.replicates,
        spec.reference.seed,
    );
    if spec.reference.adaptive {
        m.adaptive = Some(Adaptive {
            rule: reference::ADAPTIVE_RULE.into(),
            min_rays: rays,
            budget: match spec.reference.rays {
                ReferenceRays::Fixed(r) => Some(r),
                ReferenceRays::Auto => None,
            },
            total_rays: None,
            max_rays: None,
        });
    }
    m.jitter_average = view.jitter_average;
    m.window = view.window.map(|w| [w.x, w.y, w.width, w.height]);
    m
}

/// The image and manifest of the view's first reference (`Manifest::file_stem`).
pub fn paths(dir: &Path, manifest: &Manifest) -> (PathBuf, PathBuf) {
    paths_of(dir, &manifest.file_stem())
}

fn paths_of(dir: &Path, stem: &str) -> (PathBuf, PathBuf) {
    (dir.join(format!("{stem}.exr")), dir.join(format!("{stem}.json")))
}

/// Where a reference of `wanted`'s settings is, or goes: the view's own name, or, once that holds
/// a reference of other settings, a name of the settings' own (`Manifest::settings_stem`), in the
/// order to look.
pub fn candidates(dir: &Path, wanted: &Manifest) -> [(PathBuf, PathBuf); 2] {
    [paths(dir, wanted), paths_of(dir, &wanted.settings_stem())]
}

/// Where a newly built reference of `wanted` is stored: the view's own name if nothing is there or
/// what is there has the same settings (a rebuild of it, `hemilab reference --force`), else the
/// settings' own name. A reference is never overwritten by a different one, so a committed
/// reference other specs rely on is never replaced by a run with other reference settings.
pub fn target(dir: &Path, wanted: &Manifest) -> (PathBuf, PathBuf) {
    let [first, own] = candidates(dir, wanted);
    let same = |json: &Path| {
        io::read_string(json)
            .ok()
            .and_then(|t| Manifest::from_json(&t).ok())
            .is_some_and(|m| m.matches(wanted).is_ok())
    };
    if !io::exists(&first.1) && !io::exists(&first.0) || same(&first.1) { first } else { own }
}

/// The reference scene `si` needs, if `dir` holds no usable one (what `obtain` would build).
pub fn missing(spec: &Spec, si: usize, scene: &Scene, dir: &Path) -> Result<Option<Manifest>> {
    let wanted = wanted_manifest(spec, si, scene, Geometry::of(spec.resolution, spec.ao_distance, scene));
    Ok(find(spec, &wanted, dir)?.err().map(|_| wanted))
}

/// A stored reference of `wanted` in `dir`, under either of its names (`candidates`): `Ok(Err)`
/// with the first name's reason when there is none (see `load_if_matching`).
pub fn find(
    spec: &Spec,
    wanted: &Manifest,
    dir: &Path,
) -> Result<std::result::Result<Reference, (PathBuf, String)>> {
    let [(exr, json), (exr2, json2)] = candidates(dir, wanted);
    let first = load_if_matching(spec, wanted, &exr, &json)?;
    if first.is_ok() || !io::exists(&json2) {
        return Ok(first);
    }
    Ok(load_if_matching(spec, wanted, &exr2, &json2)?.or(first))
}

/// The reference of `view` of scene `si` (a camera path's frame), if `dir` holds no usable one.
pub fn missing_view(
    spec: &Spec,
    si: usize,
    scene: &Scene,
    dir: &Path,
    view: &ReferenceView,
) -> Result<Option<Manifest>> {
    let g = Geometry::of(spec.resolution, spec.ao_distance, scene);
    let wanted = wanted_view(spec, si, scene, g, view);
    let (exr, json) = paths(dir, &wanted);
    Ok(load_if_matching(spec, &wanted, &exr, &json)?.err().map(|_| wanted))
}

/// `Ok(Err((file, why)))` when there is nothing reusable; `Err` only for a stored file that cannot
/// be read.
pub fn load_if_matching(
    spec: &Spec,
    wanted: &Manifest,
    exr: &Path,
    json: &Path,
) -> Result<std::result::Result<Reference, (PathBuf, String)>> {
    for file in [json, exr] {
        if !io::exists(file) {
            return Ok(Err((file.to_path_buf(), "not found".into())));
        }
    }
    let stored = Manifest::from_json(&io::read_string(json)?)
        .map_err(|e| Error::input(json, format!("not a reference manifest: {e}")))?;
    let check = match spec.reference.rays {
        // An adaptive reference's rays follow from its (exactly compared) pilot settings.
        _ if wanted.adaptive.is_some() => stored.matches(wanted),
        ReferenceRays::Fixed(_) => stored.matches(wanted),
        // The floor the run needs is known only after it; a reference with at least the rays `auto`
        // would spend now is as good as a new one, one with fewer (the spec grew) is not.
        ReferenceRays::Auto => stored.matches_auto(wanted, f64::INFINITY).and_then(|()| {
            let total = |m: &Manifest| m.rays as u64 * m.replicates as u64;
            if total(&stored) >= total(wanted) {
                return Ok(());
            }
            Err(vec![format!(
                "rays: stored {} x {}, wanted at least {} x {} for rays = \"auto\"",
                stored.replicates, stored.rays, wanted.replicates, wanted.rays
            )])
        }),
    };
    if let Err(diffs) = check {
        return Ok(Err((json.to_path_buf(), format!("does not match ({})", diffs.join("; ")))));
    }
    let (mean, stderr, coverage) = read_channels(exr)?;
    if [mean.width, mean.height] != wanted.image_size() {
        return Ok(Err((exr.to_path_buf(), "has the wrong size".into())));
    }
    check_pixels(&stored, &mean, &stderr, &coverage, exr, json)?;
    Ok(Ok(Reference { mean, stderr, coverage, manifest: stored, exr: exr.to_path_buf() }))
}

/// A reference image's mean (`Y`), standard error (`stderr`) and coverage (`A`).
fn read_channels(exr: &Path) -> Result<(Image, Image, Image)> {
    let channels = io::read_exr(exr)?;
    let take = |name: &str| {
        channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, img)| img.clone())
            .ok_or_else(|| Error::input(exr, format!("reference lacks channel '{name}'")))
    };
    Ok((take("Y")?, take("stderr")?, take("A")?))
}

/// The text of manifest `json` with the `pixels` hash of its image (the `.exr` beside it) added
/// as its last key, every other byte as it was; the text itself if it has the hash already and the
/// hash is right. The one-off migration of manifests written before pixel hashes
/// (`examples/reference_hashes.rs`), and what a test checks every committed manifest against.
pub fn with_pixel_hash(json: &Path) -> Result<String> {
    let text = io::read_string(json)?;
    let bad = |e: String| Error::input(json, format!("not a reference manifest: {e}"));
    let m = Manifest::from_json(&text).map_err(bad)?;
    let exr = json.with_extension("exr");
    let (mean, stderr, coverage) = read_channels(&exr)?;
    if let Some(what) = reference::first_non_finite(&mean, &stderr, &coverage) {
        return Err(Error::input(&exr, format!("not a usable reference: {what}")));
    }
    let hash = reference::pixel_hash(&mean, &stderr, &coverage);
    let new = match &m.pixels {
        Some(_) => text,
        None => {
            let body = text.trim_end().strip_suffix('}').ok_or_else(|| bad("no closing brace".into()))?;
            format!("{},\n  \"pixels\": \"{hash}\"\n}}\n", body.trim_end())
        }
    };
    let check = Manifest::from_json(&new).map_err(bad)?;
    if check.pixels.as_deref() != Some(hash.as_str()) {
        return Err(Error::input(
            json,
            format!("its `pixels` is not the hash of {} ({hash})", exr.display()),
        ));
    }
    Ok(new)
}

/// The image read is the one its manifest was written for: every value finite and the pixels'
/// hash the manifest's `pixels` (`reference::pixel_hash`). Either failing is one error naming the
/// image: a reference edited after it was made is never measured against (with one NaN pixel every
/// RMSE came out empty), and never silently rebuilt over, since other specs may rely on it.
fn check_pixels(
    stored: &Manifest,
    mean: &Image,
    stderr: &Image,
    coverage: &Image,
    exr: &Path,
    json: &Path,
) -> Result<()> {
    let redo = format!(
        "restore it, or remove it and {} to build it again",
        json.file_name().map_or(String::new(), |n| n.to_string_lossy().into_owned())
    );
    if let Some(bad) = reference::first_non_finite(mean, stderr, coverage) {
        return Err(Error::input(exr, format!("not a usable reference: {bad}; {redo}")));
    }
    let have = reference::pixel_hash(mean, stderr, coverage);
    match &stored.pixels {
        Some(want) if *want == have => Ok(()),
        Some(want) => Err(Error::input(
            exr,
            format!(
                "its pixels are not the ones {} was written for (hash {have}, the manifest says {want}): the \
                 image was changed after it was made; {redo}",
                json.display()
            ),
        )),
        None => Err(Error::input(
            exr,
            format!(
                "{} has no `pixels` hash (written by an older hemilab), so this image cannot be checked; {redo}",
                json.display()
            ),
        )),
    }
}

/// A reference image's provenance: its manifest (what determines it, and its noise floor), without
/// its render time, which would make the image's bytes differ from one build to the next.
fn provenance(m: &Manifest) -> Provenance {
    // Through the manifest's text, so an f32 reads as the manifest writes it (39.3077, not
    // 39.307701110839844).
    let mut json: serde_json::Value = serde_json::from_str(&m.to_json()).unwrap_or_default();
    if let Some(o) = json.as_object_mut() {
        o.remove("time_s");
        // The hash of the pixels is the manifest's to hold: the image's bytes stay as they were.
        o.remove("pixels");
        o.insert("image".into(), "reference".into());
    }
    let summary = format!(
        "hemilab {} reference of {} ({}x{}, d = {}): mean of {} replicates of {} rays per pixel of {} / {} / \
         {}, seed {}; noise floor {:.3e}",
        m.hemilab_version,
        m.scene,
        m.resolution[0],
        m.resolution[1],
        m.ao_distance,
        m.replicates,
        if m.adaptive.is_some() { format!("adaptive (pilot {})", m.rays) } else { m.rays.to_string() },
        m.distribution,
        m.sequence,
        m.seed_mode,
        m.seed,
        m.noise_floor.unwrap_or(f64::NAN)
    );
    Provenance { summary, json }
}

/// The stems of the other references of `m`'s scene file in `dir` (older views, other sizes): a
/// camera edit builds a new reference beside the old one, which is kept, so say what piles up.
fn others_of_scene(dir: &Path, m: &Manifest, mine: &str) -> Result<Vec<String>> {
    let mut out = Vec::new();
    for p in io::list_dir(dir)? {
        let stem = p.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        if p.extension().is_none_or(|e| e != "json") || stem == mine {
            continue;
        }
        let Ok(text) = io::read_string(&p) else { continue };
        if Manifest::from_json(&text).is_ok_and(|o| o.scene == m.scene) {
            out.push(stem);
        }
    }
    Ok(out)
}

/// Stores a freshly rendered reference (its mean and standard error over `replicates`, coverage)
/// as `manifest` says, atomically, image first, and says so; `started` is when its render began.
pub fn save(
    mut manifest: Manifest,
    mean: Image,
    stderr: Image,
    coverage: Image,
    dir: &Path,
    scene_name: &str,
    started: Instant,
) -> Result<Reference> {
    let (exr, json) = target(dir, &manifest);
    let (exr, json) = (exr.as_path(), json.as_path());
    manifest.noise_floor = Some(reference::noise_floor(&stderr, &coverage));
    manifest.time_s = Some(started.elapsed().as_secs_f64());
    if let Some(bad) = reference::first_non_finite(&mean, &stderr, &coverage) {
        return Err(Error::Refused(format!(
            "the reference rendered for '{scene_name}' is not finite: {bad}"
        )));
    }
    manifest.pixels = Some(reference::pixel_hash(&mean, &stderr, &coverage));
    // Image first, manifest last: a crash in between leaves no manifest, so nothing stale is reused.
    io::write_exr_with(
        exr,
        &[
            Channel { name: "Y", image: &mean },
            Channel { name: "stderr", image: &stderr },
            Channel { name: "A", image: &coverage },
        ],
        Some(&provenance(&manifest)),
    )?;
    io::write_atomic(json, manifest.to_json().as_bytes())?;
    let rays = match &manifest.adaptive {
        Some(a) => {
            let pixels = reference::noise_floor_pixels(&coverage);
            let mean = a.total_rays.unwrap_or(0) as f64 / pixels.max(1) as f64;
            format!("adaptive, {mean:.0} mean (pilot {} x {})", manifest.replicates, manifest.rays)
        }
        None => manifest.rays.to_string(),
    };
    eprintln!(
        "reference for '{}': {} x {} rays, noise floor {:.2e}, {:.1} s → {}",
        scene_name,
        manifest.replicates,
        rays,
        manifest.noise_floor.unwrap_or(0.0),
        manifest.time_s.unwrap_or(0.0),
        exr.display()
    );
    Ok(Reference { mean, stderr, coverage, manifest, exr: exr.to_path_buf() })
}

/// "note: DIR also holds N other reference(s) of SCENE …" after building `r`, if the directory
/// holds others of its scene (another view, size or AO distance): never deleted, so a user sees
/// where they come from. Not said of a camera path's frames, which are many views by design.
pub fn others_note(r: &Reference) -> Result<Option<String>> {
    let dir = r.exr.parent().unwrap_or(Path::new("."));
    let mine = r.exr.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let others = others_of_scene(dir, &r.manifest, &mine)?;
    Ok((!others.is_empty()).then(|| {
        format!(
            "note: {} also holds {} other reference(s) of '{}' (another view, size, AO distance or estimator; \
             never deleted, another spec may use them): {}",
            dir.display(),
            others.len(),
            r.manifest.scene,
            others.join(", ")
        )
    }))
}

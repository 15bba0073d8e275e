//! A spec with every scene it names, loaded and validated before any work: every command that
//! takes a spec (`run`, `plan`, `reference`) starts here, and the report reads the same `Loaded`;
//! the commands that take a scene file (`render`, `bench`, `advise`) load it here too.

use crate::error::{Error, Result};
use crate::io;
use crate::plan::Geometry;
use crate::plan::Job;
use crate::sampling::{SeedMode, Sequence};
use crate::scene::{self, Camera, Scene, file, mesh};
use crate::spec::{self, SceneRef, Spec};
use std::path::Path;
use std::sync::Arc;

mod describe;
mod open;
pub mod points;
mod realtime;
pub mod texture;

pub use describe::{check_view, facing_warning, summary};

/// The files a spec names besides its scenes (noise textures, point sets), read relative to the
/// spec's directory: what `spec::parse_spec_with` resolves their entries with.
pub struct SpecFiles<'a> {
    pub dir: &'a Path,
}

impl spec::Files for SpecFiles<'_> {
    fn texture(
        &self,
        written: &str,
        use_: crate::sampling::texture::TextureUse,
    ) -> std::result::Result<SeedMode, String> {
        texture::texture(self.dir, written, use_)
    }

    fn points(&self, written: &str) -> std::result::Result<Sequence, String> {
        points::points(self.dir, written)
    }
}

/// A `--seed-mode` value naming a texture, `texture:PATH[:offset|rotation|vector]` (default
/// `offset`), read relative to the current directory; the error names the flag and the file.
pub fn texture_arg(text: &str) -> Result<SeedMode> {
    let (path, use_) = texture_use(text.strip_prefix("texture:").unwrap_or(text));
    texture::texture(Path::new(""), path, use_).map_err(|e| Error::Usage(format!("--seed-mode {text}: {e}")))
}

/// `PATH[:offset|rotation|vector]` as (PATH, use); `offset` when no use ends it.
pub fn texture_use(text: &str) -> (&str, crate::sampling::texture::TextureUse) {
    use crate::sampling::texture::TextureUse;
    match text.rsplit_once(':').map(|(p, u)| (p, TextureUse::parse(u))) {
        Some((p, Ok(u))) => (p, u),
        _ => (text, TextureUse::Offset),
    }
}

/// A `--sequence` value naming a point file, `points:PATH`, read relative to the current directory.
pub fn points_arg(text: &str) -> Result<Sequence> {
    let path = text.strip_prefix("points:").unwrap_or(text);
    points::points(Path::new(""), path).map_err(|e| Error::Usage(format!("--sequence {text}: {e}")))
}

/// A spec with every scene it names loaded: all bad input is found here, before any work.
/// `scenes[i]` is the scene of `spec.scenes[i]`; the entries of one scene file measured under
/// several integrands share one loaded scene (one parse, one BVH).
pub struct Loaded {
    pub spec: Spec,
    pub scenes: Vec<Arc<Scene>>,
}

impl Loaded {
    /// The spec scene (index into `spec.scenes`, `scenes` and a run's references) a job measures:
    /// its scene file under its integrand.
    pub fn scene_of(&self, job: &Job) -> (usize, &Scene) {
        let i = self
            .spec
            .scenes
            .iter()
            .position(|s| s.id == job.scene_id && s.integrand == job.measurement.integrand)
            .expect("planned scene is in the spec");
        (i, &self.scenes[i])
    }
}

pub fn load(spec_path: &Path) -> Result<Loaded> {
    let text = read_named(spec_path, "spec")?;
    let dir = spec_path.parent().unwrap_or(Path::new(""));
    let spec = spec::parse_spec_with(&text, spec_path, &SpecFiles { dir })?;
    let jobs = crate::plan::plan(&spec).jobs;
    let mut scenes: Vec<Arc<Scene>> = Vec::with_capacity(spec.scenes.len());
    for (i, s) in spec.scenes.iter().enumerate() {
        match spec.scenes[..i].iter().position(|o| o.id == s.id) {
            Some(first) => scenes.push(Arc::clone(&scenes[first])),
            None => {
                let scene = Arc::new(load_named_scene(&spec, s, &jobs)?);
                if let Some(w) = dropped_warning(&scene) {
                    eprintln!("{w}");
                }
                scenes.push(scene);
            }
        }
    }
    if let Some(w) = single_replicate_warning(&spec) {
        eprintln!("{w}");
    }
    realtime::check_cameras(&spec, &scenes)?;
    realtime::probe_denoisers(&spec)?;
    Ok(Loaded { spec, scenes })
}

/// The real-time axes of a spec made in memory (advise's cameras and denoiser), checked before any
/// work as `load` checks a spec file's: every camera path's frames see the scene, and every
/// denoiser command runs on a test frame.
pub fn check_realtime(spec: &Spec, scenes: &[Arc<Scene>]) -> Result<()> {
    realtime::check_cameras(spec, scenes)?;
    realtime::probe_denoisers(spec)
}

/// A scene the spec names: a missing file is the spec's mistake, so the message points at its key;
/// an image too large to hold in memory is refused here rather than by the allocator mid-run.
/// Its BVH build effort follows the rays the spec's jobs and reference trace in it (`spec_rays`).
fn load_named_scene(spec: &Spec, s: &SceneRef, jobs: &[Job]) -> Result<Scene> {
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
    let scene = load_scene_with(&s.path, &|res| spec_rays(spec, s, jobs, res))?;
    let g = Geometry::of(spec.resolution, spec.ao_distance, &scene);
    check_pixels(g.width, g.height)
        .map_err(|e| Error::input(&spec.path, format!("key `resolution`: scene '{}': {e}", s.name)))?;
    if (g.width, g.height) != scene.resolution {
        check_view(&s.path, &scene, g.width, g.height)?;
    }
    Ok(scene)
}

/// Reads, parses and validates a scene file and its mesh, and builds the BVH. Every error names the
/// scene file (and its line/key) or the mesh file (and its line). The BVH gets the full build
/// effort (as a paper run's); see `load_scene_for`.
pub fn load_scene(path: &Path) -> Result<Scene> {
    load_scene_for(path, None, None)
}

/// `load_scene` for a command that will trace `rays_per_pixel` AO rays in each pixel of one image
/// of `resolution` (default: the scene's): the BVH build effort follows that work
/// (`scene::Effort::for_work`, counting the primary rays too). None: unknown, full effort.
pub fn load_scene_for(
    path: &Path,
    resolution: Option<(u32, u32)>,
    rays_per_pixel: Option<u32>,
) -> Result<Scene> {
    load_scene_with(path, &|res| {
        let (w, h) = resolution.unwrap_or(res);
        rays_per_pixel.map(|r| w as u64 * h as u64 * (r as u64 + 1))
    })
}

/// About the rays a spec traces in the scene file of `s`, whose own resolution is `res`: every
/// job's primary and AO rays in each frame up to the one it reports (under every integrand), and
/// each of its references' replicates (None, so
/// the full build, when the reference's rays are `auto`: decided later, by the measured errors).
/// Timing repeats and calibration renders come on top; the committed specs trace far more than
/// `FAST_BELOW_RAYS_PER_TRIANGLE` rays per triangle by this count alone, so they keep the full
/// build, and a small spec over a large scene (10 M triangles) gets the fast one.
fn spec_rays(spec: &Spec, s: &SceneRef, jobs: &[Job], res: (u32, u32)) -> Option<u64> {
    let spec::ReferenceRays::Fixed(reference) = spec.reference.rays else { return None };
    let pixels = |r: Option<[u32; 2]>| {
        r.or(spec.resolution).map_or(res.0 as u64 * res.1 as u64, |[w, h]| w as u64 * h as u64)
    };
    let mine = jobs.iter().filter(|j| j.scene_id == s.id);
    let frames = |j: &Job| j.measurement.frame.max(1) as u64;
    let traced: u64 = mine.map(|j| pixels(j.resolution) * (j.rays as u64 + 1) * frames(j)).sum();
    let references = spec.scenes.iter().filter(|o| o.id == s.id).count() as u64;
    Some(traced + references * pixels(None) * (reference as u64 + 1) * spec.reference.replicates as u64)
}

/// `load_scene` with the BVH build effort by `rays`: the rays the command will trace, given the
/// scene file's resolution (None: unknown, full effort).
fn load_scene_with(path: &Path, rays: &dyn Fn((u32, u32)) -> Option<u64>) -> Result<Scene> {
    let text = read_named(path, "scene")?;
    let spec = file::parse(&text).map_err(|e| Error::input(path, e))?;
    let lower = spec.mesh.to_ascii_lowercase();
    let gltf = file::is_gltf(&spec.mesh);
    if !(gltf || lower.ends_with(".obj") || lower.ends_with(".obj.zst")) {
        return Err(Error::input(
            path,
            format!(
                "key `mesh`: '{}' must be a Wavefront .obj or .obj.zst file, or a glTF 2.0 .gltf or .glb file",
                spec.mesh
            ),
        ));
    }
    let mesh_path = path.parent().unwrap_or(Path::new("")).join(&spec.mesh);
    if !io::exists(&mesh_path) {
        return Err(Error::input(
            path,
            format!(
                "key `mesh`: mesh file '{}' not found (looked for {}); mesh paths are relative to the scene file",
                spec.mesh,
                looked_for(&mesh_path, &spec.mesh)
            ),
        ));
    }
    let bytes = io::read_bytes(&mesh_path).map_err(|e| Error::input(path, format!("key `mesh`: {e}")))?;
    // The files a mesh names (glTF buffers and images, OBJ material libraries and their textures),
    // relative to the mesh file.
    let dir = mesh_path.parent().unwrap_or(Path::new("")).to_path_buf();
    let fetch = |name: &str, relative: String| {
        let p = dir.join(relative);
        if !io::exists(&p) {
            return Err(format!("file not found (looked for {})", looked_for(&p, name)));
        }
        io::read_bytes(&p).map_err(|e| e.to_string())
    };
    let (mesh, file_camera, external) = if gltf {
        let mut fetch = |uri: &str| fetch(uri, scene::gltf_mesh::uri_path(uri));
        let mut g =
            scene::gltf_mesh::parse_gltf(&bytes, &mut fetch).map_err(|e| Error::input(&mesh_path, e))?;
        // Its warnings (extensions ignored) name the file they are about.
        for n in &mut g.mesh.notes {
            *n = format!("{}: {n}", spec.mesh);
        }
        (g.mesh, g.camera, g.external)
    } else {
        let mut fetch = |name: &str| fetch(name, name.to_string());
        let o = mesh::parse_obj_with(&bytes, Some(&mut fetch)).map_err(|e| Error::input(&mesh_path, e))?;
        (o.mesh, None, o.external)
    };
    let view = match (&spec.camera.0, file_camera) {
        (Some(c), _) => c.camera(),
        (None, Some(c)) => c,
        (None, None) => {
            return Err(Error::input(
                path,
                format!(
                    "key `camera`: missing, and the glTF file '{}' has no camera placed by a node of its scene; {}",
                    spec.mesh,
                    file::MISSING_CAMERA
                ),
            ));
        }
    };
    let name = spec.name.clone().unwrap_or_else(|| {
        let stem = path.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        stem.strip_suffix(".toml").unwrap_or(&stem).to_string()
    });
    let mut parts: Vec<&[u8]> = vec![text.as_bytes(), &bytes];
    parts.extend(external.iter().map(|b| &b[..]));
    let hash = scene::content_hash(&parts);
    // The file's bytes are hashed: free them before the BVH build, the load's peak of memory.
    drop(parts);
    drop((bytes, external));
    let res = (spec.resolution.0, spec.resolution.1);
    let mut scene = Scene::new(name, view, res, spec.ao_distance.0, hash, mesh, rays(res)).map_err(|e| {
        // Its camera and distance were checked with the file; an empty mesh is the mesh's fault.
        Error::input(if e.starts_with(scene::EMPTY_MESH) { &mesh_path } else { path }, e)
    })?;
    scene.paths = spec.cameras.iter().map(|(n, c)| (n.clone(), c.path.clone(), c.jitter)).collect();
    let sight = check_view(path, &scene, res.0, res.1)?;
    let camera = match (&spec.camera.0, &scene.view) {
        (None, _) => {
            format!("the camera of the glTF file '{}' (a `[camera.perspective]` places another)", spec.mesh)
        }
        (Some(_), Camera::Perspective { .. }) => "key `camera.perspective.eye`".to_string(),
        (Some(_), Camera::Orthographic { .. }) => "key `camera.orthographic.eye`".to_string(),
    };
    if let Some(w) = facing_warning(path, &scene, &sight, &camera) {
        eprintln!("{w}");
    } else if let Some(w) = open::all_open_warning(path, &scene, &camera) {
        eprintln!("{w}");
    }
    Ok(scene)
}

/// A spec or scene file named on the command line, read whole: a missing one is one clear error
/// with the path it was looked for at (a relative path is relative to the current directory, which
/// may not be where the user thinks), not the operating system's bare "No such file or directory".
pub fn read_named(path: &Path, what: &str) -> Result<String> {
    if !io::exists(path) {
        let shown = path.display().to_string();
        return Err(Error::input(
            path,
            format!(
                "{what} file not found (looked for {}; a relative path is relative to the current directory)",
                looked_for(path, &shown)
            ),
        ));
    }
    if io::is_dir(path) {
        return Err(Error::input(path, format!("is a directory; name a {what} file (.toml)")));
    }
    io::read_string(path)
}

/// The absolute, normalized form of a path for "looked for" in messages (`fallback` if it has none).
fn looked_for(p: &Path, fallback: &str) -> String {
    std::path::absolute(p).map_or(fallback.to_string(), |p| crate::spec::normalize(&p.to_string_lossy()))
}

/// A group run with one replicate has no spread: its "± 0" would read as a certainty, so say it once.
pub fn single_replicate_warning(spec: &Spec) -> Option<String> {
    let single: Vec<&str> =
        spec.groups.iter().filter(|g| g.replicates == 1).map(|g| g.name.as_str()).collect();
    (!single.is_empty()).then(|| {
        format!(
            "warning: {}: {} one replicate ({}): no spread, so no standard error and every ± reads 0; \
             replicates = 4 (the default) gives one",
            spec.path.display(),
            if single.len() == 1 { "this group has" } else { "these groups have" },
            single.join(", ")
        )
    })
}

/// The warnings of a scene's load, if any, one line each: triangles dropped (zero area or
/// non-finite), and mesh elements skipped because they are not faces (AO renders surfaces only).
pub fn dropped_warning(scene: &Scene) -> Option<String> {
    let mut lines = Vec::new();
    if scene.dropped_triangles > 0 {
        lines.push(format!(
            "warning: scene '{}': dropped {} triangles with zero area or non-finite vertices",
            scene.name, scene.dropped_triangles
        ));
    }
    if let Some(s) = &scene.skipped_elements {
        lines.push(format!(
            "warning: scene '{}': skipped mesh elements that are not faces: {s}; AO renders faces only",
            scene.name
        ));
    }
    for n in &scene.notes {
        lines.push(format!("warning: scene '{}': {n}", scene.name));
    }
    (!lines.is_empty()).then(|| lines.join("\n"))
}

/// An image size outside the one limit (`spec::resolution_ok`: what specs, scene files and the
/// command line accept) is refused before any work, rather than by the allocator mid-run. Callers
/// add where the size came from.
pub fn check_pixels(w: u32, h: u32) -> std::result::Result<(), String> {
    if !spec::resolution_ok(w as u64, h as u64) {
        return Err(format!("{w}x{h} is too large to hold in memory; {}", spec::RESOLUTION_RULE));
    }
    Ok(())
}

/// Loads a scene for one image of `resolution` (default: the scene's), refusing an absurd size
/// before the mesh is even read, and prints the dropped-triangle warning. Full BVH effort.
pub fn scene_at(path: &Path, resolution: Option<(u32, u32)>) -> Result<(Scene, u32, u32)> {
    scene_for(path, resolution, None)
}

/// `scene_at` for one image with `rays_per_pixel` AO rays a pixel: the BVH effort follows the
/// work (`load_scene_for`).
pub fn scene_for(
    path: &Path,
    resolution: Option<(u32, u32)>,
    rays_per_pixel: Option<u32>,
) -> Result<(Scene, u32, u32)> {
    let usage = |e: String| Error::Usage(format!("resolution {e}"));
    if let Some((w, h)) = resolution {
        check_pixels(w, h).map_err(usage)?;
    }
    let scene = load_scene_for(path, resolution, rays_per_pixel)?;
    if let Some(w) = dropped_warning(&scene) {
        eprintln!("{w}");
    }
    image_size(path, &scene, resolution).map(|(width, height)| (scene, width, height))
}

/// `scene_for`'s size of an image of `scene` at `resolution` (default: the scene's), for a caller
/// that loads a scene once and renders it at several sizes (the Python module's `Scene`).
pub fn image_size(path: &Path, scene: &Scene, resolution: Option<(u32, u32)>) -> Result<(u32, u32)> {
    let (width, height) = resolution.unwrap_or(scene.resolution);
    check_pixels(width, height).map_err(|e| Error::Usage(format!("resolution {e}")))?;
    if (width, height) != scene.resolution {
        check_view(path, scene, width, height)?;
    }
    Ok((width, height))
}

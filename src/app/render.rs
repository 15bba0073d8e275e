//! `hemilab render`, and scene loading for the whole app.

use crate::cli::RenderArgs;
use crate::error::{Error, Result};
use crate::image::{self, Channel, Image};
use crate::io;
use crate::progress;
use crate::render::{self, RenderJob, RenderOutput};
use crate::sampling::SamplerConfig;
use crate::scene::{self, Scene, file, mesh};
use std::path::{Path, PathBuf};
use std::time::Instant;

pub use crate::spec::MAX_PIXELS;

/// Reads, parses and validates a scene file and its mesh, and builds the BVH. Every error names the
/// scene file (and its line/key) or the mesh file (and its line).
pub fn load_scene(path: &Path) -> Result<Scene> {
    let text = io::read_string(path)?;
    let spec = file::parse(&text).map_err(|e| Error::input(path, e))?;
    let lower = spec.mesh.to_ascii_lowercase();
    if !(lower.ends_with(".obj") || lower.ends_with(".obj.zst")) {
        return Err(Error::input(
            path,
            format!("key `mesh`: '{}' must be a Wavefront .obj or .obj.zst file", spec.mesh),
        ));
    }
    let mesh_path = path.parent().unwrap_or(Path::new("")).join(&spec.mesh);
    if !io::exists(&mesh_path) {
        let looked = std::path::absolute(&mesh_path)
            .map_or(spec.mesh.clone(), |p| crate::spec::normalize(&p.to_string_lossy()));
        return Err(Error::input(
            path,
            format!(
                "key `mesh`: mesh file '{}' not found (looked for {looked}); mesh paths are relative to the \
                 scene file",
                spec.mesh
            ),
        ));
    }
    let bytes = io::read_bytes(&mesh_path).map_err(|e| Error::input(path, format!("key `mesh`: {e}")))?;
    let mesh = mesh::parse_obj(&bytes).map_err(|e| Error::input(&mesh_path, e))?;
    let name = spec.name.clone().unwrap_or_else(|| {
        let stem = path.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        stem.strip_suffix(".toml").unwrap_or(&stem).to_string()
    });
    let hash = scene::content_hash(&[text.as_bytes(), &bytes]);
    let res = (spec.resolution.0, spec.resolution.1);
    Scene::new(name, spec.camera.camera(), res, spec.ao_distance.0, hash, mesh)
        .map_err(|e| Error::input(path, e))
}

/// The one-line warning for triangles dropped at load, if any.
pub fn dropped_warning(scene: &Scene) -> Option<String> {
    (scene.dropped_triangles > 0).then(|| {
        format!(
            "warning: scene '{}': dropped {} triangles with zero area or non-finite vertices",
            scene.name, scene.dropped_triangles
        )
    })
}

pub(super) fn check_pixels(w: u32, h: u32) -> Result<()> {
    if w as u64 * h as u64 > MAX_PIXELS {
        return Err(Error::Usage(format!(
            "resolution {w}x{h} is too large to hold in memory; {}",
            crate::spec::RESOLUTION_RULE
        )));
    }
    Ok(())
}

/// Loads a scene for one image of `resolution` (default: the scene's), refusing an absurd size
/// before the mesh is even read, and prints the dropped-triangle warning.
pub(super) fn scene_at(path: &Path, resolution: Option<(u32, u32)>) -> Result<(Scene, u32, u32)> {
    if let Some((w, h)) = resolution {
        check_pixels(w, h)?;
    }
    let scene = load_scene(path)?;
    if let Some(w) = dropped_warning(&scene) {
        eprintln!("{w}");
    }
    let (width, height) = resolution.unwrap_or(scene.resolution);
    check_pixels(width, height)?;
    Ok((scene, width, height))
}

pub(super) fn pool(threads: Option<u32>) -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0) as usize)
        .build()
        .map_err(|e| Error::Refused(format!("cannot start worker threads: {e}")))
}

pub fn run_render(args: RenderArgs) -> Result<()> {
    let out = &args.output;
    if !out.to_string_lossy().to_ascii_lowercase().ends_with(".exr") {
        return Err(Error::Usage(format!("--output {}: must name an .exr file", out.display())));
    }
    let png = out.with_extension("png");
    let sampler =
        SamplerConfig::new(args.sampling.sequence, args.sampling.seed_mode, args.rays, args.sampling.seed)
            .map_err(|e| Error::Usage(format!("--rays: {e}")))?;
    let (scene, width, height) = scene_at(&args.scene, args.resolution)?;
    let dir = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    io::ensure_writable_dir(&dir)?;
    io::ensure_writable_file(out)?;
    io::ensure_writable_file(&png)?;

    let job = RenderJob {
        distribution: args.sampling.distribution,
        sampler,
        width,
        height,
        ao_distance: scene.ao_distance,
    };
    let bar = progress::bar(width as u64 * height as u64, "render", args.common.quiet);
    let start = Instant::now();
    let result = pool(args.common.threads)?.install(|| render::render(&scene, &job, &|n| bar.inc(n)));
    let secs = start.elapsed().as_secs_f64();
    bar.finish_and_clear();

    let exr = image::encode_exr(&[
        Channel { name: "Y", image: &result.ao },
        Channel { name: "A", image: &result.coverage },
    ])
    .map_err(|e| Error::input(out, format!("cannot encode EXR: {e}")))?;
    let preview = image::encode_png_gray(&preview(&result))
        .map_err(|e| Error::input(&png, format!("cannot encode PNG: {e}")))?;
    io::write_atomic(out, &exr)?;
    io::write_atomic(&png, &preview)?;
    if !args.common.quiet {
        println!(
            "{}: {width}x{height}, {} rays/pixel, {} AO rays in {secs:.2} s ({:.2} M rays/s) -> {}, {}",
            scene.name,
            args.rays,
            result.rays,
            result.rays as f64 / secs.max(1e-9) / 1e6,
            out.display(),
            png.display()
        );
    }
    Ok(())
}

/// The PNG preview: AO clamped to [0, 1] by the encoder, background black so it stands out.
fn preview(r: &RenderOutput) -> Image {
    let data = r.ao.data.iter().zip(&r.coverage.data).map(|(&a, &c)| if c > 0.0 { a } else { 0.0 }).collect();
    Image::from_vec(r.ao.width, r.ao.height, data)
}

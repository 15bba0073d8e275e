//! `hemilab render`, and scene loading for the whole app.

use crate::cli::RenderArgs;
use crate::error::{Error, Result};
use crate::image::{self, Channel, Provenance};
use crate::io;
use crate::load::scene_for;
use crate::progress;
use crate::render::{self, RenderJob, RenderOutput};
use crate::scene::Scene;
use crate::spec::AoDistance;
use std::path::{Path, PathBuf};
use std::time::Instant;

pub fn run(args: RenderArgs) -> Result<()> {
    // Absolute and without `..`: a missing directory is made where the path says, and said so.
    let out = &crate::io::absolute(&args.output);
    if !out.to_string_lossy().to_ascii_lowercase().ends_with(".exr") {
        return Err(Error::Usage(format!("--output {}: must name an .exr file", args.output.display())));
    }
    let png = out.with_extension("png");
    let s = &args.sampling;
    let (_, sampler) = crate::app::sampler(
        s.distribution,
        &s.sequence,
        &s.seed_mode,
        s.seed,
        &s.frames,
        args.rays,
        "--rays",
    )?;
    // The BVH's build effort follows the rays this image traces (`scene::Effort::for_work`).
    let (scene, width, height) = scene_for(&args.scene, args.resolution, Some(args.rays))?;
    let dir = out.parent().map_or_else(|| PathBuf::from("/"), Path::to_path_buf);
    io::ensure_writable_dir(&dir)?;
    io::ensure_writable_file(out)?;
    io::ensure_writable_file(&png)?;
    // Made by the first write below; said afterwards, so that a mistyped path does not go unseen.
    let creates_dir = !io::exists(&dir);

    let job = RenderJob {
        distribution: args.sampling.distribution,
        sampler,
        width,
        height,
        ao_distance: scene.ao_distance,
    };
    if !args.common.quiet {
        println!("{}", crate::load::summary(&scene, width, height));
    }
    // The masks and tables it reads, before the clock starts (the spatiotemporal masks take seconds).
    job.sampler.prepare();
    // What it will cost, before it starts: refused over --max-minutes (exit 2, nothing written).
    let threads = crate::jobs::Threads::resolve(args.common.threads);
    let forecast = crate::jobs::forecast::render(&scene, &job, args.integrand, threads.pool_threads)?;
    forecast
        .check(args.max_minutes)
        .map_err(|e| Error::Usage(format!("{}\n{e}", forecast.line("render"))))?;
    if !args.common.quiet {
        println!("{}", forecast.line("render"));
    }
    crate::interrupt::renders_one_image(&args.output);
    let bar = progress::bar(width as u64 * height as u64, "render", args.common.quiet);
    let start = Instant::now();
    let result =
        threads.pool()?.install(|| render::render_integrand(&scene, &job, args.integrand, &|n| bar.inc(n)));
    let secs = start.elapsed().as_secs_f64();
    bar.finish_and_clear();

    let provenance = provenance(&args, &scene, &job);
    let exr = image::encode_exr_with(
        &[Channel { name: "Y", image: &result.ao }, Channel { name: "A", image: &result.coverage }],
        Some(&provenance),
    )
    .map_err(|e| Error::input(out, format!("cannot encode EXR: {e}")))?;
    let preview = image::encode_png_rgb(width, height, &preview(&result))
        .map_err(|e| Error::input(&png, format!("cannot encode PNG: {e}")))?;
    io::write_atomic(out, &exr)?;
    io::write_atomic(&png, &preview)?;
    if creates_dir {
        eprintln!("note: created the directory {} for --output (it did not exist)", dir.display());
    }
    if !args.common.quiet {
        println!(
            "{}: {width}x{height}, {} rays/pixel, {} AO rays in {secs:.2} s ({:.2} M rays/s) -> {}, {}",
            scene.name,
            args.rays,
            result.rays,
            result.rays as f64 / secs.max(1e-9) / 1e6,
            args.output.display(),
            args.output.with_extension("png").display()
        );
    }
    Ok(())
}

/// What the EXR's header says about where it came from (`image::Provenance`).
fn provenance(args: &RenderArgs, scene: &Scene, job: &RenderJob) -> Provenance {
    let s = &args.sampling;
    let (sequence, seed_mode) = (job.sampler.sequence, job.sampler.seed_mode);
    // Written as a run's images and the references write it (`AoDistance::canonical`).
    let d = match job.ao_distance {
        d if d.is_finite() => AoDistance::Finite(d as f64),
        _ => AoDistance::Infinite,
    }
    .canonical();
    let file = args.scene.to_string_lossy();
    let mut json = serde_json::json!({
        "image": "render",
        "hemilab_version": env!("CARGO_PKG_VERSION"),
        "scene": file,
        "scene_name": scene.name,
        "scene_hash": scene.content_hash,
        "distribution": s.distribution.name(),
        "sequence": sequence.name(),
        "seed_mode": seed_mode.name(),
        "rays": args.rays,
        "seed": s.seed,
        "resolution": [job.width, job.height],
        "ao_distance": d,
    });
    // A frame past 0 says which and how (a single image's header stays as it was).
    let (frame, schedule) = (job.sampler.frame, job.sampler.schedule);
    let framed = frame != 0 || schedule != crate::sampling::Schedule::Independent;
    if framed {
        json["frame"] = frame.into();
        json["schedule"] = schedule.name().into();
    }
    // Another integrand says which (an AO image's header stays as it was).
    let integrand = args.integrand;
    if integrand != crate::sampling::Integrand::Ao {
        json["integrand"] = integrand.to_string().into();
    }
    let mut summary = format!(
        "hemilab {} render of {file} ('{}', {}x{}, d = {d}, hash {}): {} / {} / {}, {} rays per pixel, seed {}",
        env!("CARGO_PKG_VERSION"),
        scene.name,
        job.width,
        job.height,
        scene.content_hash,
        s.distribution.name(),
        sequence.name(),
        seed_mode.name(),
        args.rays,
        s.seed
    );
    if framed {
        summary.push_str(&format!(", frame {frame} ({schedule})"));
    }
    if integrand != crate::sampling::Integrand::Ao {
        summary.push_str(&format!(", integrand {integrand}"));
    }
    Provenance { summary, json }
}

/// The PNG preview: AO in gray, clamped to [0, 1]; where no surface is seen, a blue checkerboard,
/// so that background never reads as full occlusion (black) or as open sky (white).
fn preview(r: &RenderOutput) -> Vec<u8> {
    let w = r.ao.width;
    let mut rgb = Vec::with_capacity(r.ao.len() * 3);
    for (i, (&a, &c)) in r.ao.data.iter().zip(&r.coverage.data).enumerate() {
        let (x, y) = (i as u32 % w, i as u32 / w);
        let px = if c > 0.0 {
            let v = image::to_u8(a);
            [v, v, v]
        } else if (x / 8 + y / 8).is_multiple_of(2) {
            NO_SURFACE[0]
        } else {
            NO_SURFACE[1]
        };
        rgb.extend_from_slice(&px);
    }
    rgb
}

/// The preview's two colours for "no surface" (`preview`).
pub const NO_SURFACE: [[u8; 3]; 2] = [[40, 60, 110], [60, 85, 140]];

//! A fixed amount of render or AO-query work on one thread, for profilers (perf, callgrind):
//! `cargo run --release --example profile_render -- SCENE.toml MODE D [REPEATS] [RAYS]`, MODE one
//! of `render` (whole renders), `query` (hemilab's AO query on the render's rays), `single`
//! (hemilab's single-ray walk, `Accel::occluded`, on each of them), `obvhs` (plain obvhs on them),
//! `rays` (only collecting the ray set), `points` and `directions` (each covered
//! pixel's point set, and its point set and directions around its normal: what the render spends
//! on them, per direction) or `primaries` (the primary rays alone, in packets of 8 × 4 pixels as the
//! renderer traces them; the camera rays' making included). Prints the wall time of the timed part.
//! Timing figures of record come from `hemilab bench`, not from this.

use hemilab::render::{self, RenderJob, bench};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let scene = hemilab::load::load_scene(std::path::Path::new(&args[1]))?;
    let mode = args.get(2).map(String::as_str).unwrap_or("render");
    let d: f32 = match args.get(3).map(String::as_str) {
        None => scene.ao_distance,
        Some("inf") => f32::INFINITY,
        Some(s) => s.parse()?,
    };
    let repeats: u32 = args.get(4).map(|s| s.parse()).transpose()?.unwrap_or(3);
    let rays: u32 = args.get(5).map(|s| s.parse()).transpose()?.unwrap_or(32);
    let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, rays, 1)?;
    let (width, height) = scene.resolution;
    let job = RenderJob { distribution: Distribution::SineCosine, sampler, width, height, ao_distance: d };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    let set =
        (mode != "render" && mode != "rays" && mode != "primaries").then(|| bench::ray_set(&scene, &job));
    let base = if mode == "obvhs" { Some(bench::obvhs_baseline(&scene)) } else { None };
    let start = Instant::now();
    let mut count = 0u64;
    for _ in 0..repeats {
        match mode {
            "render" => count += pool.install(|| render::render(&scene, &job, &|_| {})).occluded_rays,
            "rays" => count += bench::ray_set(&scene, &job).len() as u64,
            "single" => {
                let set = set.as_ref().expect("made above");
                for (i, dir) in set.dirs.iter().enumerate() {
                    let o = set.origins[i / set.n];
                    count += scene.accel.occluded(&hemilab::scene::accel::Ray::new(o, *dir, d)) as u64;
                }
            }
            "query" | "obvhs" => {
                let set = set.as_ref().expect("made above");
                match &base {
                    Some(b) => {
                        let mut out = vec![false; set.len()];
                        pool.install(|| bench::trace_obvhs(b, set, d, &mut out));
                        count += out.iter().filter(|&&b| b).count() as u64;
                    }
                    None => {
                        let mut out = vec![0u32; set.origins.len() * set.masks_per_pixel()];
                        pool.install(|| bench::trace_hemilab(&scene, set, d, &mut out));
                        count += out.iter().map(|m| m.count_ones() as u64).sum::<u64>();
                    }
                }
            }
            "points" | "directions" => {
                let set = set.as_ref().expect("made above");
                let mut points = vec![glam::Vec2::ZERO; rays as usize];
                let mut batch = hemilab::sampling::batch::Directions::default();
                let (w, order) = (width as u64, hemilab::render::pixel_order(width, height));
                // The covered pixels, as the ray set lists them (the same order).
                let covered = order.filter(|&(x, y)| {
                    let r = scene.camera.ray(x, y, width, height);
                    scene
                        .accel
                        .closest(&hemilab::scene::accel::Ray::new(r.origin, r.dir, f32::INFINITY))
                        .is_some()
                });
                let covered: Vec<(u32, u32)> = covered.collect();
                let t0 = Instant::now();
                for (&(x, y), n) in covered.iter().zip(&set.normals) {
                    sampler.fill_pixel(x, y, y as u64 * w + x as u64, &mut points);
                    if mode == "directions" {
                        batch.fill(job.distribution, &points, &hemilab::sampling::Frame::from_normal(*n));
                        count += batch.len() as u64;
                    } else {
                        count += points.len() as u64;
                    }
                }
                let ns = t0.elapsed().as_secs_f64() * 1e9 / (covered.len() as f64 * rays as f64);
                println!("{mode}: {ns:.2} ns per direction");
            }
            "primaries" => {
                // The renderer's primary packets: 8 × 4 pixels from the eye (`render::tile_primaries`).
                let raster = scene.camera.raster(width, height);
                let o = raster.ray(0, 0).origin;
                let mut hits = [None; 32];
                let t0 = Instant::now();
                for y0 in (0..height).step_by(4) {
                    for x0 in (0..width).step_by(8) {
                        let dirs: Vec<glam::Vec3> = (y0..(y0 + 4).min(height))
                            .flat_map(|y| (x0..(x0 + 8).min(width)).map(move |x| (x, y)))
                            .map(|(x, y)| raster.ray(x, y).dir)
                            .collect();
                        let k = dirs.len();
                        scene.accel.closest_from(o, &dirs, f32::INFINITY, &mut hits[..k]);
                        count += hits[..k].iter().filter(|h| h.is_some()).count() as u64;
                    }
                }
                let ns = t0.elapsed().as_secs_f64() * 1e9 / (width as f64 * height as f64);
                println!("{mode}: {ns:.1} ns per primary ray");
            }
            other => return Err(format!("unknown mode {other}").into()),
        }
    }
    println!("{mode} d={d}: {:.3} s for {repeats} repeats ({count})", start.elapsed().as_secs_f64());
    Ok(())
}

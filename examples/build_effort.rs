//! The BVH build effort's trade-off (docs/performance.md): for each scene, the core build
//! time of the full and the fast build and the AO query speed through each tree (hemilab's query,
//! one thread, the bench's ray set at the scene's d), min / median / max of REPEATS:
//! `cargo run --release --example build_effort -- REPEATS SCENE.toml...`. Prints markdown rows.
//! The `hemilab bench` figures of record use the full build, as the paper runs do.

use hemilab::render::{RenderJob, bench};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use std::time::Instant;

fn spread(mut v: Vec<f64>) -> String {
    v.sort_by(f64::total_cmp);
    format!("{:.3} ({:.3}..{:.3})", v[v.len() / 2], v[0], v[v.len() - 1])
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let repeats: usize = args[0].parse()?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
    println!("| scene | triangles | build | core build s | AO query M rays/s (1 thread) |");
    println!("|---|---|---|---|---|");
    for path in &args[1..] {
        let path = std::path::Path::new(path);
        for (name, rays) in [("full", None), ("fast", Some(1))] {
            let mut build = Vec::new();
            let mut scene = None;
            for _ in 0..repeats {
                let s = hemilab::load::load_scene_for(path, Some((1, 1)), rays)?;
                build.push(s.bvh_build_s);
                scene = Some(s);
            }
            let scene = scene.expect("repeats > 0");
            let sampler = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 32, 1)?;
            let (width, height) = scene.resolution;
            let d = scene.ao_distance;
            let job =
                RenderJob { distribution: Distribution::SineCosine, sampler, width, height, ao_distance: d };
            let set = bench::ray_set(&scene, &job);
            let mut speed = Vec::new();
            for _ in 0..repeats {
                let mut out = vec![0u32; set.origins.len() * set.masks_per_pixel()];
                let t = Instant::now();
                pool.install(|| bench::trace_hemilab(&scene, &set, d, &mut out));
                speed.push(set.len() as f64 / t.elapsed().as_secs_f64() / 1e6);
            }
            println!(
                "| {} | {} | {name} | {} | {} |",
                scene.name,
                scene.triangle_count,
                spread(build),
                spread(speed)
            );
        }
    }
    Ok(())
}

//! How docs/realtime.md's numbers for the user's own denoiser were measured: renders 1-ray frames
//! of a scene at a committed reference's size, runs a `DenoiseCommand` on each (after `probe`),
//! and prints the RMSE against the reference before and after, and the command's time
//! (min/median/max over the frames).
//!
//! cargo run --release --example denoise_check -- SCENE.toml REFERENCE.exr FRAMES PROGRAM [ARGS…]
//!
//! e.g. `… scenes/kitchen.toml reference/kitchen-128x96-7776d997.exr 5 python3
//! examples/oidn_denoise.py {input} {output}`.

use hemilab::denoise_command::DenoiseCommand;
use hemilab::render::{RenderJob, gbuffer, render};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        return Err("usage: denoise_check SCENE.toml REFERENCE.exr FRAMES PROGRAM [ARGS…]".into());
    }
    let frames: u32 = args[2].parse()?;
    let reference = hemilab::io::read_exr(Path::new(&args[1]))?
        .into_iter()
        .find(|(n, _)| n == "Y")
        .ok_or("the reference has no Y channel")?
        .1;
    let (w, h) = (reference.width, reference.height);
    let scene = hemilab::load::load_scene_for(Path::new(&args[0]), Some((w, h)), Some(1))?;
    let command = DenoiseCommand { program: args[3].clone(), args: args[4..].to_vec(), timeout_s: 600.0 };
    command.validate()?;
    let dir = std::env::temp_dir().join(format!("hemilab-denoise-check-{}", std::process::id()));
    command.probe(&dir)?;
    let g = gbuffer(&scene, w, h);
    let (mut before, mut after, mut times) = (Vec::new(), Vec::new(), Vec::new());
    for f in 0..frames {
        let job = RenderJob {
            distribution: Distribution::SineCosine,
            sampler: SamplerConfig::new(Sequence::Random, SeedMode::Shift, 1, 1).unwrap().with_frame(f),
            width: w,
            height: h,
            ao_distance: scene.ao_distance,
        };
        let frame = render(&scene, &job, &|_| {});
        let (denoised, took) = command.run(&dir, &frame.ao, &g)?;
        let rmse = |img| hemilab::metrics::measure(img, &reference, &frame.coverage).map(|s| s.rmse);
        before.push(rmse(&frame.ao)?);
        after.push(rmse(&denoised)?);
        times.push(took.as_secs_f64());
    }
    hemilab::io::remove_dir_all_if_exists(&dir)?;
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    times.sort_by(f64::total_cmp);
    println!(
        "{} at {w}x{h}, {frames} one-ray frames (sine-cosine, random, shift): RMSE {:.4} -> {:.4} (mean); \
         command time min/median/max {:.3}/{:.3}/{:.3} s",
        scene.name,
        mean(&before),
        mean(&after),
        times[0],
        times[times.len() / 2],
        times[times.len() - 1]
    );
    Ok(())
}

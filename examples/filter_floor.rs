//! The bias floor of each real-time filter: RMSE(F(reference), reference) over covered
//! pixels, with "reference" a high-ray render of the scene, for à-trous at 1…5 passes and at the
//! share-of-image default (`denoise::default_iterations`), SVGF with its temporal part converged
//! (the reference pushed as every frame) at 5 passes and at the default; then the noise/bias split
//! of each pipeline (ema0.1+atrous, taa0.1+atrous and svgf at 1…5 passes and the default) on
//! noisy frames (1 ray per pixel per frame, the lattice with blue-noise offsets, independent
//! per-frame seeds, a static camera) by the joint application `FrameFilter::push_pair`: at the last
//! frame the RMSE against the reference, the noise part RMSE(F_w(noisy), F_w(reference)), the
//! bias part RMSE(F_w(reference), reference) and the flicker over the frames
//! (`metrics::flicker_sequence`).
//!
//! `cargo run --release --example filter_floor -- RAYS FRAMES WxH[,WxH...] SCENE.toml...`,
//! e.g. `-- 1024 16 96x72,320x180 scenes/kitchen.toml scenes/cornell-box.toml scenes/slats.toml`.
//! Prints markdown tables (the reference's own noise, the RMS difference of two renders over
//! √2, on stderr). About 7 minutes on two cores for the example's three scenes at both sizes.

use hemilab::denoise::{Motion, Pipeline, default_iterations};
use hemilab::image::Image;
use hemilab::metrics;
use hemilab::render::{self, RenderJob};
use hemilab::sampling::{Distribution, SamplerConfig, Schedule, SeedMode, Sequence};
use hemilab::scene::Scene;
use std::path::Path;

fn render_ao(scene: &Scene, w: u32, h: u32, sampler: SamplerConfig) -> Image {
    let job = RenderJob {
        distribution: Distribution::SineCosine,
        sampler,
        width: w,
        height: h,
        ao_distance: scene.ao_distance,
    };
    render::render(scene, &job, &|_| {}).ao
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 4 {
        return Err("usage: filter_floor RAYS FRAMES WxH[,WxH...] SCENE.toml...".into());
    }
    let rays: u32 = args[0].parse()?;
    let frames: u32 = args[1].parse()?;
    let sizes: Vec<(u32, u32)> = args[2]
        .split(',')
        .map(|s| {
            let (w, h) = s.split_once('x').ok_or("a size is WxH")?;
            Ok((w.parse()?, h.parse()?))
        })
        .collect::<Result<_, Box<dyn std::error::Error>>>()?;
    let mut floors =
        vec!["| scene | size | filter | passes | floor RMSE |".to_string(), "|---|---|---|---|---|".into()];
    let mut splits = vec![
        format!("| scene | size | pipeline (frame {frames}) | RMSE | noise part | bias part | flicker |"),
        "|---|---|---|---|---|---|---|".into(),
    ];
    for path in &args[3..] {
        for &(w, h) in &sizes {
            let (scene, w, h) = hemilab::load::scene_for(Path::new(path), Some((w, h)), Some(rays))?;
            let g = render::gbuffer(&scene, w, h);
            let reference =
                render_ao(&scene, w, h, SamplerConfig::new(Sequence::Fibonacci, SeedMode::Shift, rays, 7)?);
            let cov = &g.coverage;
            // The reference's own noise: half the RMS difference of two independent renders, √2 σ.
            let again =
                render_ao(&scene, w, h, SamplerConfig::new(Sequence::Fibonacci, SeedMode::Shift, rays, 8)?);
            let own = metrics::measure(&again, &reference, cov)?.rmse / 2f64.sqrt();
            eprintln!("{} at {w}x{h}: the {rays}-ray reference's own noise {own:.4}", scene.name);
            let still = Motion::identity(w, h);
            let rmse = |a: &Image, b: &Image| metrics::measure(a, b, cov).map(|s| s.rmse);
            let k0 = default_iterations(w, h);
            let mut row = |name: &str, passes: u32, out: &Image| -> Result<(), Box<dyn std::error::Error>> {
                let e = rmse(out, &reference)?;
                let e = if e < 1e-3 { format!("{e:.1e}") } else { format!("{e:.4}") };
                floors.push(format!("| {} | {w}x{h} | {name} | {passes} | {e} |", scene.name));
                Ok(())
            };
            row("gauss", 0, &"gauss".parse::<Pipeline>()?.start(w, h).push(&reference, &g, &still))?;
            for k in 1..=5 {
                let p: Pipeline = format!("atrous:{k}").parse()?;
                row("atrous", k, &p.start(w, h).push(&reference, &g, &still))?;
            }
            row(
                "atrous (default)",
                k0,
                &"atrous".parse::<Pipeline>()?.start(w, h).push(&reference, &g, &still),
            )?;
            for (name, k) in [("svgf:5", 5), ("svgf", k0)] {
                let mut f = name.parse::<Pipeline>()?.start(w, h);
                let mut out = reference.clone();
                for _ in 0..64 {
                    out = f.push(&reference, &g, &still);
                }
                row(&format!("{name} (converged)"), k, &out)?;
            }
            // The noise/bias split on noisy frames.
            let base = SamplerConfig::new(Sequence::Fibonacci, SeedMode::BlueNoise, 1, 11)?
                .with_schedule(Schedule::Independent);
            let noisy: Vec<Image> =
                (0..frames).map(|f| render_ao(&scene, w, h, base.with_frame(f))).collect();
            let mut names: Vec<String> = ["raw", "atrous:5", "atrous"].map(String::from).to_vec();
            for base in ["ema0.1+atrous", "taa0.1+atrous", "svgf"] {
                names.extend((1..=5).map(|k| format!("{base}:{k}")));
                names.push(base.into());
            }
            for name in &names {
                let p: Pipeline = name.parse()?;
                let mut f = p.start(w, h);
                let (mut outs, mut refs) = (Vec::new(), Vec::new());
                for frame in &noisy {
                    let (o, r) = f.push_pair(frame, &reference, &g, &still);
                    outs.push(o);
                    refs.push(r);
                }
                let (o, r) = (outs.last().unwrap(), refs.last().unwrap());
                let flick = metrics::flicker_sequence(&outs, &vec![reference.clone(); outs.len()], cov)?;
                splits.push(format!(
                    "| {} | {w}x{h} | {name} | {:.4} | {:.4} | {:.4} | {flick:.4} |",
                    scene.name,
                    rmse(o, &reference)?,
                    rmse(o, r)?,
                    rmse(r, &reference)?
                ));
            }
        }
    }
    println!("{}\n\n{}", floors.join("\n"), splits.join("\n"));
    Ok(())
}

//! What one real-time frame's filtering and measuring cost at the real-time runs' size (320x180):
//! SVGF (2 passes shown, then state advanced), its à-trous pass, the per-job metrics
//! (`metrics::measure`) and LDR-FLIP against a reference, on the frames of a scene rendered at 1
//! ray per pixel per frame. Prints the best of several repetitions of each (a loaded machine only
//! ever makes it slower) and a checksum of every output's bits, so that a change that claims the
//! same results can be checked to give them.
//!
//!     cargo run --release --example filter_speed -- scenes/kitchen.toml [FRAMES]

use hemilab::denoise::{Motion, Svgf, SvgfParams};
use hemilab::image::Image;
use hemilab::metrics::{self, flip};
use hemilab::render::{self, RenderJob};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use std::path::Path;
use std::time::Instant;

fn best<T>(reps: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut out = None;
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let t = Instant::now();
        let o = f();
        best = best.min(t.elapsed().as_secs_f64());
        out = Some(o);
    }
    (best, out.expect("reps > 0"))
}

fn hash(h: &mut u64, v: impl Iterator<Item = u64>) {
    for x in v {
        *h = (*h ^ x).wrapping_mul(0x100_0000_01b3).rotate_left(17);
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().ok_or("usage: filter_speed SCENE.toml [FRAMES]")?;
    let frames: u32 = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(16);
    let (scene, w, h) = hemilab::load::scene_for(Path::new(path), Some((320, 180)), Some(1))?;
    let g = render::gbuffer(&scene, w, h);
    let job = |sampler: SamplerConfig| RenderJob {
        distribution: Distribution::SineCosine,
        sampler,
        width: w,
        height: h,
        ao_distance: scene.ao_distance,
    };
    let base = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 1, 11)?;
    let noisy: Vec<Image> =
        (0..frames).map(|f| render::render(&scene, &job(base.with_frame(f)), &|_| {}).ao).collect();
    let reference = render::render(
        &scene,
        &job(SamplerConfig::new(Sequence::Fibonacci, SeedMode::Shift, 256, 7)?),
        &|_| {},
    )
    .ao;
    let still = Motion::identity(w, h);
    let mut check = 0u64;
    let (t_svgf, outs) = best(5, || {
        let mut s = Svgf::new(SvgfParams::default());
        noisy.iter().map(|f| s.push_passes(f, &g, &still, &[2, 5])).collect::<Vec<_>>()
    });
    for o in outs.iter().flatten() {
        hash(&mut check, o.data.iter().map(|v| v.to_bits() as u64));
    }
    println!(
        "svgf (2 and 5 passes shown) {:.2} ms per frame ({} frames)",
        t_svgf * 1e3 / frames as f64,
        frames
    );
    let (t_adv, adv) = best(5, || {
        let mut s = Svgf::new(SvgfParams::default());
        for f in &noisy {
            s.advance(f, None, &g, &still);
        }
        s.history()
    });
    hash(&mut check, adv.data.iter().map(|v| v.to_bits() as u64));
    println!("svgf advanced (its first pass only) {:.2} ms per frame", t_adv * 1e3 / frames as f64);
    let shown: Vec<&Image> = outs.iter().map(|o| &o[0]).collect();
    let (t_m, stats) =
        best(5, || shown.iter().map(|o| metrics::measure(o, &reference, &g.coverage)).collect::<Vec<_>>());
    for s in stats {
        let s = s?;
        hash(
            &mut check,
            [s.rmse, s.bias, s.autocorr_x, s.autocorr_y, s.lowpass_rmse, s.whiteness_z, s.lowfreq_ratio]
                .into_iter()
                .map(f64::to_bits),
        );
    }
    println!("metrics::measure {:.2} ms per image", t_m * 1e3 / frames as f64);
    {
        let o = shown[shown.len() - 1];
        let err = metrics::error_image(o, &reference, &g.coverage)?;
        let (t, _) = best(20, || metrics::error_image(o, &reference, &g.coverage));
        println!("  error_image {:.2} ms", t * 1e3);
        let (t, _) = best(20, || metrics::autocorrelation(&err, &g.coverage));
        println!("  autocorrelation {:.2} ms", t * 1e3);
        let (t, _) = best(20, || metrics::lowfreq::lowpass_rmse(&err, &g.coverage, metrics::LOWPASS_SIGMA));
        println!("  lowpass_rmse {:.2} ms", t * 1e3);
        let (t, _) = best(20, || metrics::whiteness::whiteness(&err, &g.coverage));
        println!("  whiteness {:.2} ms", t * 1e3);
        let (t, _) = best(20, || metrics::lowfreq::lowfreq_ratio(&err, &g.coverage, metrics::LOWPASS_SIGMA));
        println!("  lowfreq_ratio {:.2} ms", t * 1e3);
    }
    let (t_f, maps) = best(5, || {
        shown.iter().map(|o| flip::ldr_flip_map(&reference, o, flip::DEFAULT_PPD)).collect::<Vec<_>>()
    });
    for m in &maps {
        hash(&mut check, m.data.iter().map(|v| v.to_bits() as u64));
    }
    println!("ldr_flip_map {:.2} ms per image", t_f * 1e3 / frames as f64);
    let prepared = flip::FlipReference::new(&reference, flip::DEFAULT_PPD);
    let (t_k, kmaps) = best(5, || shown.iter().map(|o| prepared.map(o)).collect::<Vec<_>>());
    assert!(
        kmaps.iter().zip(&maps).all(|(a, b)| a
            .data
            .iter()
            .zip(&b.data)
            .all(|(x, y)| x.to_bits() == y.to_bits()))
    );
    println!(
        "FlipReference::map {:.2} ms per image (the reference's half made once)",
        t_k * 1e3 / frames as f64
    );
    println!("checksum {check:016x}");
    Ok(())
}

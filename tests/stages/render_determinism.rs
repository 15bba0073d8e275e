//! The image depends only on (scene, job): bit-identical for 1 thread and for all threads, and across
//! reruns.

use hemilab::load::load_scene;
use hemilab::render::{RenderJob, RenderOutput, render};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use std::path::Path;

fn bits(o: &RenderOutput) -> (Vec<u32>, Vec<u32>, u64, u64) {
    let b = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    (b(&o.ao.data), b(&o.coverage.data), o.rays, o.occluded_rays)
}

fn render_with(threads: usize, scene: &hemilab::scene::Scene, job: &RenderJob) -> RenderOutput {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| render(scene, job, &|_| {}))
}

#[test]
fn one_thread_and_all_threads_give_identical_bits() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let all = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(1).max(2);
    for (file, res) in [("scenes/kitchen.toml", (64, 48)), ("scenes/cornell-box.toml", (48, 48))] {
        let scene = load_scene(&root.join(file)).unwrap();
        for (distribution, sequence, seed_mode) in [
            (Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Rotation),
            (Distribution::Uniform, Sequence::Random, SeedMode::Shift),
        ] {
            let job = crate::support::jobs::render_job(
                distribution,
                SamplerConfig::new(sequence, seed_mode, 16, 3).unwrap(),
                (res.0, res.1),
                scene.ao_distance,
            );
            let one = bits(&render_with(1, &scene, &job));
            assert!(one.3 > 0 && one.3 < one.2, "{file}: want some but not all rays occluded");
            assert_eq!(one, bits(&render_with(all, &scene, &job)), "{file}: 1 vs {all} threads");
            assert_eq!(one, bits(&render_with(all, &scene, &job)), "{file}: rerun");
            assert_eq!(one, bits(&render_with(3, &scene, &job)), "{file}: 3 threads");
        }
    }
}

/// The BVH's build effort (a render of few rays gets the fast build) changes the tree,
/// never the image: AO is any-hit and a primary ray takes the least (t, input index) hit.
#[test]
fn fast_and_full_bvh_builds_give_identical_bits() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for file in ["kitchen", "cornell-box", "slats", "terrain", "floating-rectangle", "atrium", "bunny"] {
        let path = root.join(format!("scenes/{file}.toml"));
        let full = load_scene(&path).unwrap();
        // One ray a pixel of a 1x1 image: far below any rule's threshold.
        let fast = hemilab::load::load_scene_for(&path, Some((1, 1)), Some(1)).unwrap();
        assert_eq!(fast.triangle_count, full.triangle_count);
        assert_ne!(fast.accel.len(), 0);
        for d in [full.ao_distance, f32::INFINITY] {
            let job = crate::support::jobs::render_job(
                Distribution::SineCosine,
                SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 8, 1).unwrap(),
                (40, 30),
                d,
            );
            let a = bits(&render_with(2, &full, &job));
            assert!(a.3 > 0, "{file}: want some rays occluded");
            assert_eq!(a, bits(&render_with(2, &fast, &job)), "{file} at d = {d}: fast vs full build");
        }
    }
}

//! The fast BVH build does not depend on the order of the mesh's triangles: a grid whose
//! quads' two halves lie far apart in the file, or whose triangles (and each triangle's corners)
//! are shuffled, gets the tree of the ordered grid, counted by its nodes, leaves, slots and surface
//! area cost, and renders the same bits; so do the kitchen and the terrain shuffled.

use glam::DVec3;
use hemilab::render::{RenderJob, RenderOutput, render};
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::tree::TreeStats;
use hemilab::scene::{Camera, Effort, Mesh, Scene, WorldCamera, file, mesh};
use std::path::Path;

/// `examples/write_grid`'s terrain, n × n quads, each quad's two triangles next to each other.
fn grid(n: u32) -> Mesh {
    let side = n + 1;
    let height =
        |x: f64, z: f64| 0.05 * ((x * 7.0).sin() + (z * 5.0).cos()) + 0.02 * (x * 31.0 + z * 17.0).sin();
    let mut positions = Vec::new();
    for j in 0..side {
        for i in 0..side {
            let (x, z) = (i as f64 / n as f64, j as f64 / n as f64);
            positions.push(DVec3::new(x, height(x, z), z));
        }
    }
    let mut indices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = j * side + i;
            let (b, c, d) = (a + 1, a + side + 1, a + side);
            indices.extend([[a, d, c], [a, c, b]]);
        }
    }
    Mesh { positions, indices, ..Mesh::default() }
}

/// A fixed pseudo-random permutation of the triangles (xorshift, Fisher-Yates), each triangle's
/// corners rotated by a pseudo-random step (the same triangle, facing the same way).
fn shuffled(mut m: Mesh, seed: u64) -> Mesh {
    let mut state = seed;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for i in (1..m.indices.len()).rev() {
        m.indices.swap(i, (next() % (i as u64 + 1)) as usize);
    }
    for t in &mut m.indices {
        t.rotate_left((next() % 3) as usize);
    }
    m
}

/// Every quad's first triangle, then every second one: a quad's halves n² places apart.
fn split(mut m: Mesh) -> Mesh {
    let (first, second): (Vec<_>, Vec<_>) = m.indices.iter().enumerate().partition(|(i, _)| i % 2 == 0);
    m.indices = first.into_iter().chain(second).map(|(_, t)| *t).collect();
    m
}

/// The scene of `mesh` with the fast build (one ray: far below the full build's threshold).
fn fast_scene(mesh: Mesh, view: WorldCamera, ao_distance: f32) -> Scene {
    let scene = Scene::new("order".into(), view, (40, 30), ao_distance, "h".into(), mesh, Some(1)).unwrap();
    assert_eq!(scene.accel.effort(), Effort::Fast);
    scene
}

fn bits(o: &RenderOutput) -> (Vec<u32>, Vec<u32>, u64, u64) {
    let b = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    (b(&o.ao.data), b(&o.coverage.data), o.rays, o.occluded_rays)
}

fn image(scene: &Scene) -> (Vec<u32>, Vec<u32>, u64, u64) {
    let job = RenderJob {
        distribution: Distribution::SineCosine,
        sampler: SamplerConfig::new(Sequence::Fibonacci, SeedMode::Shift, 16, 7).unwrap(),
        width: 40,
        height: 30,
        ao_distance: scene.ao_distance,
    };
    bits(&render(scene, &job, &|_| {}))
}

/// The bar: within 10 % on every count (the build reads no order, so they are equal).
fn assert_close(name: &str, want: TreeStats, got: TreeStats) {
    let close = |a: f64, b: f64| (a - b).abs() <= 0.1 * a;
    assert!(
        close(want.nodes as f64, got.nodes as f64)
            && close(want.leaves as f64, got.leaves as f64)
            && close(want.slots as f64, got.slots as f64)
            && close(want.sah, got.sah)
            && close(want.bytes as f64, got.bytes as f64),
        "{name}: {got:?} against the ordered mesh's {want:?}"
    );
    assert_eq!(want, got, "{name}: the same tree");
}

#[test]
fn a_grids_tree_and_image_do_not_depend_on_its_triangle_order() {
    let view = Camera::Perspective {
        eye: DVec3::new(0.5, 0.6, -0.4),
        target: DVec3::new(0.5, 0.0, 0.5),
        up: DVec3::Y,
        fov_y_deg: 50.0,
    };
    let n = 96;
    let ordered = fast_scene(grid(n), view, 0.05);
    let want = ordered.accel.tree_stats();
    // Nearly every quad is one pair, so one leaf: about one leaf per two triangles.
    let triangles = 2 * (n * n) as usize;
    assert_eq!(want.slots, triangles);
    assert!(want.leaves <= triangles * 51 / 100, "{want:?}");
    let picture = image(&ordered);
    assert!(picture.3 > 0 && picture.3 < picture.2, "want some but not all rays occluded");
    for (name, mesh) in [
        ("split", split(grid(n))),
        ("shuffled", shuffled(grid(n), 0x9e37_79b9)),
        ("reshuffled", shuffled(grid(n), 17)),
    ] {
        let scene = fast_scene(mesh, view, 0.05);
        assert_close(name, want, scene.accel.tree_stats());
        assert_eq!(picture, image(&scene), "{name}: the image");
    }
}

#[test]
fn committed_meshes_shuffled_keep_their_tree_and_image() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for name in ["kitchen", "terrain"] {
        let spec =
            file::parse(&std::fs::read_to_string(root.join(format!("scenes/{name}.toml"))).unwrap()).unwrap();
        let bytes =
            mesh::decompress(&std::fs::read(root.join(format!("scenes/{name}.obj.zst"))).unwrap()).unwrap();
        let load = || mesh::parse_obj(&bytes).unwrap();
        let ordered = fast_scene(load(), spec.camera.camera(), spec.ao_distance.0);
        let shuffled = fast_scene(shuffled(load(), 0x2545_f491), spec.camera.camera(), spec.ao_distance.0);
        assert_close(name, ordered.accel.tree_stats(), shuffled.accel.tree_stats());
        assert_eq!(image(&ordered), image(&shuffled), "{name}: the image");
    }
}

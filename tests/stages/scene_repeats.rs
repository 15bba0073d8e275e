//! Triangles that repeat another exactly (a face written 32,000 times in an OBJ, 20,000 glTF
//! instances of one mesh at one place) are given to the BVH once: the load's work is counted here,
//! not timed (it was quadratic: 8,000 faces 2 s, 32,000 14 s, in obvhs's PLOC build), and the image
//! is the single copy's, bit for bit, whatever order a repeat lists its corners in (the tree sorts
//! them).

use super::support::common::Tmp;
use super::support::gltf_ext::masked_square;
use hemilab::load::load_scene;
use hemilab::render::render;
use hemilab::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use hemilab::scene::Scene;
use hemilab::scene::gltf_write::{Doc, Node};

/// Looking straight down at the unit square [0, 1]² (z = 0) from z = 3.
const SCENE: &str = "mesh = \"m.glb\"\nresolution = [32, 24]\nao_distance = 1.0\n[camera.perspective]\n\
    eye = [0.5, 0.5, 3.0]\ntarget = [0.5, 0.5, 0.0]\nup = [0.0, 1.0, 0.0]\nfov_y_deg = 45.0\n";

fn image_bits(scene: &Scene) -> Vec<u32> {
    let job = crate::support::jobs::render_job(
        Distribution::SineCosine,
        SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 8, 1).unwrap(),
        (32, 24),
        scene.ao_distance,
    );
    let out = render(scene, &job, &|_| {});
    out.ao.data.iter().chain(&out.coverage.data).map(|v| v.to_bits()).collect()
}

#[test]
fn coincident_instances_are_built_once_and_render_as_one() {
    let t = Tmp::new("gltf-instances");
    let load = |doc: &Doc| {
        std::fs::write(t.path("m.glb"), doc.to_glb()).unwrap();
        std::fs::write(t.path("s.toml"), SCENE).unwrap();
        load_scene(&t.path("s.toml")).unwrap()
    };
    let one = masked_square();
    let mut many = masked_square();
    // 20,000 more nodes drawing the square where node 0 does (the file took over 20 s).
    many.nodes.extend((0..20_000).map(|_| Node { mesh: Some(0), ..Node::default() }));
    many.roots.extend(2..many.nodes.len());
    let (a, b) = (load(&one), load(&many));
    assert_eq!(b.triangle_count, a.triangle_count + 20_000 * 2);
    assert_eq!(b.repeated_triangles, 40_000);
    // The work: the BVH holds each distinct triangle once.
    assert_eq!(b.accel.len(), a.accel.len());
    assert_eq!(image_bits(&b), image_bits(&a));
}

#[test]
fn duplicate_obj_faces_are_built_once_and_render_as_one() {
    let t = Tmp::new("obj-repeats");
    let load = |faces: &str| {
        let obj = format!(
            "v -1 -1 0\nv 2 -1 0\nv 2 2 0\nv -1 2 0\nv 0 0 0.5\nv 1 0 0.5\nv 1 1 0.5\nf 1 2 3 4\n{faces}"
        );
        std::fs::write(t.path("m.obj"), obj).unwrap();
        std::fs::write(t.path("s.toml"), SCENE.replace("m.glb", "m.obj")).unwrap();
        load_scene(&t.path("s.toml")).unwrap()
    };
    let one = load("f 5 6 7\n");
    let many = load(&"f 5 6 7\n".repeat(32_000));
    assert_eq!((one.triangle_count, one.repeated_triangles), (3, 0));
    assert_eq!((many.triangle_count, many.repeated_triangles), (32_002, 31_999));
    // The work: the BVH is built over the 3 distinct triangles (its slots as for the single copy).
    assert_eq!(many.accel.len(), one.accel.len());
    assert_eq!(image_bits(&many), image_bits(&one));
    // The same corners in another order, or the other winding, are the same triangle to the tree.
    let turned = load("f 5 6 7\nf 6 7 5\nf 7 6 5\n");
    assert_eq!((turned.triangle_count, turned.repeated_triangles), (5, 2));
    assert_eq!(image_bits(&turned), image_bits(&one));
    // A triangle sharing two corners is not a repeat.
    let other = load("f 5 6 7\nf 5 6 1\n");
    assert_eq!(other.repeated_triangles, 0);
}

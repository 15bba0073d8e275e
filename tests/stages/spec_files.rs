//! The shipped specs parse and say what the paper's tables need.

use hemilab::sampling::{Distribution as D, SeedMode as M, Sequence as Q};
use hemilab::spec::{GroupKind, ReferenceRays, Row, parse_spec};
use std::path::Path;

fn load(name: &str) -> hemilab::spec::Spec {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments").join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    parse_spec(&text, &path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn smoke_spec_is_small() {
    let s = load("smoke.toml");
    assert_eq!(s.name, "smoke");
    assert_eq!(s.resolution, Some([32, 32]));
    assert_eq!(s.scenes.len(), 1);
    assert_eq!(s.scenes[0].name, "cornell-box");
    assert!(s.scenes[0].path.ends_with("experiments/../scenes/cornell-box.toml"));
    assert_eq!(s.groups.len(), 1);
    assert!(hemilab::plan::plan(&s).jobs.len() <= 32);
}

#[test]
fn paper_spec_has_tables_2_and_3_and_the_sweep() {
    let s = load("paper.toml");
    assert_eq!(s.name, "paper");
    assert_eq!(s.scenes[0].id, "../scenes/kitchen.toml");
    assert_eq!(s.reference.rays, ReferenceRays::Auto);
    let t2 = s.group("table2").unwrap();
    assert_eq!(t2.kind, GroupKind::Table);
    assert_eq!(t2.rays, vec![8, 16, 32]);
    assert_eq!(
        t2.rows,
        vec![
            Row::new(D::Uniform, Q::Random, M::Rotation),
            Row::new(D::Sine, Q::Random, M::Rotation),
            Row::new(D::SineCosine, Q::Random, M::Rotation),
        ]
    );
    let t3 = s.group("table3").unwrap();
    assert_eq!(t3.rays, vec![8, 16, 32]);
    assert_eq!(
        t3.rows,
        vec![
            Row::new(D::SineCosine, Q::Random, M::Rotation),
            Row::new(D::SineCosine, Q::Fibonacci, M::Rotation),
            Row::new(D::SineCosine, Q::Fibonacci, M::Static),
        ]
    );
    let c = s.group("convergence").unwrap();
    assert_eq!(c.kind, GroupKind::Convergence);
    assert_eq!(c.rays, (0..=10).map(|k| 1u32 << k).collect::<Vec<_>>());
    for row in t2.rows.iter().chain(&t3.rows) {
        assert!(c.rows.contains(row), "sweep lacks {}", row.label());
    }
    for extra in [
        Row::new(D::SineCosine, Q::Fibonacci, M::Shift),
        Row::new(D::SineCosine, Q::Stratified, M::Shift),
        Row::new(D::SineCosine, Q::Sobol, M::Shift),
        Row::new(D::SineCosine, Q::Fibonacci, M::BlueNoise),
        Row::new(D::SineCosine, Q::Random, M::BlueNoise),
    ] {
        assert!(c.rows.contains(&extra), "sweep lacks {}", extra.label());
    }
    assert!(c.rows.iter().any(|r| r.distribution == D::ConcentricCosine));
}

#[test]
fn axes_form_expands_as_a_product_with_random_shift_merged() {
    let text = r#"
scenes = ["s.toml"]
[[convergence]]
name = "c"
rays = [1, 2]
distributions = ["sine", "sine-cosine"]
sequences = ["random", "fibonacci"]
seed_modes = ["rotation", "shift"]
"#;
    let s = parse_spec(text, Path::new("x/c.toml")).unwrap();
    assert_eq!(s.name, "c");
    let rows = &s.groups[0].rows;
    assert_eq!(
        rows,
        &vec![
            Row::new(D::Sine, Q::Random, M::Rotation),
            Row::new(D::Sine, Q::Fibonacci, M::Rotation),
            Row::new(D::Sine, Q::Fibonacci, M::Shift),
            Row::new(D::SineCosine, Q::Random, M::Rotation),
            Row::new(D::SineCosine, Q::Fibonacci, M::Rotation),
            Row::new(D::SineCosine, Q::Fibonacci, M::Shift),
        ]
    );
    assert_eq!(s.groups[0].replicates, hemilab::spec::DEFAULT_REPLICATES);
}

#[test]
fn defaults_and_overrides() {
    let text = r#"
scenes = ["../scenes/a.toml", "./b.toml"]
ao_distance = "infinite"
seed = 7
replicates = 3
[reference]
rays = 2048
replicates = 8
[[table]]
name = "t"
rays = [4, 4, 8]
scenes = ["b"]
rows = [{ distribution = "sine", sequence = "random", seed_mode = "shift" }]
"#;
    let s = parse_spec(text, Path::new("exp/t.toml")).unwrap();
    assert_eq!(s.ao_distance, Some(hemilab::spec::AoDistance::Infinite));
    assert_eq!((s.seed, s.replicates), (7, 3));
    assert_eq!(s.reference.rays, ReferenceRays::Fixed(2048));
    assert_eq!(s.reference.replicates, 8);
    assert_eq!(s.reference.seed, 7);
    assert_eq!(s.reference.estimator, Row::new(D::SineCosine, Q::Fibonacci, M::Shift));
    let g = &s.groups[0];
    assert_eq!(g.rays, vec![4, 8]);
    assert_eq!(g.scenes, vec![1]);
    assert_eq!(g.replicates, 3);
    assert_eq!(g.rows, vec![Row::new(D::Sine, Q::Random, M::Rotation)]);
    assert_eq!(s.scenes[1].id, "b.toml");
    assert_eq!(s.scenes[1].path, Path::new("exp/b.toml"));
    assert_eq!(s.resolution, None);
}

#[test]
fn format_example_in_the_module_doc_parses() {
    let src = include_str!("../../src/spec/mod.rs");
    let block: String = src
        .lines()
        .skip_while(|l| !l.starts_with("//! ```toml"))
        .skip(1)
        .take_while(|l| !l.starts_with("//! ```"))
        .map(|l| format!("{}\n", l.trim_start_matches("//!").strip_prefix(' ').unwrap_or("")))
        .collect();
    assert!(block.contains("[[convergence]]"), "doc block not found");
    let s = parse_spec(&block, Path::new("experiments/paper.toml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.groups.len(), 4);
    assert_eq!(s.groups[1].rows.len(), 3, "random+shift merged into random+rotation");
    assert_eq!(s.groups[2].frames, 16, "the real-time group");
    let names: Vec<&str> = s.groups[3].scenes.iter().map(|&i| s.scenes[i].name.as_str()).collect();
    assert_eq!(names, ["kitchen", "kitchen-visibility", "kitchen-cos-lobe-8"], "the integrands group");
}

#[test]
fn blue_noise_is_a_seed_mode_in_rows_axes_and_the_reference() {
    let text = r#"
scenes = ["s.toml"]
[reference]
seed_mode = "blue-noise"
[[table]]
name = "t"
rays = [8]
rows = [{ distribution = "sine", sequence = "random", seed_mode = "blue-noise" }]
[[convergence]]
name = "c"
rays = [1, 2]
distributions = ["sine-cosine"]
sequences = ["fibonacci"]
seed_modes = ["shift", "blue-noise"]
"#;
    let s = parse_spec(text, Path::new("x/c.toml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.reference.estimator, Row::new(D::SineCosine, Q::Fibonacci, M::BlueNoise));
    // Not merged into rotation as random + shift is: the static set shifted by the mask.
    assert_eq!(s.groups[0].rows, vec![Row::new(D::Sine, Q::Random, M::BlueNoise)]);
    assert_eq!(
        s.groups[1].rows,
        vec![
            Row::new(D::SineCosine, Q::Fibonacci, M::Shift),
            Row::new(D::SineCosine, Q::Fibonacci, M::BlueNoise)
        ]
    );
}

#[test]
fn blue_noise_spec_pairs_every_sequence_with_its_per_pixel_seed() {
    let s = load("blue_noise.toml");
    let t = s.group("blue_noise").unwrap();
    assert_eq!(t.rays, vec![8, 16, 32]);
    assert!(t.replicates >= 4);
    // The sequences the blue-noise experiment was written for (the four renderer samplers, Halton, R2, ZSobol and pmj02bn, are not in it yet).
    for q in Q::all().into_iter().take(4) {
        assert!(t.rows.contains(&Row::new(D::SineCosine, q, M::BlueNoise)), "{q} blue-noise");
        let per_pixel = if q == Q::Random { M::Rotation } else { M::Shift };
        assert!(t.rows.contains(&Row::new(D::SineCosine, q, per_pixel)), "{q} {per_pixel}");
    }
}

#[test]
fn replicates_default_to_four_and_one_is_warned_about() {
    // One replicate printed "± 0.0000" everywhere without a word; the default now gives a spread.
    let path = Path::new("/tmp/hemilab-replicates.toml");
    let text = "scenes = [\"s.toml\"]\n[[table]]\nname = \"t\"\nrays = [4]\nrows = [{ distribution = \"sine\", sequence = \"random\" }]\n";
    let s = parse_spec(text, path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.replicates, hemilab::spec::DEFAULT_REPLICATES);
    assert_eq!(s.group("t").unwrap().replicates, 4);
    assert_eq!(hemilab::load::single_replicate_warning(&s), None);
    let one = parse_spec(&text.replace("rays = [4]", "rays = [4]\nreplicates = 1"), path).unwrap();
    let w = hemilab::load::single_replicate_warning(&one).expect("one replicate is warned about");
    assert!(
        w.contains("/tmp/hemilab-replicates.toml") && w.contains("(t)") && w.contains("replicates = 4"),
        "{w}"
    );
}

/// A spec's scenes get the BVH build effort of the rays it traces in them: the committed paper spec
/// (millions of rays per scene) the full build, a tiny spec over the terrain (30,000 triangles,
/// about 15,000 rays) the fast one, and a spec whose reference rays are `auto` the full one.
#[test]
fn a_specs_scenes_are_built_for_the_rays_it_traces() {
    use hemilab::scene::Effort;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let paper = hemilab::load::load(&root.join("experiments/paper.toml")).unwrap();
    assert!(paper.scenes.iter().all(|s| s.accel.effort() == Effort::Full));
    let t = crate::support::common::Tmp::new("spec-effort");
    let tiny = crate::support::common::tiny_spec(16, "").replace("cornell-box.toml", "terrain.toml");
    let spec = t.spec("tiny.toml", &tiny);
    let loaded = hemilab::load::load(&spec).unwrap();
    assert_eq!(loaded.scenes[0].accel.effort(), Effort::Fast);
    let spec = t.spec("auto.toml", &tiny.replace("rays = 16", "rays = \"auto\""));
    assert_eq!(hemilab::load::load(&spec).unwrap().scenes[0].accel.effort(), Effort::Full);
}

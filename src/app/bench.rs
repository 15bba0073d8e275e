//! `hemilab bench`: the performance figure of record (`render::bench::measure`), printed as a table
//! or as JSON.

use crate::cli::BenchArgs;
use crate::error::{Error, Result};
use crate::io;
use crate::load::scene_at;
use crate::render::RenderJob;
use crate::render::bench::RaySet;
use crate::render::bench::dump::hlrays1;
use crate::render::bench::measure::measure;
use crate::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use glam::Vec3;
use serde_json::Value;

pub fn run(args: BenchArgs) -> Result<()> {
    let (scene, width, height) = scene_at(&args.scene, args.resolution)?;
    let (distribution, sequence, seed_mode) =
        (Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Rotation);
    let sampler = SamplerConfig::new(sequence, seed_mode, args.rays, 1)
        .map_err(|e| Error::Usage(format!("--rays: {e}")))?;
    let job = RenderJob { distribution, sampler, width, height, ao_distance: scene.ao_distance };
    if let Some(path) = &args.dump_rays {
        check_dumpable(&args.scene, &scene)?;
        io::ensure_writable_file(path)?;
    }
    let mut dump = |set: &RaySet| -> Result<()> {
        let Some(path) = &args.dump_rays else { return Ok(()) };
        let tris: Vec<[Vec3; 3]> =
            scene.accel.source_triangles().iter().map(|t| [t.v0, t.v1, t.v2].map(Vec3::from)).collect();
        let bytes = hlrays1(&tris, set).map_err(|e| Error::Refused(format!("--dump-rays: {}", e.0)))?;
        io::write_atomic(path, &bytes)
    };
    let v = measure(&scene, &job, args.distances.as_deref(), args.repeats, &mut dump)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&v).unwrap_or_default());
    } else {
        print_table(&v);
    }
    Ok(())
}

/// The peers a dump is for have no alpha test: on a scene with alpha masks they would count hits
/// that hemilab's masks let through, so such a dump is refused before any work.
fn check_dumpable(path: &std::path::Path, scene: &crate::scene::Scene) -> Result<()> {
    if scene.accel.has_alpha() {
        return Err(Error::input(
            path,
            format!(
                "--dump-rays: the scene has alpha masks ({} material(s)); a dump's readers have no \
                 alpha test and would count hits the masks let through. Dump a copy of the scene \
                 whose masked materials are opaque (glTF alphaMode \"OPAQUE\", OBJ without map_d)",
                scene.masked_materials
            ),
        ));
    }
    Ok(())
}

fn print_table(v: &Value) {
    let m = |x: &Value| x.as_f64().unwrap_or(0.0) / 1e6;
    println!(
        "scene {} ({} triangles), {}x{}, {} {} rays/pixel ({} / {}), {} cores",
        v["scene"].as_str().unwrap_or(""),
        v["triangles"],
        v["resolution"][0],
        v["resolution"][1],
        v["rays_per_pixel"],
        v["distribution"].as_str().unwrap_or(""),
        v["sequence"].as_str().unwrap_or(""),
        v["seed_mode"].as_str().unwrap_or(""),
        v["cores"]
    );
    println!(
        "BVH build: hemilab (obvhs CWBVH, slow preset) {:.3} s; baseline (medium preset) {:.3} s",
        v["bvh_build_s"].as_f64().unwrap_or(0.0),
        v["obvhs_baseline_bvh_build_s"].as_f64().unwrap_or(0.0)
    );
    for key in ["single_thread", "all_threads"] {
        let r = &v[key];
        println!(
            "whole render, d = {}, {} thread(s): {:.2} M AO rays/s",
            d_text(&v["ao_distance"]),
            r["threads"],
            m(&r["rays_per_s"])
        );
    }
    println!("render speed-up: {:.2}x", v["speedup"].as_f64().unwrap_or(0.0));
    println!(
        "AO rays only, {} rays, median (min..max) of {} repeats, M rays/s:",
        v["ray_set"]["rays"], v["repeats"]
    );
    println!("{:>10} {:>7} {:>22} {:>22} {:>20}", "d", "threads", "obvhs", "hemilab", "ratio");
    let empty = Vec::new();
    for c in v["comparison"].as_array().unwrap_or(&empty) {
        for r in c["runs"].as_array().unwrap_or(&empty) {
            let f = |x: &Value, s: f64| {
                format!("{:.2} ({:.2}..{:.2})", m(&x["median"]) * s, m(&x["min"]) * s, m(&x["max"]) * s)
            };
            println!(
                "{:>10} {:>7} {:>22} {:>22} {:>20}",
                d_text(&c["ao_distance"]),
                r["threads"].to_string(),
                f(&r["obvhs_rays_per_s"], 1.0),
                f(&r["hemilab_rays_per_s"], 1.0),
                f(&r["ratio"], 1e6)
            );
        }
        println!("{:>10} mismatching rays: {}", "", mismatch_text(&c["mismatches"]));
        println!("{:>10} occluded rays: {} of {}", "", c["occluded"]["hemilab"], c["rays"]);
    }
    let p = &v["points"];
    println!(
        "points alone ({} pixels, {}, {} thread), ns per point, median (min..max) of {} repeats:",
        p["pixels"],
        p["seed_mode"].as_str().unwrap_or(""),
        p["threads"],
        v["repeats"]
    );
    for r in p["rows"].as_array().unwrap_or(&empty) {
        let ns = &r["ns_per_point"];
        let g = |k: &str| ns[k].as_f64().unwrap_or(0.0);
        println!(
            "{:>10} {:>5} points: {:.2} ({:.2}..{:.2})",
            r["sequence"].as_str().unwrap_or(""),
            r["points_per_pixel"],
            g("median"),
            g("min"),
            g("max")
        );
    }
}

/// A distance as the table prints it: the JSON number, or ∞ (the JSON says "infinite").
fn d_text(d: &Value) -> String {
    match d.as_f64() {
        Some(x) => x.to_string(),
        None => "∞".into(),
    }
}

/// `mismatching rays: 12 (obvhs_node_test_short 5, triangle_test 7)`: the categories that occurred
/// (`render::bench::Mismatches`), by their names.
fn mismatch_text(m: &Value) -> String {
    let total = m["total"].as_u64().unwrap_or(0);
    let parts: Vec<String> = m
        .as_object()
        .into_iter()
        .flatten()
        .filter(|(k, v)| *k != "total" && v.as_u64().is_some_and(|n| n > 0))
        .map(|(k, v)| format!("{k} {v}"))
        .collect();
    if parts.is_empty() { format!("{total}") } else { format!("{total} ({})", parts.join(", ")) }
}

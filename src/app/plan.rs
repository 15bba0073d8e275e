//! `hemilab plan`: the plan's size, and how long its run will take on this machine, now (the
//! calibration is `jobs::calibrate`'s).

use crate::cli::PlanArgs;
use crate::error::Result;
use crate::jobs::calibrate::{Build, adaptive_rays, builds, by_scene, calibrate, references_s};
use crate::load::load;
use crate::plan::{self, Job, Plan, cost, format_duration};
use crate::reference::store as refs;
use crate::shard::manifest as shard;
use crate::timing::clock;
use std::fmt::Write as _;

pub fn run(args: PlanArgs) -> Result<()> {
    let t0 = clock::wall_s();
    let loaded = load(&args.spec)?;
    let load_s = clock::wall_s() - t0;
    let spec = &loaded.spec;
    let full = plan::plan(spec);
    let count = args.shard.map(|s| s.count).or(args.shards);
    let selected = args.shard.map_or_else(|| full.clone(), |s| shard::select(&loaded, &full, s));
    let threads = crate::jobs::Threads::resolve(args.threads).workers;

    let ref_dir = refs::dir(args.reference_dir.as_deref(), spec);
    // Built only for the scenes and camera paths the plan uses (`calibrate::builds`).
    let builds = builds(&loaded, &full, &ref_dir)?;
    let cal = calibrate(&loaded, &full, &by_scene(&loaded, &builds), threads)?;
    let refs_s = references_s(&loaded, &cal, &builds, threads);
    let estimate = |p: &Plan| {
        cost::jobs(
            p,
            |j| cal.frame_s(&loaded, j),
            |j, frames, shown| cal.filter_s(&loaded, j, frames, shown),
            |id| cal.overhead_s(&loaded, id),
            &cal.model(&loaded, threads),
        )
    };

    let mut s = String::new();
    let what = args.shard.map_or(String::new(), |k| format!(", shard {k}"));
    let b = estimate(&selected);
    // Under `[tiles]` a job renders its tiles' windows and writes the mosaic of their interiors.
    let tiles: Vec<Option<crate::jobs::tiles::TileSet>> = (0..loaded.scenes.len())
        .map(|si| crate::jobs::tiles::of_spec(spec, si, &loaded.scenes[si]))
        .collect();
    let size = plan::estimate_with(&selected, |j| {
        let (si, sc) = loaded.scene_of(j);
        match &tiles[si] {
            Some(t) => t.rendered_pixels(),
            None => plan::Geometry::of(j.resolution, j.ao_distance, sc).pixels(),
        }
    });
    let _ = writeln!(
        s,
        "plan for {}{what}: {} jobs in {} configurations; at most {} AO rays ({:.3} G) over {} pixels",
        args.spec.display(),
        selected.jobs.len(),
        b.units,
        size.total_rays,
        size.total_rays as f64 / 1e9,
        size.pixels
    );
    let _ = writeln!(
        s,
        "timing protocol: at least {} timed renders per configuration, {} one-thread workers: {} renders",
        spec.timing.repeats, threads, b.renders
    );
    for (si, sc) in spec.scenes.iter().enumerate() {
        if !full.jobs.iter().any(|j| loaded.scene_of(j).0 == si) {
            continue;
        }
        match builds.iter().find(|b| b.scene == si && b.view.is_none()) {
            Some(b) => {
                let _ = writeln!(s, "reference '{}': must be built ({})", sc.name, how_built(&loaded, b));
            }
            None => {
                let _ = writeln!(s, "reference '{}': stored in {}, reused", sc.name, ref_dir.display());
            }
        }
        let si_of = |j: &Job| loaded.scene_of(j).0;
        let views = crate::jobs::reference::needed_views(&full, &loaded.scenes, si_of);
        let mut cameras: Vec<plan::CameraId> =
            views.iter().filter(|v| v.scene == si).map(|v| v.camera).collect();
        cameras.dedup();
        for c in cameras {
            let needed = views.iter().filter(|v| v.scene == si && v.camera == c).count();
            let built: Vec<&Build> =
                builds.iter().filter(|b| b.scene == si && b.view.is_some_and(|(bc, _)| bc == c)).collect();
            let what = match built.first() {
                None => format!("stored in {}, reused", ref_dir.display()),
                Some(b) => format!(
                    "{} must be built ({} each{}){}",
                    built.len(),
                    how_built(&loaded, b),
                    if b.views > 1 {
                        format!(", the mean of {} jittered views", b.views)
                    } else {
                        String::new()
                    },
                    if built.len() < needed {
                        format!(", the other {} stored or the scene's own", needed - built.len())
                    } else {
                        String::new()
                    }
                ),
            };
            let _ = writeln!(
                s,
                "references of camera '{}' on '{}': {needed} (a moving camera's measured frames and the frame \
                 before each): {what}",
                c.name(),
                sc.name
            );
        }
    }
    let _ =
        write!(s, "calibration on this machine ({:.2} s of rendering in {:.2} s): ", cal.cpu_s, cal.wall_s);
    let parts: Vec<String> = spec
        .scenes
        .iter()
        .zip(&cal.scenes)
        .filter_map(|(sc, c)| {
            let c = c.as_ref()?;
            let ns: Vec<f64> = c.rows.iter().map(|(_, k)| k.ns_per_ray).collect();
            let (lo, hi) =
                ns.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
            let per_image = c.rows.first().map_or(0.0, |(_, k)| k.overhead_s);
            // Each pipeline's own work per frame, on top of the frame's render.
            let filters: String = c
                .filters
                .iter()
                .map(|(p, moving, f)| {
                    let cam = if *moving { " (moving camera)" } else { "" };
                    // A history's first frames cost more (SVGF's spatial variance).
                    let first = f.first.first().map_or(String::new(), |x| format!(" {:.2} ms at first, then", x * 1e3));
                    format!(", {p}{cam} +{first} {:.2} ms per frame", f.later * 1e3)
                })
                .collect();
            Some(format!(
                "'{}' {:.1} ms per image + {:.0}–{:.0} ns per AO ray by estimator ({} estimators at {} rays){filters}",
                sc.name,
                per_image * 1e3,
                lo,
                hi,
                c.rows.len(),
                c.rays
            ))
        })
        .collect();
    let _ = writeln!(s, "{}", parts.join("; "));
    if cal.contention > 1.15 {
        let load = match (cal.now, cal.averaged) {
            (Some(n), _) => format!(", other processes' runnable threads say {n:.1}x"),
            (None, Some(a)) => format!(", the load average says {a:.1}x"),
            (None, None) => String::new(),
        };
        let _ = writeln!(
            s,
            "the machine is busy: the calibration renders took {:.1}x their CPU time in wall time{load}; the \
             estimate assumes {:.1}x for the whole run",
            cal.measured, cal.contention
        );
    }
    let total = load_s + refs_s + b.wall_s;
    let _ = writeln!(
        s,
        "estimate: ≈ {} (renders {:.1} s CPU, per-job metrics and results {:.1} s, warm-up {:.1} s, on {} workers; \
         references {}; loading {:.1} s; not counted: writing the report)",
        format_duration(total),
        b.render_cpu_s + b.overhead_cpu_s,
        b.post_cpu_s,
        b.warmup_cpu_s,
        threads,
        if refs_s > 0.0 { format_duration(refs_s) } else { "none to build".into() },
        load_s
    );
    let pixels = |j: &Job| {
        let (si, sc) = loaded.scene_of(j);
        match &tiles[si] {
            Some(t) => t.mosaic_pixels(),
            None => plan::Geometry::of(j.resolution, j.ao_distance, sc).pixels(),
        }
    };
    let jobs_bytes =
        cost::output_bytes(&selected, pixels, |j| cal.bytes_per_pixel(j), cal.post.record_bytes, true);
    let refs_bytes: f64 = builds
        .iter()
        .map(|b| {
            let [w, h] = b.manifest.image_size();
            // Three channels: the mean, its standard error, the coverage.
            w as f64 * h as f64 * cal.post.exr_bytes_per_pixel * 1.5
        })
        .sum();
    let _ = writeln!(
        s,
        "disk: ≈ {} ({} job images at {:.1} bytes per pixel for a raw frame, {:.1} for a filtered one, as \
         encoded here, and their records; references {})",
        plan::format_bytes(jobs_bytes + refs_bytes),
        selected.jobs.len(),
        cal.post.exr_bytes_per_pixel,
        cal.post.filtered_exr_bytes_per_pixel,
        if builds.is_empty() { "none to build".into() } else { plan::format_bytes(refs_bytes) }
    );
    if let Some(n) = count {
        let of = shard::partition(&loaded, &full, n);
        let _ = writeln!(
            s,
            "\n{:>7}  {:>6}  {:>14}  {:>8}  estimate",
            "shard", "jobs", "configurations", "renders"
        );
        for k in 0..n {
            let jobs: Vec<Job> =
                full.jobs.iter().zip(&of).filter(|(_, x)| **x == k).map(|(j, _)| j.clone()).collect();
            let p = Plan { jobs };
            let e = estimate(&p);
            let t = if p.jobs.is_empty() { 0.0 } else { load_s + refs_s + e.wall_s };
            let _ = writeln!(
                s,
                "{:>7}  {:>6}  {:>14}  {:>8}  ≈ {}",
                format!("{k}/{n}"),
                p.jobs.len(),
                e.units,
                e.renders,
                format_duration(t)
            );
        }
        if refs_s > 0.0 {
            let _ = writeln!(
                s,
                "(each shard's estimate includes building the references, or waiting for the shard that does; \
                 build them first with `hemilab reference` to save that)"
            );
        }
    }
    if args.jobs {
        let _ = writeln!(s, "\njobs, in run order:");
        s.push_str(&plan::format_jobs(&selected));
    } else {
        let _ = writeln!(s, "(--jobs lists the {} jobs)", selected.jobs.len());
    }
    print!("{s}");
    Ok(())
}

/// How a reference is built: "4 x 1024 rays", or an adaptive one's pilot and renders.
fn how_built(loaded: &crate::load::Loaded, b: &Build) -> String {
    let m = &b.manifest;
    match adaptive_rays(loaded, b.scene, m) {
        Some(r) => format!("adaptive: a pilot of {0} x {1} rays, then {0} x about {r}", m.replicates, m.rays),
        None => format!("{} x {} rays", m.replicates, m.rays),
    }
}

//! `hemilab plan`: the plan's size, and how long its run will take on this machine, now (the
//! calibration is `jobs::calibrate`'s).

use crate::cli::PlanArgs;
use crate::error::Result;
use crate::jobs::calibrate::{adaptive_rays, calibrate, references_s};
use crate::load::load;
use crate::plan::{self, Job, Plan, cost, format_duration};
use crate::reference::Manifest;
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
    let builds: Vec<Option<Manifest>> = (0..loaded.scenes.len())
        .map(|si| refs::missing(spec, si, &loaded.scenes[si], &ref_dir))
        .collect::<Result<_>>()?;
    let builds: Vec<Option<Manifest>> = builds
        .into_iter()
        .enumerate()
        .map(|(si, b)| b.filter(|_| full.jobs.iter().any(|j| loaded.scene_of(j).0 == si)))
        .collect();
    let cal = calibrate(&loaded, &full, &builds, threads)?;
    let refs_s = references_s(&loaded, &cal, &builds, threads);
    let estimate = |p: &Plan| {
        cost::jobs(
            p,
            |j| cal.render_s(&loaded, j),
            |id| cal.overhead_s(&loaded, id),
            &cal.model(&loaded, p.jobs.len(), threads),
        )
    };

    let mut s = String::new();
    let what = args.shard.map_or(String::new(), |k| format!(", shard {k}"));
    let b = estimate(&selected);
    let size = plan::estimate(&selected, |j| {
        let (_, sc) = loaded.scene_of(j);
        [sc.resolution.0, sc.resolution.1]
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
        match &builds[si] {
            Some(m) => {
                let how = match adaptive_rays(&loaded, si, m) {
                    Some(r) => format!(
                        "adaptive: a pilot of {0} x {1} rays, then {0} x about {r}",
                        m.replicates, m.rays
                    ),
                    None => format!("{} x {} rays", m.replicates, m.rays),
                };
                let _ = writeln!(s, "reference '{}': must be built ({how})", sc.name);
            }
            None => {
                let _ = writeln!(s, "reference '{}': stored in {}, reused", sc.name, ref_dir.display());
            }
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
            Some(format!(
                "'{}' {:.1} ms per image + {:.0}–{:.0} ns per AO ray by estimator ({} estimators at {} rays)",
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
        let load = cal.averaged.map_or(String::new(), |a| format!(", the load average says {a:.1}x"));
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

//! Pure: what a run of a plan costs under the timing protocol (`crate::timing`), given what one
//! render of each job costs on this machine (the calibration `hemilab plan` measures). The
//! protocol decides the renders: every configuration (unit) is rendered at least `repeats` times
//! (its replicates, then timing-only re-renders), each scene's no-AO-ray overhead render
//! `overhead_renders` times, and every worker warms up on each scene before its first timed render.

use super::shard;
use super::{Job, Plan};

/// The protocol and the machine's per-job costs, as the estimate needs them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Model {
    /// Timed renders per configuration at least.
    pub repeats: u32,
    /// One-thread renders side by side.
    pub workers: usize,
    /// Untimed CPU seconds per worker and scene before the first timed render.
    pub warmup_s: f64,
    /// Timed no-AO-ray renders per scene.
    pub overhead_renders: u32,
    /// CPU seconds per recorded job besides its render: metrics, EXR encoding, rewriting results.
    pub post_s: f64,
    /// Wall seconds per CPU second of a worker (1 on an idle machine, more when other work shares
    /// the cores), as measured during the calibration.
    pub contention: f64,
}

/// The predicted cost of a plan, in parts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Breakdown {
    /// Timed renders (records and timing-only re-renders), without the overhead renders.
    pub renders: usize,
    /// Configurations (timing units).
    pub units: usize,
    /// CPU seconds of those renders, of the overhead renders, of the per-job work, of warm-up.
    pub render_cpu_s: f64,
    pub overhead_cpu_s: f64,
    pub post_cpu_s: f64,
    pub warmup_cpu_s: f64,
    /// Wall seconds with `workers` workers at the measured contention.
    pub wall_s: f64,
}

/// `render_s(job)`: CPU seconds of one render of the job; `overhead_s(scene_id)`: of the scene's
/// no-AO-ray render.
pub fn jobs(
    plan: &Plan,
    render_s: impl Fn(&Job) -> f64,
    overhead_s: impl Fn(&str) -> f64,
    m: &Model,
) -> Breakdown {
    let units = shard::units(plan);
    let mut b = Breakdown { units: units.len(), ..Breakdown::default() };
    for u in &units {
        let n = u.len().max(m.repeats as usize);
        b.renders += n;
        b.render_cpu_s += n as f64 * render_s(&plan.jobs[u[0]]);
    }
    let mut scenes: Vec<&str> = plan.jobs.iter().map(|j| j.scene_id.as_str()).collect();
    scenes.sort_unstable();
    scenes.dedup();
    if b.renders == 0 {
        return b;
    }
    let workers = m.workers.clamp(1, b.renders);
    for s in &scenes {
        b.overhead_cpu_s += m.overhead_renders as f64 * overhead_s(s);
    }
    b.post_cpu_s = plan.jobs.len() as f64 * m.post_s;
    b.warmup_cpu_s = (workers * scenes.len()) as f64 * m.warmup_s;
    // Workers share the renders; each warms up on every scene itself.
    let per_worker = (b.render_cpu_s + b.overhead_cpu_s + b.post_cpu_s) / workers as f64;
    b.wall_s = (per_worker + scenes.len() as f64 * m.warmup_s) * m.contention.max(1.0);
    b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::parse_spec;
    use std::path::Path;

    fn plan_of(text: &str) -> Plan {
        super::super::plan(&parse_spec(text, Path::new("c.toml")).unwrap())
    }

    #[test]
    fn renders_follow_the_protocol() {
        // Unit (8 rays) has 4 replicates, unit (16 rays) 1 from the sweep: re-rendered to 3.
        let p = plan_of(
            r#"
scenes = ["a.toml"]
resolution = [10, 10]
replicates = 4
[[table]]
name = "t"
rays = [8]
rows = [ { distribution = "sine", sequence = "random" } ]
[[convergence]]
name = "c"
rays = [16]
replicates = 1
rows = [ { distribution = "sine", sequence = "random" } ]
"#,
        );
        let m = Model {
            repeats: 3,
            workers: 2,
            warmup_s: 0.5,
            overhead_renders: 7,
            post_s: 0.01,
            contention: 1.0,
        };
        let b = jobs(&p, |j| j.rays as f64, |_| 0.1, &m);
        assert_eq!((b.units, b.renders), (2, 7));
        assert_eq!(b.render_cpu_s, 4.0 * 8.0 + 3.0 * 16.0);
        assert!((b.overhead_cpu_s - 0.7).abs() < 1e-12);
        assert!((b.post_cpu_s - 0.05).abs() < 1e-12);
        assert_eq!(b.warmup_cpu_s, 2.0 * 0.5);
        let wall = (80.0 + 0.7 + 0.05) / 2.0 + 0.5;
        assert!((b.wall_s - wall).abs() < 1e-9, "{b:?}");
        let busy = jobs(&p, |j| j.rays as f64, |_| 0.1, &Model { contention: 2.5, ..m });
        assert!((busy.wall_s - 2.5 * wall).abs() < 1e-9);
        let one = jobs(&p, |j| j.rays as f64, |_| 0.1, &Model { workers: 1, ..m });
        assert!((one.wall_s - (80.75 + 0.5)).abs() < 1e-9);
        assert_eq!(jobs(&Plan::default(), |_| 1.0, |_| 1.0, &m), Breakdown::default());
    }
}

//! Pure: what a run of a plan costs under the timing protocol (`crate::timing`), given what one
//! render of each job costs on this machine (the calibration `hemilab plan` measures). The
//! protocol decides the renders: every configuration (unit) is rendered at least `repeats` times
//! (its replicates, then timing-only re-renders), each scene's no-AO-ray overhead render
//! `overhead_renders` times; then cheap units are topped up by the protocol's own rule
//! (`timing::top_up`); and every worker warms up on each scene before its first timed render.

use super::{Job, Plan, series, units};
use crate::timing::{self, Protocol};

/// The protocol and the machine's per-job costs, as the estimate needs them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Model {
    /// Repeats, workers, warm-up and the second round's rule.
    pub protocol: Protocol,
    /// Timed no-AO-ray renders per scene in the first round.
    pub overhead_renders: u32,
    /// CPU seconds per recorded job besides its render: metrics, EXR encoding, its journal line.
    pub post_s: f64,
    /// CPU seconds per record each time the results files are rewritten whole, which a run does
    /// at most every `rewrite_every_s` wall seconds (`outdir::Saver`): after every job, as this
    /// model once assumed, a 13,200-job real-time run would spend 900 s rewriting; it spends 40.
    pub rewrite_s: f64,
    pub rewrite_every_s: f64,
    /// Wall seconds per CPU second of a worker (1 on an idle machine, more when other work shares
    /// the cores).
    pub contention: f64,
}

impl Model {
    /// Samples of a unit of `jobs` jobs after `n` first-round renders of `t` seconds each and the
    /// second round.
    fn samples(&self, jobs: usize, n: usize, t: f64) -> usize {
        let p = &self.protocol;
        let need = timing::top_up(&[((0..jobs).collect(), vec![t; n])], p.min_total_s, p.max_repeats);
        n.max(need.first().map_or(0, |x| x.repeats as usize))
    }
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

/// `frame_s(job)`: CPU seconds of one render of the job (of one frame, for a series of frames),
/// without its pipeline's own work; `filter_s(job, frames, shown)`: of the job's pipeline over a
/// series of `frames` frames of which `shown` are shown (0 for raw); `overhead_s(scene_id)`: of the
/// scene's no-AO-ray render. A series is rendered once for all its accumulating pipelines, and each
/// of them filters every frame: the engine-noise spec's series of 16 frames feed SVGF and
/// ema0.1+atrous, each showing 5 (a forecast of one pipeline's single shown frame said 88 s of
/// renders for 147).
pub fn jobs(
    plan: &Plan,
    frame_s: impl Fn(&Job) -> f64,
    filter_s: impl Fn(&Job, usize, usize) -> f64,
    overhead_s: impl Fn(&str) -> f64,
    m: &Model,
) -> Breakdown {
    let units = units(plan);
    let mut b = Breakdown { units: units.len(), ..Breakdown::default() };
    // A series of frames is rendered once, by its leader, frame after frame (`plan::series`).
    let series = series(plan);
    let mut led: Vec<Option<usize>> = vec![None; plan.jobs.len()];
    for (k, s) in series.iter().enumerate() {
        led[s.leader] = Some(k);
    }
    for u in &units {
        let first = &plan.jobs[u[0]];
        if first.measurement.is_single_frame() {
            let t = frame_s(first) + filter_s(first, 1, 1);
            let n = m.samples(u.len(), u.len().max(m.protocol.repeats as usize), t);
            b.renders += n;
            b.render_cpu_s += n as f64 * t;
            continue;
        }
        // Each of the unit's series renders its leader's frames and feeds every pipeline of its
        // members; a multi-frame unit is not topped up (`Measurement::tops_up`), but re-rendered to
        // `repeats` like any other, for its time only (no filter).
        let mut frames = 1;
        let mut recorded = 0usize;
        for s in u.iter().filter_map(|&i| led[i]).map(|k| &series[k]) {
            let leader = &plan.jobs[s.leader];
            let n = leader.measurement.frames_rendered().len();
            frames = frames.max(n);
            recorded += 1;
            b.render_cpu_s += n as f64 * frame_s(leader);
            let mut pipelines: Vec<(crate::denoise::Pipeline, &Job, Vec<u32>)> = Vec::new();
            for j in s.members.iter().map(|&i| &plan.jobs[i]) {
                let (p, f) = (j.measurement.pipeline, j.measurement.frame);
                match pipelines.iter_mut().find(|x| x.0 == p) {
                    Some(x) if x.2.contains(&f) => {}
                    Some(x) => x.2.push(f),
                    None => pipelines.push((p, j, vec![f])),
                }
            }
            b.render_cpu_s += pipelines.iter().map(|(_, j, shown)| filter_s(j, n, shown.len())).sum::<f64>();
        }
        let n = recorded.max(m.protocol.repeats as usize);
        b.renders += n;
        b.render_cpu_s += (n - recorded) as f64 * frames as f64 * frame_s(first);
    }
    // Each scene a run loads (one per scene and integrand: `load::Loaded::scene_of`) has its own
    // overhead renders and every worker's warm-up: the integrands spec's 3 scenes are 12.
    let mut scenes: Vec<(&str, crate::sampling::Integrand)> = Vec::new();
    for j in &plan.jobs {
        let k = (j.scene_id.as_str(), j.measurement.integrand);
        if !scenes.contains(&k) {
            scenes.push(k);
        }
    }
    if b.renders == 0 {
        return b;
    }
    let workers = m.protocol.workers.clamp(1, b.renders);
    for (s, _) in &scenes {
        let t = overhead_s(s);
        b.overhead_cpu_s += m.samples(1, m.overhead_renders as usize, t) as f64 * t;
    }
    let jobs = plan.jobs.len() as f64;
    b.post_cpu_s = jobs * m.post_s;
    b.warmup_cpu_s = (workers * scenes.len()) as f64 * m.protocol.warmup_s;
    // Workers share the renders; each warms up on every scene itself.
    let wall = |b: &Breakdown| {
        let per_worker = (b.render_cpu_s + b.overhead_cpu_s + b.post_cpu_s) / workers as f64;
        (per_worker + scenes.len() as f64 * m.protocol.warmup_s) * m.contention.max(1.0)
    };
    // The results files are rewritten whole at most once per job and once per interval, on
    // average half full.
    let rewrites = if m.rewrite_every_s > 0.0 { (wall(&b) / m.rewrite_every_s).min(jobs) } else { jobs };
    b.post_cpu_s += rewrites * jobs / 2.0 * m.rewrite_s;
    b.wall_s = wall(&b);
    b
}

/// What a run of a plan writes, in bytes: one image per job (`pixels(job)` pixels at
/// `bytes_per_pixel(job)`, as the calibration encoded one like it) and its records
/// (`record_bytes` each, in results.json and results.csv); `images` false for a command that keeps
/// numbers only (advise's sweep).
pub fn output_bytes(
    plan: &Plan,
    pixels: impl Fn(&Job) -> u64,
    bytes_per_pixel: impl Fn(&Job) -> f64,
    record_bytes: f64,
    images: bool,
) -> f64 {
    let image: f64 =
        if images { plan.jobs.iter().map(|j| pixels(j) as f64 * bytes_per_pixel(j)).sum() } else { 0.0 };
    image + plan.jobs.len() as f64 * record_bytes
}

/// Largest calibration image: the paper's 160x120 is calibrated as it is run.
pub const CALIBRATION_PIXELS: u64 = 20_000;

/// The calibration image of a `w` x `h` image, and how many times more pixels the real one has.
pub fn calibration_size(w: u32, h: u32) -> (u32, u32, f64) {
    let pixels = w as u64 * h as u64;
    if pixels <= CALIBRATION_PIXELS {
        return (w, h, 1.0);
    }
    let s = (CALIBRATION_PIXELS as f64 / pixels as f64).sqrt();
    let (cw, ch) = (((w as f64 * s).floor() as u32).max(1), ((h as f64 * s).floor() as u32).max(1));
    (cw, ch, pixels as f64 / (cw as u64 * ch as u64) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::parse_spec;
    use std::path::Path;

    fn plan_of(text: &str) -> Plan {
        super::super::plan(&parse_spec(text, Path::new("c.toml")).unwrap())
    }

    /// The protocol's renders alone: one overhead render, no per-job work, an idle machine.
    fn renders_only(protocol: Protocol) -> Model {
        Model {
            protocol,
            overhead_renders: 1,
            post_s: 0.0,
            rewrite_s: 0.0,
            rewrite_every_s: 0.0,
            contention: 1.0,
        }
    }

    #[test]
    fn calibration_images_are_small_with_the_same_aspect() {
        assert_eq!(calibration_size(160, 120), (160, 120, 1.0));
        let (w, h, ratio) = calibration_size(8000, 8000);
        assert_eq!((w, h), (141, 141));
        assert!((ratio - 64e6 / (141.0 * 141.0)).abs() < 1e-9);
        let (w, h, _) = calibration_size(16384, 4096);
        assert!(
            w as u64 * h as u64 <= CALIBRATION_PIXELS && (w as f64 / h as f64 - 4.0).abs() < 0.1,
            "{w}x{h}"
        );
    }

    #[test]
    fn output_bytes_count_each_jobs_image_and_record() {
        let p = plan_of(
            r#"
scenes = ["a.toml"]
resolution = [10, 10]
replicates = 3
[[table]]
name = "t"
rays = [2, 4]
rows = [ { distribution = "sine", sequence = "random" } ]
"#,
        );
        assert_eq!(p.jobs.len(), 6);
        assert_eq!(output_bytes(&p, |_| 100, |_| 2.5, 1000.0, true), 6.0 * (250.0 + 1000.0));
        assert_eq!(output_bytes(&p, |_| 100, |_| 2.5, 1000.0, false), 6000.0);
        assert_eq!(crate::plan::format_bytes(504e6), "504 MB");
        assert_eq!(crate::plan::format_bytes(1.8e10), "18 GB");
        assert_eq!(crate::plan::format_bytes(2.34e9), "2.3 GB");
        assert_eq!(crate::plan::format_bytes(12.0), "12 bytes");
    }

    #[test]
    fn a_series_of_frames_costs_its_frames_once() {
        // Frames 1, 2, 4 and 8 of two accumulating pipelines are read from one render of 8 frames
        // per replicate: 3 replicates, 2 rays → 3 renders of 8 frames each, not 24 one-frame ones.
        let p = plan_of(
            r#"
scenes = ["a.toml"]
resolution = [10, 10]
replicates = 3
[[table]]
name = "t"
rays = [2]
distributions = ["sine"]
sequences = ["random"]
pipelines = ["mean", "ema0.1"]
frames = 8
"#,
        );
        assert!(p.jobs.len() >= 8, "{} jobs", p.jobs.len());
        let mut protocol = Protocol::new(1, 1, 1);
        protocol.warmup_s = 0.0;
        protocol.min_total_s = 100.0;
        let m = renders_only(protocol);
        let b = jobs(&p, |_| 0.5, |_, _, _| 0.0, |_| 0.0, &m);
        assert_eq!((b.units, b.renders), (1, 3), "{b:?}");
        assert!((b.render_cpu_s - 3.0 * 8.0 * 0.5).abs() < 1e-12, "{b:?}");
        // Re-rendered to the protocol's repeats like any unit, never topped up.
        let b = jobs(&p, |_| 0.5, |_, _, _| 0.0, |_| 0.0, &Model { protocol: Protocol::new(5, 1, 1), ..m });
        assert_eq!(b.renders, 5, "{b:?}");
        // Each series feeds both pipelines, each showing frames 1, 2, 4 and 8 (a filter costs 1 a
        // frame and 10 more a shown one); the 2 renders for time alone filter nothing.
        let filter = |_: &Job, frames: usize, shown: usize| frames as f64 + 10.0 * shown as f64;
        let b = jobs(&p, |_| 0.5, filter, |_| 0.0, &m);
        assert!((b.render_cpu_s - 3.0 * (8.0 * 0.5 + 2.0 * (8.0 + 40.0))).abs() < 1e-9, "{b:?}");
        let b = jobs(&p, |_| 0.5, filter, |_| 0.0, &Model { protocol: Protocol::new(5, 1, 1), ..m });
        assert!((b.render_cpu_s - 3.0 * (8.0 * 0.5 + 2.0 * 48.0) - 2.0 * 8.0 * 0.5).abs() < 1e-9, "{b:?}");
    }

    #[test]
    fn results_are_rewritten_as_often_as_a_run_rewrites_them() {
        // 6 jobs of 1 s on one worker: a rewrite every 2 s is 3 of them (of 3 records on average),
        // not one after every job; every 0 s (or less often than jobs finish) is one a job.
        let p = plan_of(
            r#"
scenes = ["a.toml"]
resolution = [10, 10]
replicates = 6
[[table]]
name = "t"
rays = [2]
rows = [ { distribution = "sine", sequence = "random" } ]
"#,
        );
        let mut protocol = Protocol::new(1, 1, 1);
        protocol.warmup_s = 0.0;
        protocol.min_total_s = 0.0;
        let m =
            Model { overhead_renders: 0, rewrite_s: 0.01, rewrite_every_s: 2.0, ..renders_only(protocol) };
        let b = jobs(&p, |_| 1.0, |_, _, _| 0.0, |_| 0.0, &m);
        assert!((b.post_cpu_s - 3.0 * 3.0 * 0.01).abs() < 1e-12, "{b:?}");
        let b = jobs(&p, |_| 1.0, |_, _, _| 0.0, |_| 0.0, &Model { rewrite_every_s: 0.0, ..m });
        assert!((b.post_cpu_s - 6.0 * 3.0 * 0.01).abs() < 1e-12, "{b:?}");
    }

    #[test]
    fn each_scene_and_integrand_is_warmed_up_by_every_worker() {
        // One scene under two integrands is two loaded scenes (`load::Loaded::scene_of`).
        let p = plan_of(
            r#"
scenes = ["a.toml"]
resolution = [10, 10]
replicates = 2
[[table]]
name = "t"
rays = [2]
distributions = ["sine"]
sequences = ["random"]
integrands = ["ao", "visibility"]
"#,
        );
        let mut protocol = Protocol::new(1, 1, 2);
        protocol.warmup_s = 0.5;
        let m = renders_only(protocol);
        let b = jobs(&p, |_| 1.0, |_, _, _| 0.0, |_| 0.25, &m);
        assert_eq!(b.warmup_cpu_s, 2.0 * 2.0 * 0.5, "{b:?}");
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
        let mut protocol = Protocol::new(3, 1, 2);
        protocol.warmup_s = 0.5;
        protocol.min_total_s = 0.25;
        protocol.max_repeats = 15;
        let m = Model { overhead_renders: 7, post_s: 0.01, ..renders_only(protocol) };
        let b = jobs(&p, |j| j.rays as f64, |_, _, _| 0.0, |_| 0.1, &m);
        assert_eq!((b.units, b.renders), (2, 7));
        assert_eq!(b.render_cpu_s, 4.0 * 8.0 + 3.0 * 16.0);
        assert!((b.overhead_cpu_s - 0.7).abs() < 1e-12);
        assert!((b.post_cpu_s - 0.05).abs() < 1e-12);
        assert_eq!(b.warmup_cpu_s, 2.0 * 0.5);
        let wall = (80.0 + 0.7 + 0.05) / 2.0 + 0.5;
        assert!((b.wall_s - wall).abs() < 1e-9, "{b:?}");
        let busy = jobs(&p, |j| j.rays as f64, |_, _, _| 0.0, |_| 0.1, &Model { contention: 2.5, ..m });
        assert!((busy.wall_s - 2.5 * wall).abs() < 1e-9);
        let one = jobs(
            &p,
            |j| j.rays as f64,
            |_, _, _| 0.0,
            |_| 0.1,
            &Model { protocol: Protocol { workers: 1, ..protocol }, ..m },
        );
        assert!((one.wall_s - (80.75 + 0.5)).abs() < 1e-9);
        assert_eq!(jobs(&Plan::default(), |_| 1.0, |_, _, _| 0.0, |_| 1.0, &m), Breakdown::default());

        // Cheap renders: the second round tops each unit up towards 0.25 s, at most 15 samples, and
        // the overhead render too: 8 ms needs 32 → 15, 16 ms needs 16 → 15, 10 ms needs 25 → 15.
        let cheap = jobs(&p, |j| j.rays as f64 * 1e-3, |_, _, _| 0.0, |_| 0.01, &m);
        assert_eq!(cheap.renders, 30);
        assert!((cheap.render_cpu_s - 15.0 * (0.008 + 0.016)).abs() < 1e-12, "{cheap:?}");
        assert!((cheap.overhead_cpu_s - 15.0 * 0.01).abs() < 1e-12, "{cheap:?}");
        // 50 ms: 4 × 0.1 s and 3 × 0.2 s are past 0.25 s already; the overhead (7 × 0.1 s) too.
        let dear = jobs(&p, |j| j.rays as f64 * 12.5e-3, |_, _, _| 0.0, |_| 0.1, &m);
        assert_eq!(dear.renders, 7);
        assert!((dear.overhead_cpu_s - 0.7).abs() < 1e-12);
    }
}

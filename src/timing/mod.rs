//! The timing protocol: how hemilab measures what a render costs, so that error can be reported
//! against run time on a shared machine without the machine's drift turning into a configuration
//! effect. `hemilab run` and `hemilab advise` time every job with it; `plan`'s estimate reuses the
//! same pieces (the schedule, the workers, [`Calibration`]).
//!
//! - **What a time is**: the CPU time of the one thread that renders the whole image (primary
//!   rays, hit points, frames, point sets, AO rays, assembling the image), read from the thread's
//!   CPU clock ([`clock`]). Not the reference, the metrics or any file IO. On a shared machine wall
//!   time also counts the time another process held the core; the thread's CPU time does not.
//! - **One thread per render**, and `workers` renders side by side (one per core by default), so
//!   the run still uses every core while each time stays a one-thread time.
//! - **Units and repeats**: a unit is what costs the same every time it is rendered — one
//!   configuration (scene, estimator, ray count); its replicates differ only in the seed. Every
//!   render of a unit is one timing sample, and a unit with fewer than `repeats` replicates is
//!   rendered again (timing only) until it has `repeats` samples. Median, min and max are kept.
//! - **Cheap units get more samples**: after that first round, a unit whose samples add up to less
//!   than `min_total_s` is rendered again until they would (by its median), up to `max_repeats`
//!   samples ([`top_up`]) — a second round, interleaved the same way. A 10 ms render is then timed
//!   about 15 times for a fraction of a second, while a 1 s render keeps its `repeats`.
//! - **Interleaved order**: pass p holds the p-th sample of every unit, in a seeded random order
//!   of its own ([`schedule`]), so slow drift (a build starting on the other core, frequency
//!   changes) lands evenly on all units instead of on whichever ran last.
//! - **Warm-up**: before its first timed render on a scene a worker renders untimed for at least
//!   `warmup_s` of CPU time (page faults, caches, branch predictors, clock ramp-up).
//! - **Overhead apart from per-ray cost**: a render with no AO rays at all (primary rays and
//!   setup) is timed as a unit of its own, interleaved like the others. A job's AO time is its
//!   median time minus that overhead; divided by its AO rays it is the marginal cost of a ray.

pub mod clock;
pub mod record;
mod workers;

pub use record::{RunTiming, SceneOverhead, SessionRecord};
pub use workers::{Time, Worker, run_queue, workers};

use serde::{Deserialize, Serialize};

/// What a time includes, as the report and `timing.json` say it.
pub const TIME_INCLUDES: &str = "the CPU time of the one thread that rendered the image: primary rays, \
    hit points, frames, point sets, warps and AO rays, and assembling the image; not the reference, the \
    metrics or any file IO";

/// Timing samples per unit unless the spec or `--timing-repeats` says otherwise.
pub const DEFAULT_REPEATS: u32 = 3;
/// Untimed CPU seconds a worker renders on a scene before its first timed render there.
pub const WARMUP_S: f64 = 0.3;
/// Timing samples of the no-AO-ray overhead render per scene, at least.
pub const OVERHEAD_REPEATS: u32 = 7;
/// Relative run-to-run scatter of a median time that no single run can see (each run is one
/// process: its memory layout, the other work on the machine). Measured: five runs of the paper
/// experiment on this project's shared 2-core machine (2026-11-23, load 4-8) gave a standard
/// deviation of ln(median time) between runs of 0.023 for the median configuration and 0.044 at
/// the 90th percentile, while a configuration's own 4 renders sometimes spread by only 1 %.
pub const RUN_TO_RUN: f64 = 0.03;
/// A unit whose samples add up to less CPU time than this gets more (see [`top_up`]).
pub const MIN_TOTAL_S: f64 = 0.25;
/// … but no more samples than this in all.
pub const MAX_REPEATS: u32 = 15;

/// The cores this process may use (1 if unknown): the one default of every thread count.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// How the renders of a run are timed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Protocol {
    /// Timing samples per unit, at least (its replicates count; re-renders make up the rest).
    pub repeats: u32,
    /// Seed of the interleaved order.
    pub seed: u64,
    /// Untimed CPU seconds per worker and scene before the first timed render.
    pub warmup_s: f64,
    /// Renders side by side, each on one thread of its own.
    pub workers: usize,
    /// Second round: units whose samples add up to less CPU time get more, up to `max_repeats`.
    pub min_total_s: f64,
    pub max_repeats: u32,
    /// Threads per timed render (always 1: see the module notes).
    pub threads_per_render: usize,
}

impl Protocol {
    pub fn new(repeats: u32, seed: u64, workers: usize) -> Self {
        let repeats = repeats.max(1);
        Self {
            repeats,
            seed,
            warmup_s: WARMUP_S,
            workers: workers.max(1),
            min_total_s: MIN_TOTAL_S,
            max_repeats: MAX_REPEATS.max(repeats),
            threads_per_render: 1,
        }
    }
}

/// Median, min and max of a unit's timing samples, in seconds, and the median's distribution-free
/// 95 % confidence interval (`stats::median_interval`; min..max when there are too few samples).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub median: f64,
    pub min: f64,
    pub max: f64,
    /// Samples.
    pub n: usize,
    pub ci_low: f64,
    pub ci_high: f64,
}

impl Summary {
    /// `None` when there is no finite sample.
    pub fn of(samples: &[f64]) -> Option<Self> {
        let v: Vec<f64> = samples.iter().copied().filter(|x| x.is_finite()).collect();
        if v.is_empty() {
            return None;
        }
        let min = v.iter().copied().fold(f64::INFINITY, f64::min);
        let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let (ci_low, ci_high, _) = crate::stats::median_interval(&v, 0.95);
        Some(Self { median: crate::stats::median(&v), min, max, n: v.len(), ci_low, ci_high })
    }

    /// The spread the report puts on a time: half the width of the median's confidence interval
    /// (unlike half the range it shrinks as samples are added, and one slow outlier does not set
    /// it), combined in quadrature with the run-to-run scatter [`RUN_TO_RUN`] × median.
    pub fn spread(&self) -> f64 {
        (0.5 * (self.ci_high - self.ci_low)).hypot(RUN_TO_RUN * self.median)
    }
}

/// A render's time split into the per-image overhead and the part that scales with AO rays.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Split {
    /// Median time of the scene's no-AO-ray render.
    pub overhead_s: f64,
    /// The unit's median time minus the overhead: the AO rays' share (point sets, warps, tracing).
    pub ao_time_s: f64,
    /// `ao_time_s` per AO ray cast, in nanoseconds: the marginal cost of a ray.
    pub ns_per_ray: f64,
}

impl Split {
    /// NaN parts where the overhead is unknown or the AO time is not positive (then the time is
    /// too short against the overhead's own noise to split).
    pub fn of(median_s: f64, overhead_s: f64, rays_cast: u64) -> Self {
        let ao = median_s - overhead_s;
        let ao_time_s = if ao > 0.0 && ao.is_finite() { ao } else { f64::NAN };
        let ns_per_ray = if rays_cast > 0 { 1e9 * ao_time_s / rays_cast as f64 } else { f64::NAN };
        Self { overhead_s, ao_time_s, ns_per_ray }
    }
}

/// What one unit still needs measured.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Need {
    /// Jobs never rendered: each is rendered once for its image and timed (`Slot::record`).
    pub fresh: Vec<usize>,
    /// Jobs rendered before (a resumed run, or the overhead render): re-rendered for timing only.
    pub again: Vec<usize>,
    /// Timing samples already measured.
    pub have: usize,
    /// Timing samples wanted in all.
    pub repeats: u32,
}

/// One render of the schedule.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Slot {
    /// Index into the `needs` the schedule was made from.
    pub unit: usize,
    /// The caller's job id.
    pub job: usize,
    /// First render of a fresh job: keep its image. Otherwise the render is for its time only.
    pub record: bool,
}

/// The renders that give every unit its fresh jobs and at least its `repeats` timing samples, in
/// passes: pass p holds the p-th render of every unit that needs one, shuffled by `seed` (a
/// different order each pass). Deterministic: the same needs and seed give the same schedule.
pub fn schedule(needs: &[Need], seed: u64) -> Vec<Slot> {
    let mut per_unit: Vec<Vec<Slot>> = Vec::with_capacity(needs.len());
    for (unit, n) in needs.iter().enumerate() {
        let count = n.fresh.len().max((n.repeats as usize).saturating_sub(n.have));
        let all: Vec<usize> = n.again.iter().chain(&n.fresh).copied().collect();
        let mut slots: Vec<Slot> = n.fresh.iter().map(|&job| Slot { unit, job, record: true }).collect();
        if !all.is_empty() {
            for i in slots.len()..count {
                slots.push(Slot { unit, job: all[i % all.len()], record: false });
            }
        }
        per_unit.push(slots);
    }
    let passes = per_unit.iter().map(Vec::len).max().unwrap_or(0);
    let mut out = Vec::with_capacity(per_unit.iter().map(Vec::len).sum());
    for p in 0..passes {
        let mut pass: Vec<Slot> = per_unit.iter().filter_map(|s| s.get(p).copied()).collect();
        shuffle(&mut pass, mix(seed ^ mix(p as u64 + 1)));
        out.extend(pass);
    }
    out
}

/// The second round's needs: for each unit (its jobs and the samples it has), enough further
/// renders that its samples would add up to `min_total_s` at its median time, at most
/// `max_samples` in all; units already there need nothing.
pub fn top_up(units: &[(Vec<usize>, Vec<f64>)], min_total_s: f64, max_samples: u32) -> Vec<Need> {
    units
        .iter()
        .map(|(jobs, samples)| {
            let total: f64 = samples.iter().filter(|x| x.is_finite()).sum();
            let median = crate::stats::median(samples);
            let want = if total < min_total_s && median > 0.0 {
                ((min_total_s / median).ceil() as u32).min(max_samples)
            } else {
                0
            };
            Need { fresh: vec![], again: jobs.clone(), have: samples.len(), repeats: want }
        })
        .collect()
}

/// SplitMix64's finalizer.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Fisher–Yates with a SplitMix64 stream: fixed forever, unlike a library RNG's output.
fn shuffle<T>(v: &mut [T], seed: u64) {
    let mut state = seed;
    for i in (1..v.len()).rev() {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let r = mix(state);
        // Multiply-shift: an unbiased-enough index in 0..=i for lists far below 2^32.
        let j = ((r >> 32) * (i as u64 + 1)) >> 32;
        v.swap(i, j as usize);
    }
}

/// Per-image overhead and per-ray cost of a scene at one image size, fitted as
/// time = overhead + cost · AO rays through the units' median times (weights 1/time², so every
/// ray count counts alike in relative terms), with 95 % intervals. What `plan` needs to predict a
/// run's time, and what the report shows per estimator.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Calibration {
    pub overhead_s: f64,
    pub overhead_interval: Option<(f64, f64)>,
    pub ns_per_ray: f64,
    pub ns_per_ray_interval: Option<(f64, f64)>,
    /// Units in the fit.
    pub points: usize,
}

impl Calibration {
    /// From (AO rays cast, median seconds) per unit; `None` with fewer than two distinct ray counts.
    pub fn fit(points: &[(u64, f64)]) -> Option<Self> {
        let xs: Vec<f64> = points.iter().map(|p| p.0 as f64).collect();
        let ys: Vec<f64> = points.iter().map(|p| p.1).collect();
        let ws: Vec<f64> = ys.iter().map(|t| if *t > 0.0 { 1.0 / (t * t) } else { 0.0 }).collect();
        let f = crate::stats::linear_fit(&xs, &ys, Some(&ws))?;
        let ns = |(a, b): (f64, f64)| (a * 1e9, b * 1e9);
        Some(Self {
            overhead_s: f.intercept,
            overhead_interval: f.intercept_interval(0.95),
            ns_per_ray: f.slope * 1e9,
            ns_per_ray_interval: f.slope_interval(0.95).map(ns),
            points: f.n,
        })
    }

    /// Predicted render time of an image with `rays_cast` AO rays.
    pub fn predict(&self, rays_cast: u64) -> f64 {
        self.overhead_s + self.ns_per_ray * 1e-9 * rays_cast as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn needs() -> Vec<Need> {
        vec![
            Need { fresh: vec![0, 1, 2, 3], repeats: 3, ..Need::default() },
            Need { fresh: vec![4], repeats: 3, ..Need::default() },
            Need { fresh: vec![], again: vec![9], have: 0, repeats: 3 },
            Need { fresh: vec![5], again: vec![6], have: 1, repeats: 3 },
            Need { fresh: vec![], again: vec![7, 8], have: 3, repeats: 3 },
        ]
    }

    #[test]
    fn schedule_renders_every_fresh_job_once_and_reaches_the_repeats() {
        let s = schedule(&needs(), 1);
        let count = |u: usize| s.iter().filter(|x| x.unit == u).count();
        assert_eq!([count(0), count(1), count(2), count(3), count(4)], [4, 3, 3, 2, 0]);
        for job in [0, 1, 2, 3, 4, 5] {
            assert_eq!(s.iter().filter(|x| x.job == job && x.record).count(), 1, "job {job}");
        }
        assert!(s.iter().filter(|x| x.unit == 2).all(|x| x.job == 9 && !x.record));
        // Unit 1 has one replicate: it is rendered again, timing only.
        let u1: Vec<(usize, bool)> = s.iter().filter(|x| x.unit == 1).map(|x| (x.job, x.record)).collect();
        assert_eq!(u1, [(4, true), (4, false), (4, false)]);
        // Unit 3 has one sample from before: its fresh job and one re-render make three.
        assert_eq!(s.iter().filter(|x| x.unit == 3 && !x.record).count(), 1);
    }

    #[test]
    fn schedule_is_interleaved_in_passes_and_seeded() {
        let many: Vec<Need> =
            (0..40).map(|u| Need { fresh: vec![2 * u, 2 * u + 1], repeats: 3, ..Need::default() }).collect();
        let s = schedule(&many, 7);
        assert_eq!(s.len(), 120);
        // Every unit's k-th render comes before any unit's (k+1)-th.
        let mut seen = vec![0usize; 40];
        let mut pass_of = Vec::new();
        for x in &s {
            pass_of.push(seen[x.unit]);
            seen[x.unit] += 1;
        }
        assert!(pass_of.windows(2).all(|w| w[0] <= w[1]), "passes in order");
        assert_eq!(schedule(&many, 7), s, "same seed, same order");
        assert_ne!(schedule(&many, 8), s, "another seed, another order");
        let first: Vec<usize> = s[..40].iter().map(|x| x.unit).collect();
        let second: Vec<usize> = s[40..80].iter().map(|x| x.unit).collect();
        assert_ne!(first, second, "each pass has its own order");
        assert_ne!(first, (0..40).collect::<Vec<_>>(), "not plan order");
    }

    #[test]
    fn top_up_gives_cheap_units_more_samples() {
        let units = vec![
            (vec![0, 1], vec![0.01, 0.012, 0.011]), // 33 ms in all: 23 samples wanted, 15 at most
            (vec![2], vec![0.05, 0.06, 0.05]),      // 160 ms: 5 samples
            (vec![3], vec![0.5, 0.5, 0.5]),         // already 1.5 s
        ];
        let needs = top_up(&units, 0.25, 15);
        assert_eq!(needs.iter().map(|n| n.repeats).collect::<Vec<_>>(), [15, 5, 0]);
        let s = schedule(&needs, 3);
        let count = |u: usize| s.iter().filter(|x| x.unit == u).count();
        assert_eq!([count(0), count(1), count(2)], [12, 2, 0]);
        assert!(s.iter().all(|x| !x.record), "timing only");
        assert!(s.iter().filter(|x| x.unit == 0).any(|x| x.job == 0) && s.iter().any(|x| x.job == 1));
    }

    #[test]
    fn summaries_splits_and_calibration() {
        let s = Summary::of(&[0.3, 0.1, f64::NAN, 0.2, 0.5]).unwrap();
        assert_eq!((s.median, s.min, s.max, s.n), (0.25, 0.1, 0.5, 4));
        let expect = 0.2f64.hypot(RUN_TO_RUN * 0.25);
        assert!((s.spread() - expect).abs() < 1e-15, "four samples: the interval is min..max");
        let many: Vec<f64> = (0..15).map(|i| 1.0 + 0.01 * i as f64).chain([9.0]).collect();
        let s = Summary::of(&many).unwrap();
        assert!(s.max == 9.0 && s.spread() < 0.07, "an outlier sets the max, not the spread: {s:?}");
        let same = Summary::of(&[0.5; 9]).unwrap();
        assert!(
            (same.spread() - RUN_TO_RUN * 0.5).abs() < 1e-15,
            "identical renders still carry the run-to-run term"
        );
        assert!(Summary::of(&[]).is_none());
        let sp = Split::of(0.011, 0.009, 1000);
        assert!((sp.ao_time_s - 0.002).abs() < 1e-15 && (sp.ns_per_ray - 2000.0).abs() < 1e-6);
        assert!(Split::of(0.008, 0.009, 1000).ao_time_s.is_nan(), "time below the overhead: no split");
        // time = 9 ms + 50 ns/ray, exactly.
        let pts: Vec<(u64, f64)> =
            [0u64, 19_200, 76_800, 1_228_800].iter().map(|&r| (r, 0.009 + 50e-9 * r as f64)).collect();
        let c = Calibration::fit(&pts).unwrap();
        assert!((c.overhead_s - 0.009).abs() < 1e-12 && (c.ns_per_ray - 50.0).abs() < 1e-6, "{c:?}");
        assert!((c.predict(100_000) - 0.014).abs() < 1e-12);
        assert!(Calibration::fit(&pts[..1]).is_none());
    }
}

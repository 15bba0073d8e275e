//! The real-time verdicts, as plain data (`report::run::realtime` words them): the records of a
//! spec's `frames`/`pipelines`/`schedules` groups (`JobResult::is_single_frame` false, plus the raw
//! frame-1 records beside them) read as two questions. (1) After each pipeline, at its last
//! measured frame, does the paper's sine-cosine × Fibonacci × per-pixel seed (independent schedule)
//! still have the least error of every configuration measured with it? (2) Under the accumulating
//! pipelines, does spatiotemporal blue noise (Wolfe, Morrical & Ramamoorthi 2022) beat the 2-D
//! blue-noise mask drawn afresh each frame (the same sequence, the independent schedule), as its
//! paper reports for AO? And, at the fewest rays per frame, the noise each seed mode leaves.
//!
//! Both are read on the RMSE against the reference (what the user sees) and on its noise part,
//! measured from the replicates (`JobResult::noise_rmse`, `metrics::replicates`): per replicate
//! √max(RMSE² − bias², 0), whose mean square over the replicates is exactly the configuration's
//! noise² (bias² + noise² is the mean MSE), so the same paired margin applies. A margin is the
//! paired difference over replicates (`margin::paired`), relative to the paper's (or blue noise's)
//! mean; a verdict is called only beyond Student's t at [`ALPHA`] two-sided, else a tie. The "best
//! other" is the least mean of many, so its margin is biased towards it (the winner's curse): a tie
//! there is a tie.
//!
//! An RMSE verdict is no win where it is the two sides' biases at work, not their noise: when the
//! RMSE margin is within the difference of their biases (`bias_rmse`) and their noise parts rank
//! the other way, the cell is a **bias interaction** (one side's systematic error offsetting the
//! filter's, e.g. a rotation's fixed elevations against SVGF's brightening); and where either
//! side's mean RMSE is below the pipeline's floor (its bias on per-pixel-unbiased input,
//! `JobResult::floor`) it is **below floor**. Configurations are typed (`Config`), never read back
//! from their labels. Records made before the split (no `bias_rmse`) are read as they were: their
//! noise RMSE is the joint application's, per replicate.

use crate::compare::margin::{self, Margin};
use crate::compare::model::Estimate;
use crate::results::JobResult;
use crate::sampling::{Distribution, Schedule, SeedMode, Sequence};
use crate::stats::mean_and_standard_error;
use std::collections::BTreeMap;
use std::fmt;

/// Two-sided level of a real-time verdict: a sweep of many cells at few replicates each, read as
/// a screen (how often the paper's configuration wins), not as the paper's claims (1 %, `claims`).
pub const ALPHA: f64 = 0.05;

/// One estimator of a real-time cell: distribution, sequence, seed mode and schedule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub struct Config {
    pub distribution: Distribution,
    pub sequence: Sequence,
    pub seed_mode: SeedMode,
    pub schedule: Schedule,
}

impl Config {
    /// The paper's configuration: sine-cosine × Fibonacci × per-pixel seed, independent schedule.
    pub const PAPER: Config = Config {
        distribution: Distribution::SineCosine,
        sequence: Sequence::Fibonacci,
        seed_mode: SeedMode::Rotation,
        schedule: Schedule::Independent,
    };

    fn of(r: &JobResult) -> Option<Self> {
        let (row, schedule) = r.estimator()?;
        Some(Config {
            distribution: row.distribution,
            sequence: row.sequence,
            seed_mode: row.seed_mode,
            schedule,
        })
    }

    /// The same estimator under another seed mode and the independent schedule.
    fn with_mode(self, seed_mode: SeedMode) -> Self {
        Config { seed_mode, schedule: Schedule::Independent, ..self }
    }

    /// Everything but the schedule: the paper's under another schedule is still the paper's.
    fn estimator(self) -> (Distribution, Sequence, SeedMode) {
        (self.distribution, self.sequence, self.seed_mode)
    }

    /// "sine-cosine/fibonacci": what the mask questions hold fixed.
    pub fn prefix(self) -> String {
        format!("{}/{}", self.distribution.name(), self.sequence.name())
    }
}

impl fmt::Display for Config {
    /// "sine-cosine/fibonacci/rotation/independent".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}/{}", self.prefix(), self.seed_mode.name(), self.schedule.name())
    }
}

/// The paper's configuration as the cells label it.
pub fn paper_label() -> String {
    Config::PAPER.to_string()
}

/// One record's errors: its replicate, RMSE, the noise part of it (per replicate, module doc),
/// and the configuration's bias, noise and the place's floor.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Measured {
    replicate: u32,
    rmse: f64,
    noise: f64,
    bias_rmse: f64,
    bias_se: f64,
    noise_rmse: f64,
    floor: f64,
}

/// Where a cell is: scene, rays per frame, camera path, the user's denoiser (empty: none),
/// pipeline (as results name it) and frame; whether the pipeline accumulates and whether it is
/// raw, from the record's typed measurement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct At<'a> {
    scene: &'a str,
    rays: u32,
    camera: &'a str,
    denoiser: &'a str,
    pipeline: &'a str,
    frame: u32,
    temporal: bool,
    raw: bool,
}

impl At<'_> {
    /// The same place at another frame.
    fn same_run(&self, o: &At) -> bool {
        (self.scene, self.rays, self.camera, self.denoiser, self.pipeline)
            == (o.scene, o.rays, o.camera, o.denoiser, o.pipeline)
    }
}

/// A cell's place as the verdicts carry it.
#[derive(Debug, Clone, PartialEq)]
pub struct Place {
    pub scene: String,
    pub rays: u32,
    pub camera: String,
    pub denoiser: String,
    pub pipeline: String,
    pub frame: u32,
    /// The pipeline's floor (`JobResult::floor`: its bias on per-pixel-unbiased input) here.
    pub floor: f64,
}

impl Place {
    fn of(at: &At, floor: f64) -> Self {
        Place {
            scene: at.scene.into(),
            rays: at.rays,
            camera: at.camera.into(),
            denoiser: at.denoiser.into(),
            pipeline: at.pipeline.into(),
            frame: at.frame,
            floor,
        }
    }

    /// "svgf (frame 64)", with the camera unless static and the denoiser if any.
    pub fn pipeline_text(&self) -> String {
        let mut s = self.pipeline.clone();
        if !self.denoiser.is_empty() {
            s = format!("{s} + {}", self.denoiser);
        }
        format!("{s} (frame {})", self.frame)
    }
}

/// (place) → configuration → its replicates, in replicate order.
type Cells<'a> = BTreeMap<At<'a>, BTreeMap<Config, Vec<Measured>>>;

fn cells(results: &[JobResult]) -> Cells<'_> {
    let mut out: Cells = BTreeMap::new();
    for r in results {
        let (Some(config), Some(m)) = (Config::of(r), r.measurement()) else { continue };
        let at = At {
            scene: &r.scene,
            rays: r.rays,
            camera: &r.camera,
            denoiser: &r.denoiser,
            pipeline: &r.pipeline,
            frame: r.frame,
            temporal: m.pipeline.is_temporal(),
            raw: m.pipeline == crate::denoise::Pipeline::RAW,
        };
        // Records made before the split from replicates carry the joint application's noise RMSE
        // (against the reference under the noisy frames' weights) per replicate: read as it was.
        let noise = if r.bias_rmse.is_finite() {
            (r.rmse * r.rmse - r.bias_rmse * r.bias_rmse).max(0.0).sqrt()
        } else {
            r.noise_rmse
        };
        out.entry(at).or_default().entry(config).or_default().push(Measured {
            replicate: r.replicate,
            rmse: r.rmse,
            noise,
            bias_rmse: r.bias_rmse,
            bias_se: r.bias_se,
            noise_rmse: r.noise_rmse,
            floor: r.floor.unwrap_or(f64::NAN),
        });
    }
    for configs in out.values_mut() {
        configs.values_mut().for_each(|v| v.sort_by_key(|m| m.replicate));
    }
    out
}

/// Whether the spec measured anything real-time (more than one frame, schedule or pipeline).
pub fn any(results: &[JobResult]) -> bool {
    results.iter().any(|r| !r.is_single_frame())
}

/// Which error a margin is of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Of {
    Rmse,
    Noise,
}

fn keyed(v: &[Measured], of: Of) -> Vec<(u32, f64)> {
    v.iter().map(|m| (m.replicate, if of == Of::Rmse { m.rmse } else { m.noise })).collect()
}

/// A configuration's mean error over its replicates and that mean's standard error (∞ for one).
fn estimate(v: &[Measured], of: Of) -> Estimate {
    let (value, se) = mean_and_standard_error(&keyed(v, of).into_iter().map(|x| x.1).collect::<Vec<_>>());
    Estimate { value, se }
}

fn mean_rmse(v: &[Measured]) -> f64 {
    v.iter().map(|m| m.rmse).sum::<f64>() / v.len() as f64
}

/// A configuration's split (`JobResult::bias_rmse`, `noise_rmse`): the same in each replicate's
/// record; NaN where not measured (one replicate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parts {
    /// The bias and its standard error.
    pub bias: Estimate,
    pub noise: f64,
}

impl Parts {
    fn of(v: &[Measured]) -> Self {
        // A record made before the split has no bias: its noise RMSE is another measure.
        let m = v.first().copied().filter(|m| m.bias_rmse.is_finite());
        Parts {
            bias: Estimate {
                value: m.map_or(f64::NAN, |m| m.bias_rmse),
                se: m.map_or(f64::NAN, |m| m.bias_se),
            },
            noise: m.map_or(f64::NAN, |m| m.noise_rmse),
        }
    }
}

/// The cell's floor (the same for every configuration of one place; NaN if none was measured).
fn floor_of(configs: &BTreeMap<Config, Vec<Measured>>) -> f64 {
    configs.values().flatten().map(|m| m.floor).find(|f| f.is_finite()).unwrap_or(f64::NAN)
}

/// Whether either mean RMSE is below the floor: the filter's bias cancelling a sampler's, so the
/// cell's RMSE verdict is no win (`report` says so beside it).
fn below(floor: f64, means: &[f64]) -> bool {
    floor.is_finite() && floor > 0.0 && means.iter().any(|&m| m < floor)
}

/// `b` against `a`: the paired margin b − a (`relative()` to a's mean) and its verdict at
/// [`ALPHA`]: +1 when b has significantly more error (a wins), −1 less (b wins), 0 a tie (or
/// fewer than two pairs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Versus {
    pub margin: Margin,
    pub sign: i32,
}

impl Versus {
    fn of(a: &[Measured], b: &[Measured], of: Of) -> Self {
        let margin = margin::paired(&keyed(a, of), &keyed(b, of));
        Self { margin, sign: margin.sign(ALPHA) }
    }
}

/// Whether `rmse` (b against a) is a bias interaction (module doc): a verdict whose margin is
/// within the difference of the two biases while the noise parts rank the other way.
fn interaction(a: &[Measured], b: &[Measured], rmse: &Versus) -> bool {
    let (pa, pb) = (Parts::of(a), Parts::of(b));
    let d_bias = (pb.bias.value - pa.bias.value).abs();
    let d_noise = pb.noise - pa.noise;
    rmse.sign != 0 && rmse.margin.mean.abs() <= d_bias && d_noise * rmse.margin.mean < 0.0
}

/// Question (1) in one cell: a pipeline at its last frame, for one scene and rays per frame.
#[derive(Debug, Clone, PartialEq)]
pub struct PaperCell {
    pub place: Place,
    /// The paper's or the best other's mean RMSE is below the floor (`Place::floor`).
    pub below_floor: bool,
    /// The RMSE verdict is the two sides' biases at work (module doc): no win.
    pub bias_interaction: bool,
    /// One ray per pixel per frame: a lattice of one point is one point, so the sequence axis
    /// (Fibonacci or pseudo-random) says nothing here; only the distribution and seed mode do.
    pub degenerate: bool,
    /// The paper's RMSE, and the other estimator of least mean RMSE with its RMSE.
    pub paper: Estimate,
    pub best: Config,
    pub best_rmse: Estimate,
    /// Their bias and noise parts.
    pub paper_parts: Parts,
    pub best_parts: Parts,
    /// The best other against the paper (positive: the paper's has less error), on the RMSE and
    /// on the noise part.
    pub rmse: Versus,
    pub noise: Versus,
}

/// Question (1): one cell per (scene, rays, pipeline at its last frame) where the paper's
/// configuration was measured; `None` when the spec measured nothing real-time.
pub fn paper_cells(results: &[JobResult]) -> Option<Vec<PaperCell>> {
    if !any(results) {
        return None;
    }
    let cells = cells(results);
    let last = |at: &At| cells.keys().filter(|k| k.same_run(at)).map(|k| k.frame).max();
    let mut out = Vec::new();
    for (at, configs) in &cells {
        if Some(at.frame) != last(at) {
            continue;
        }
        let Some(paper) = configs.get(&Config::PAPER) else { continue };
        // Other estimators only: the paper's under another schedule is still the paper's (and at
        // frame 1 the very same image).
        let others = configs.iter().filter(|(c, _)| c.estimator() != Config::PAPER.estimator());
        let Some((best, b)) = others.min_by(|x, y| mean_rmse(x.1).total_cmp(&mean_rmse(y.1))) else {
            continue;
        };
        let floor = floor_of(configs);
        let rmse = Versus::of(paper, b, Of::Rmse);
        out.push(PaperCell {
            place: Place::of(at, floor),
            below_floor: below(floor, &[mean_rmse(paper), mean_rmse(b)]),
            bias_interaction: interaction(paper, b, &rmse),
            degenerate: at.rays == 1,
            paper: estimate(paper, Of::Rmse),
            best: *best,
            best_rmse: estimate(b, Of::Rmse),
            paper_parts: Parts::of(paper),
            best_parts: Parts::of(b),
            rmse,
            noise: Versus::of(paper, b, Of::Noise),
        });
    }
    Some(out)
}

/// Question (2) in one cell: stbn against per-frame-independent blue noise of one distribution and
/// sequence (`prefix`, `distribution/sequence`) under an accumulating pipeline at its last frame.
#[derive(Debug, Clone, PartialEq)]
pub struct StbnCell {
    pub place: Place,
    /// Either mask's mean RMSE is below the floor.
    pub below_floor: bool,
    /// The RMSE verdict is the two sides' biases at work: no win.
    pub bias_interaction: bool,
    pub prefix: String,
    /// RMSE with `blue-noise` and with `stbn`.
    pub blue_noise: Estimate,
    pub stbn: Estimate,
    /// stbn against blue noise (negative: stbn has less error).
    pub rmse: Versus,
    pub noise: Versus,
}

/// Question (2): every accumulating pipeline at its last frame, per (scene, rays, distribution and
/// sequence) measured with both masks.
pub fn stbn_cells(results: &[JobResult]) -> Vec<StbnCell> {
    let cells = cells(results);
    let mut out = Vec::new();
    for (at, configs) in &cells {
        if !at.temporal {
            continue;
        }
        if cells.keys().any(|k| k.same_run(at) && k.frame > at.frame) {
            continue;
        }
        let floor = floor_of(configs);
        for (config, bn) in configs {
            if config.seed_mode != SeedMode::BlueNoise || config.schedule != Schedule::Independent {
                continue;
            }
            let Some(st) = configs.get(&config.with_mode(SeedMode::Stbn)) else { continue };
            let rmse = Versus::of(bn, st, Of::Rmse);
            out.push(StbnCell {
                place: Place::of(at, floor),
                below_floor: below(floor, &[mean_rmse(bn), mean_rmse(st)]),
                bias_interaction: interaction(bn, st, &rmse),
                prefix: config.prefix(),
                blue_noise: estimate(bn, Of::Rmse),
                stbn: estimate(st, Of::Rmse),
                rmse,
                noise: Versus::of(bn, st, Of::Noise),
            });
        }
    }
    out
}

/// The noise each seed mode leaves after accumulation, for one distribution and sequence.
#[derive(Debug, Clone, PartialEq)]
pub struct SeedsCell {
    pub place: Place,
    pub prefix: String,
    /// The noise part with a per-pixel rotation, the 2-D blue-noise offsets and stbn.
    pub rotation: Estimate,
    pub blue_noise: Estimate,
    pub stbn: Estimate,
    /// Their bias parts.
    pub bias: [Estimate; 3],
    /// Blue noise against rotation, on the noise part.
    pub blue_noise_vs_rotation: Margin,
}

/// At the fewest rays per frame (returned with the cells), under every accumulating pipeline at
/// its last frame: the noise and bias parts of each sequence with a per-pixel rotation, the 2-D
/// blue-noise offsets and spatiotemporal blue noise (independent schedule). A rotation leaves a
/// lattice's elevations where they are, so with one or two points per pixel no number of frames
/// moves them: its accumulated image keeps a bias that an offset, new each frame, averages away.
/// `None` when nothing but raw frames was measured.
pub fn seeds_cells(results: &[JobResult]) -> Option<(u32, Vec<SeedsCell>)> {
    let cells = cells(results);
    let fewest = cells.keys().filter(|k| !k.raw).map(|k| k.rays).min()?;
    let mut out = Vec::new();
    for (at, configs) in &cells {
        if at.rays != fewest || !at.temporal {
            continue;
        }
        if cells.keys().any(|k| k.same_run(at) && k.frame > at.frame) {
            continue;
        }
        for (config, rot) in configs {
            if config.seed_mode != SeedMode::Rotation || config.schedule != Schedule::Independent {
                continue;
            }
            let get = |mode| configs.get(&config.with_mode(mode));
            let (Some(bn), Some(st)) = (get(SeedMode::BlueNoise), get(SeedMode::Stbn)) else { continue };
            // No split measured (one replicate): nothing to say here.
            if rot.iter().any(|m| !m.noise.is_finite()) {
                continue;
            }
            out.push(SeedsCell {
                place: Place::of(at, floor_of(configs)),
                prefix: config.prefix(),
                rotation: estimate(rot, Of::Noise),
                blue_noise: estimate(bn, Of::Noise),
                stbn: estimate(st, Of::Noise),
                bias: [rot, bn, st].map(|v| Parts::of(v).bias),
                blue_noise_vs_rotation: Versus::of(rot, bn, Of::Noise).margin,
            });
        }
    }
    Some((fewest, out))
}

/// Question (3) in one cell: what engines ship against the masks and the paper's, after one
/// pipeline at its last frame, for one scene and rays per frame.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineCell {
    pub place: Place,
    /// Either best's mean RMSE is below the floor.
    pub below_floor: bool,
    /// The RMSE verdict is the two sides' biases at work: no win.
    pub bias_interaction: bool,
    /// The configuration of least mean RMSE whose seed mode is an engine pattern
    /// (`SeedMode::pattern`), and its RMSE.
    pub engine: Config,
    pub engine_rmse: Estimate,
    /// The configuration of least mean RMSE of every other seed mode, and its RMSE.
    pub other: Config,
    pub other_rmse: Estimate,
    /// The best other against the best engine pattern (positive: the engine's has less error).
    pub rmse: Versus,
    pub noise: Versus,
}

/// Whether a configuration's seed mode is an engine pattern.
fn is_engine(c: &Config) -> bool {
    c.seed_mode.pattern().is_some()
}

/// Question (3): per (scene, rays, pipeline at its last frame) where an engine pattern and some
/// other seed mode were measured, the best of each (least mean RMSE; the winner's curse of
/// `paper_cells` applies to both sides) and their paired margins.
pub fn engine_cells(results: &[JobResult]) -> Vec<EngineCell> {
    let cells = cells(results);
    let mut out = Vec::new();
    let best = |it: &mut dyn Iterator<Item = (&Config, &Vec<Measured>)>| {
        it.min_by(|x, y| mean_rmse(x.1).total_cmp(&mean_rmse(y.1))).map(|(l, v)| (*l, v.clone()))
    };
    for (at, configs) in &cells {
        if cells.keys().any(|k| k.same_run(at) && k.frame > at.frame) {
            continue;
        }
        let engine = best(&mut configs.iter().filter(|(l, _)| is_engine(l)));
        let other = best(&mut configs.iter().filter(|(l, _)| !is_engine(l)));
        let (Some((engine, e)), Some((other, o))) = (engine, other) else { continue };
        let floor = floor_of(configs);
        let rmse = Versus::of(&e, &o, Of::Rmse);
        out.push(EngineCell {
            place: Place::of(at, floor),
            below_floor: below(floor, &[mean_rmse(&e), mean_rmse(&o)]),
            bias_interaction: interaction(&e, &o, &rmse),
            engine,
            engine_rmse: estimate(&e, Of::Rmse),
            other,
            other_rmse: estimate(&o, Of::Rmse),
            rmse,
            noise: Versus::of(&e, &o, Of::Noise),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Distribution as D, SeedMode as M, Sequence as S};
    use crate::spec::Row;

    /// Two replicates of a configuration at `rmse` ± `d`, noise RMSE half of it.
    fn recs(seq: S, mode: M, pipeline: &str, frame: u32, rmse: f64, d: f64) -> Vec<JobResult> {
        (0..2)
            .map(|rep| {
                let v = rmse + if rep == 0 { -d } else { d };
                let mut r = JobResult::for_test("k", Row::new(D::SineCosine, seq, mode), 2, rep, v, 1.0);
                r.pipeline = pipeline.into();
                r.frame = frame;
                r.bias_rmse = 0.0;
                r.noise_rmse = rmse;
                r
            })
            .collect()
    }

    #[test]
    fn cells_are_read_at_the_last_frame_with_paired_margins() {
        let rs: Vec<JobResult> = [
            recs(S::Fibonacci, M::Rotation, "raw", 1, 0.10, 0.001),
            recs(S::Random, M::Rotation, "raw", 1, 0.12, 0.001),
            recs(S::Fibonacci, M::Rotation, "ema0.1+atrous", 1, 0.05, 0.001),
            recs(S::Random, M::BlueNoise, "ema0.1+atrous", 1, 0.01, 0.001),
            recs(S::Fibonacci, M::Rotation, "ema0.1+atrous", 16, 0.02, 0.001),
            recs(S::Random, M::BlueNoise, "ema0.1+atrous", 16, 0.03, 0.002),
            recs(S::Random, M::Stbn, "ema0.1+atrous", 16, 0.015, 0.001),
        ]
        .concat();
        let paper = paper_cells(&rs).unwrap();
        assert_eq!(paper.len(), 2);
        assert_eq!((paper[0].place.pipeline.as_str(), paper[0].place.frame), ("ema0.1+atrous", 16));
        // Best other: stbn at 0.015 against 0.02; the paired differences are exactly −0.005 twice.
        assert_eq!(paper[0].best.to_string(), "sine-cosine/random/stbn/independent");
        let m = paper[0].rmse.margin;
        assert!((m.relative() + 0.25).abs() < 1e-9 && m.n == 2, "{m:?}");
        assert_eq!((paper[0].rmse.sign, paper[0].noise.sign), (-1, -1));
        assert_eq!(paper[1].rmse.sign, 1, "raw: the paper's 0.10 against 0.12");
        let stbn = stbn_cells(&rs);
        assert_eq!(stbn.len(), 1);
        // stbn − blue noise: −0.016 and −0.014 → −50 % ± 3.3 % of 0.03: beyond t(1 dof) = 12.7 SE.
        let m = stbn[0].rmse.margin;
        assert!((m.relative() + 0.5).abs() < 1e-9 && (m.relative_se() - 0.1 / 3.0).abs() < 1e-9, "{m:?}");
        assert_eq!(stbn[0].rmse.sign, -1);
        assert_eq!(seeds_cells(&rs).map(|s| s.1.len()), Some(0), "no rotation/blue-noise/stbn triple");
        assert!(paper_cells(&rs[..4]).is_none(), "single frames only: nothing real-time");
    }

    #[test]
    fn engine_cells_set_the_best_engine_pattern_against_the_best_other_seed_mode() {
        let rs: Vec<JobResult> = [
            recs(S::Fibonacci, M::Rotation, "ema0.1+atrous", 16, 0.030, 0.001),
            recs(S::Random, M::BlueNoise, "ema0.1+atrous", 16, 0.020, 0.001),
            recs(S::Random, M::Ign, "ema0.1+atrous", 16, 0.025, 0.001),
            recs(S::Fibonacci, M::Bayer, "ema0.1+atrous", 16, 0.040, 0.001),
            recs(S::Random, M::Ign, "ema0.1+atrous", 1, 0.001, 0.0001),
            recs(S::Fibonacci, M::Rotation, "raw", 1, 0.10, 0.001),
            recs(S::Fibonacci, M::MagicSquare, "raw", 1, 0.08, 0.001),
        ]
        .concat();
        let c = engine_cells(&rs);
        assert_eq!(c.len(), 2, "{c:?}");
        assert_eq!(
            (c[0].place.pipeline.as_str(), c[0].place.frame),
            ("ema0.1+atrous", 16),
            "the last frame only"
        );
        assert_eq!(c[0].engine.to_string(), "sine-cosine/random/ign/independent");
        assert_eq!(c[0].other.to_string(), "sine-cosine/random/blue-noise/independent");
        // Blue noise − IGN: exactly −0.005 twice → −20 % of 0.025, a verdict however few pairs.
        assert!((c[0].rmse.margin.relative() + 0.2).abs() < 1e-12, "{:?}", c[0].rmse.margin);
        assert_eq!((c[0].rmse.sign, c[0].noise.sign), (-1, -1), "the other wins");
        assert_eq!(c[1].engine.to_string(), "sine-cosine/fibonacci/magic-square/independent");
        assert_eq!(c[1].rmse.sign, 1, "raw: the magic square's 0.08 against the paper's 0.10");
        assert!(engine_cells(&rs[..4]).is_empty(), "no engine pattern measured: no cell");
    }

    #[test]
    fn a_margin_within_the_biases_with_the_noise_ranked_the_other_way_is_a_bias_interaction() {
        // The paper's: RMSE 0.050 ± 0.0005, bias 0.040 (noise 0.030); the other: RMSE 0.048, bias
        // 0.010 (noise 0.047). The other wins on RMSE by 0.002, within the biases' 0.030, while its
        // noise is the larger: the biases decide, not the samplers' noise.
        let set = |v: &mut Vec<JobResult>, bias: f64| {
            v.iter_mut().for_each(|r| {
                r.bias_rmse = bias;
                r.noise_rmse = (0.05f64.powi(2) - bias * bias).sqrt();
            })
        };
        let mut paper = recs(S::Fibonacci, M::Rotation, "svgf", 16, 0.050, 0.0005);
        let mut other = recs(S::Fibonacci, M::BlueNoise, "svgf", 16, 0.048, 0.0005);
        set(&mut paper, 0.040);
        set(&mut other, 0.010);
        let rs = [paper.clone(), other.clone()].concat();
        let c = &paper_cells(&rs).unwrap()[0];
        assert_eq!((c.rmse.sign, c.noise.sign), (-1, 1), "{c:?}");
        assert!(c.bias_interaction);
        assert_eq!(c.paper_parts.bias.value, 0.040);
        // The same margin with equal biases is a win.
        set(&mut other, 0.040);
        let c = &paper_cells(&[paper, other].concat()).unwrap()[0];
        assert!(c.rmse.sign == -1 && !c.bias_interaction, "{c:?}");
    }
}

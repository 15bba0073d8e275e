//! The real-time questions, one cell type and one function each (the module doc of `realtime`
//! says what they ask and how a verdict is called).

use super::*;

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
    /// The same on mean LDR-FLIP ("—" in records without it).
    pub flip: Versus,
}

impl PaperCell {
    /// Whether RMSE and FLIP disagree here (one says a side wins, the other a tie or the other
    /// side; the RMSE verdict withheld counts as none).
    pub fn rmse_flip_disagree(&self) -> bool {
        disagree(&self.rmse, self.below_floor || self.bias_interaction, &self.flip)
    }
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
            flip: Versus::of(paper, b, Of::Flip),
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
    /// The same on mean LDR-FLIP ("—" in records without it).
    pub flip: Versus,
}

impl StbnCell {
    /// Whether RMSE and FLIP disagree here (one says a side wins, the other a tie or the other
    /// side; the RMSE verdict withheld counts as none).
    pub fn rmse_flip_disagree(&self) -> bool {
        disagree(&self.rmse, self.below_floor || self.bias_interaction, &self.flip)
    }
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
                flip: Versus::of(bn, st, Of::Flip),
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
    /// Blue noise against rotation on mean LDR-FLIP (n = 0 in records without it).
    pub blue_noise_vs_rotation_flip: Margin,
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
                blue_noise_vs_rotation_flip: Versus::of(rot, bn, Of::Flip).margin,
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
    /// The same on mean LDR-FLIP ("—" in records without it).
    pub flip: Versus,
}

impl EngineCell {
    /// Whether RMSE and FLIP disagree here (one says a side wins, the other a tie or the other
    /// side; the RMSE verdict withheld counts as none).
    pub fn rmse_flip_disagree(&self) -> bool {
        disagree(&self.rmse, self.below_floor || self.bias_interaction, &self.flip)
    }
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
            flip: Versus::of(&e, &o, Of::Flip),
        });
    }
    out
}

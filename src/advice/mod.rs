//! `hemilab advise`'s analysis (pure: records in, rankings out; no IO, no rendering): which
//! configuration gives the least error **at equal time**, from each configuration's measured ladder
//! of ray counts. The equal-time model itself — the ladders, a budget's interpolation, the ranking,
//! the error model and the structure rule — is `compare`'s (`compare::budget`, `compare::model`,
//! `compare::structure`), the same `run`'s report ranks with; advise adds what it alone decides:
//!
//! - **Which configurations**: every distribution × sequence × seed mode that is a distinct,
//!   sensible estimator (`sensible_rows`), or the subset `--only` patterns select (`select`).
//! - **Which budgets**: three over the paper default's measured range unless given
//!   (`default_budgets`), and which are impossible (`impossible`).
//! - **What is shipped**: each budget's finalists measured at the integer ray count that fits it
//!   (`advice/answer.rs`); the per-pixel winner map (`advice/winner.rs`); the ranked image of a
//!   real-time pipeline (`advice/pipeline.rs`); the sweep a request sets up (`advice/setup.rs`,
//!   from inputs the command loaded, with `advice/defaults.rs`'s replicates and reference).

pub mod analysis;
pub mod answer;
pub mod defaults;
pub mod pipeline;
pub mod request;
pub mod setup;
pub mod winner;

use crate::compare::PAPER_DEFAULT;
use crate::compare::budget::{Curve, monotone_log_times, round_significant};
use crate::sampling::{Distribution, SeedMode, Sequence};
use crate::spec::Row;

/// Why a row is left out of the default set, or `None` if it is a distinct, sensible estimator.
/// (`random` × `shift` is `random` × `rotation` by `Row::canonical` and never reaches here.)
pub fn not_sensible(row: Row) -> Option<&'static str> {
    match (row.distribution, row.sequence, row.seed_mode) {
        (_, Sequence::Random, SeedMode::Static) => {
            Some("one set of pseudo-random numbers in every pixel: the static seed without the lattice")
        }
        // One frame of it is a 2-D blue-noise mask, what `blue-noise` already is; it differs only
        // over frames, which a single image does not see. Asked for by name, it is measured.
        (_, _, SeedMode::Stbn) => {
            Some("for one frame, a spatiotemporal mask's slice is a 2-D blue-noise mask like `blue-noise`'s")
        }
        // The samplers renderers ship beside the paper's (`SequenceInfo::shipped`) are measured
        // as they ship: randomized per pixel, and ZSobol also unscrambled per pixel (its Morton
        // blocks are what spreads its error as blue noise). Their other seed modes run when named
        // with --only; all of them would double the sweep.
        (_, s, m) if s.info().shipped.is_some_and(|sh| !sh.modes.contains(&m)) => {
            s.info().shipped.map(|sh| sh.why)
        }
        (Distribution::ConcentricCosine, s, SeedMode::Rotation) if s != Sequence::Random => {
            Some("through the concentric map an x offset is not a rotation about the normal")
        }
        // The engines' patterns rotate the static set by a fixed, tiled pattern (docs/textures.md):
        // one image of it is a structured x offset between `rotation` (white) and `blue-noise`
        // (blue, and 2-D); they are built for frames accumulated and filtered, where a real-time
        // pipeline's default sweep adds them as engines ship them (`engine_rows`). Every
        // distribution × sequence of them would add 4 × 4 × 5 rows of one kind.
        (_, _, m) if m.pattern().is_some() => Some(
            "an engine's rotation pattern (ign, bayer, magic-square, r2-dither): in the sweep of a real-time \
             --pipeline as engines ship it (sine-cosine, random or fibonacci); else name it in full with --only",
        ),
        // A file's texture (`advise --texture`) is measured as its use says: an offset texture as
        // `blue-noise` is, a rotation texture as `rotation`, a vector texture only with sine-cosine.
        (d, _, m) if m.texture_use() == Some(crate::sampling::texture::TextureUse::Vector) => (d
            != Distribution::SineCosine)
            .then_some("a vector texture holds cosine-weighted directions: sine-cosine only"),
        (Distribution::ConcentricCosine, s, m)
            if m.texture_use() == Some(crate::sampling::texture::TextureUse::Rotation)
                && s != Sequence::Random =>
        {
            Some("through the concentric map an x offset is not a rotation about the normal")
        }
        _ => None,
    }
}

/// The sensible rows that name at least one of the `sequences` or `modes` a command line added
/// (point files, textures: `advise --points`, `--texture`), over every distribution, built-in or
/// added sequence and seed mode, canonical and in that order.
pub fn sensible_rows_with(sequences: &[Sequence], modes: &[SeedMode]) -> Vec<Row> {
    let builtin: Vec<Sequence> =
        Sequence::all().into_iter().filter(|s| !s.name().starts_with("points:")).collect();
    let all_s: Vec<Sequence> = builtin.iter().chain(sequences).copied().collect();
    let all_m: Vec<SeedMode> = SeedMode::ALL.iter().chain(modes).copied().collect();
    let mut rows = Vec::new();
    for &d in Distribution::ALL {
        for &s in &all_s {
            for &m in &all_m {
                if !sequences.contains(&s) && !modes.contains(&m) {
                    continue;
                }
                let r = Row::new(d, s, m).canonical();
                if not_sensible(r).is_none() && r.invalid().is_none() && !rows.contains(&r) {
                    rows.push(r);
                }
            }
        }
    }
    rows
}

/// Why a static seed is not a candidate under a pipeline that accumulates frames (the page says it
/// in this one line): its error repeats every frame.
pub const REPEATING_ERROR: &str = "Static seeds are not candidates here: a static seed draws the same points in every frame, \
     so its error is the same in every frame and accumulating frames never averages it away.";

/// The configurations a pipeline's advice can recommend: under an accumulating (temporal)
/// pipeline, none whose error repeats every frame (a static seed, `REPEATING_ERROR`).
pub fn candidates_for(rows: Vec<Row>, pipeline: crate::denoise::Pipeline) -> Vec<Row> {
    if !pipeline.is_temporal() {
        return rows;
    }
    rows.into_iter().filter(|r| r.seed_mode != SeedMode::Static).collect()
}

/// The engines' rotation patterns (`SeedMode::pattern`: ign, bayer, magic-square, r2-dither) as
/// engines ship them: each rotating a cosine-weighted kernel of pseudo-random points or the
/// Fibonacci lattice (the paper's), in that order. Advise's default sweep adds them when it ranks
/// a real-time pipeline's image (`setup::check`, any `--pipeline` but raw), which is what they
/// are built for; `experiments/engine-noise.toml` measures the same rows.
pub fn engine_rows() -> Vec<Row> {
    let mut rows = Vec::new();
    for &m in SeedMode::ALL.iter().filter(|m| m.pattern().is_some()) {
        for s in [Sequence::Random, Sequence::Fibonacci] {
            rows.push(Row::new(Distribution::SineCosine, s, m).canonical());
        }
    }
    rows
}

/// The seed modes a real-time renderer chooses from: a per-pixel rotation (the paper's), a
/// blue-noise mask's offsets, spatiotemporal blue noise, and the engines' rotation patterns.
pub const REALTIME_MODES: [SeedMode; 7] = [
    SeedMode::Rotation,
    SeedMode::BlueNoise,
    SeedMode::Stbn,
    SeedMode::Ign,
    SeedMode::Bayer,
    SeedMode::MagicSquare,
    SeedMode::R2Dither,
];

/// The sequences engines draw their kernels from: pseudo-random points and the paper's lattice.
pub const REALTIME_SEQUENCES: [Sequence; 2] = [Sequence::Random, Sequence::Fibonacci];

/// What advise sweeps by default after a real-time pipeline: the cosine-weighted kernel engines
/// use, through `REALTIME_SEQUENCES`, with every seed mode of `REALTIME_MODES` and of the
/// textures `modes` (`--texture`) — the choice an engine actually makes — each under both
/// schedules and every camera, which multiplies the sweep by four, so not every distribution ×
/// sequence of the paper's raw sweep (`--only` names any of those). The paper's default first.
pub fn realtime_rows(modes: &[SeedMode]) -> Vec<Row> {
    let mut rows = vec![PAPER_DEFAULT];
    for s in REALTIME_SEQUENCES {
        for &m in REALTIME_MODES.iter().chain(modes) {
            let r = Row::new(Distribution::SineCosine, s, m).canonical();
            if r.invalid().is_none() && !rows.contains(&r) {
                rows.push(r);
            }
        }
    }
    rows
}

/// The schedules a configuration is measured under when `frames` frames are accumulated: both
/// (`independent`, `r1`) where the schedule changes its points, else `independent` alone, since
/// the other would render the very same images (`SeedMode::schedule_matters`: `stbn` up to 32
/// frames).
pub fn schedules_for(row: Row, frames: u32) -> Vec<crate::sampling::Schedule> {
    use crate::sampling::Schedule;
    if row.seed_mode.schedule_matters(frames) {
        vec![Schedule::Independent, Schedule::R1]
    } else {
        vec![Schedule::Independent]
    }
}

/// Every distribution × sequence × seed mode that `advise` runs by default: canonical (duplicates
/// such as `random` × `shift` = `random` × `rotation` merged) and sensible (`not_sensible`), in the
/// order of `Distribution::ALL`, `Sequence::all()`, `SeedMode::ALL`.
pub fn sensible_rows() -> Vec<Row> {
    let mut rows = Vec::new();
    for &d in Distribution::ALL {
        for s in Sequence::all() {
            for &m in SeedMode::ALL {
                let r = Row::new(d, s, m).canonical();
                if not_sensible(r).is_none() && !rows.contains(&r) {
                    rows.push(r);
                }
            }
        }
    }
    rows
}

/// One `--only` item, `distribution/sequence/seed_mode`, each part a name or `*` (any).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pattern {
    pub distribution: Option<Distribution>,
    pub sequence: Option<Sequence>,
    pub seed_mode: Option<SeedMode>,
}

impl Pattern {
    /// `sine-cosine/fibonacci/*`, `*/*/blue-noise`, …; the message names the item and what is allowed.
    pub fn parse(s: &str) -> Result<Self, String> {
        let parts: Vec<&str> = s.trim().split('/').map(str::trim).collect();
        let [d, q, m] = parts[..] else {
            return Err(format!(
                "'{s}' must be distribution/sequence/seed_mode, each a name or *, e.g. sine-cosine/fibonacci/*"
            ));
        };
        fn part<T: std::str::FromStr<Err = String>>(p: &str) -> Result<Option<T>, String> {
            if p == "*" { Ok(None) } else { p.parse().map(Some) }
        }
        let at = |e: String| format!("'{s}': {e}");
        Ok(Self {
            distribution: part(d).map_err(at)?,
            sequence: part(q).map_err(at)?,
            seed_mode: part(m).map_err(at)?,
        })
    }

    /// The pattern as `parse` reads it back.
    pub fn to_text(&self) -> String {
        let show = |o: Option<&str>| o.unwrap_or("*").to_string();
        format!(
            "{}/{}/{}",
            show(self.distribution.map(|d| d.name())),
            show(self.sequence.map(|s| s.name())),
            show(self.seed_mode.map(|m| m.name()))
        )
    }

    fn exact(&self) -> Option<Row> {
        Some(Row::new(self.distribution?, self.sequence?, self.seed_mode?).canonical())
    }

    fn matches(&self, r: Row) -> bool {
        self.distribution.is_none_or(|d| d == r.distribution)
            && self.sequence.is_none_or(|s| s == r.sequence)
            && self.seed_mode.is_none_or(|m| m == r.seed_mode)
    }
}

/// The configurations to run: all sensible rows (no patterns), else those the patterns match — a
/// fully named pattern is taken as asked even if not in the default set — and always the paper's
/// default (every gain is against it), first. A pattern that matches nothing is an error.
pub fn select(patterns: &[Pattern]) -> Result<Vec<Row>, String> {
    select_with(patterns, &[])
}

/// `select` over the sensible rows and `added` (the rows of `advise --texture`, `--points`:
/// `sensible_rows_with`), which patterns select as they select the built-ins'.
pub fn select_with(patterns: &[Pattern], added: &[Row]) -> Result<Vec<Row>, String> {
    let mut all = sensible_rows();
    all.extend(added.iter().filter(|r| !all.contains(r)).copied().collect::<Vec<_>>());
    select_in(patterns, all.clone(), all)
}

/// `select_with` after a real-time pipeline: without patterns, `realtime_rows` with the textures
/// of `added` and the point files' rows of the kernel engines use (sine-cosine); patterns select
/// from those, the sensible rows and `added` alike.
pub fn select_realtime(patterns: &[Pattern], added: &[Row]) -> Result<Vec<Row>, String> {
    let modes: Vec<SeedMode> =
        added.iter().map(|r| r.seed_mode).filter(|m| m.texture_use().is_some()).collect();
    let mut default = realtime_rows(&modes);
    for r in added {
        let engine_kernel = r.distribution == Distribution::SineCosine
            && (REALTIME_SEQUENCES.contains(&r.sequence) || r.sequence.name().starts_with("points:"))
            && (REALTIME_MODES.contains(&r.seed_mode) || modes.contains(&r.seed_mode));
        if engine_kernel && !default.contains(r) {
            default.push(*r);
        }
    }
    let mut all = sensible_rows();
    for r in default.iter().chain(added) {
        if !all.contains(r) {
            all.push(*r);
        }
    }
    select_in(patterns, default, all)
}

/// The paper's default first, then `default` without patterns, else what the patterns pick of
/// `all` (a fully named one taken as asked).
fn select_in(patterns: &[Pattern], default: Vec<Row>, all: Vec<Row>) -> Result<Vec<Row>, String> {
    let mut rows = vec![PAPER_DEFAULT];
    if patterns.is_empty() {
        rows.extend(default.into_iter().filter(|r| *r != PAPER_DEFAULT));
        return Ok(rows);
    }
    for p in patterns {
        let hits: Vec<Row> = match p.exact() {
            Some(r) => vec![r],
            None => all.iter().copied().filter(|r| p.matches(*r)).collect(),
        };
        if hits.is_empty() {
            return Err(format!(
                "'{}' matches no configuration of the default set (which leaves out random × static \
                 and concentric-cosine × rotation of a lattice, scramble or jitter, and stbn, whose single \
                 frame is a 2-D blue-noise mask; name one in full to run it)",
                p.to_text()
            ));
        }
        for r in hits {
            if !rows.contains(&r) {
                rows.push(r);
            }
        }
    }
    Ok(rows)
}

/// Default budgets when none are given: three times spread over the paper default's measured
/// range — a quarter, half and three quarters of the way in log time from its cheapest to its
/// dearest render — rounded to two significant digits (and kept inside the range). On a narrow
/// range (a tiny image) two of them can round to the same number: then more digits are kept, so
/// there are always three distinct budgets when the range is not a single time.
pub fn default_budgets(paper_default: &Curve) -> Vec<f64> {
    let lt = monotone_log_times(&paper_default.points);
    let (Some(&a), Some(&b)) = (lt.first(), lt.last()) else { return Vec::new() };
    let spread = |digits: usize| {
        let mut out: Vec<f64> = Vec::new();
        for q in [0.25, 0.5, 0.75] {
            let t = round_significant((a + q * (b - a)).exp(), digits).clamp(a.exp(), b.exp());
            if !out.contains(&t) {
                out.push(t);
            }
        }
        out
    };
    (2..=6).map(spread).find(|b| b.len() == 3).unwrap_or_else(|| spread(2))
}

/// How far below the calibrated cheapest render (`jobs::calibrate::cheapest`) a budget must be to
/// be refused before the sweep. The calibration is a fraction of a second of renders with a short
/// warm-up and over-predicts: the sweep's measured cheapest render was 1.17× below it on the
/// kitchen (1.37 against 1.6 ms at 64x48) and 1.33× on the Cornell box (0.21 against 0.28 ms at
/// 32x32), 2026-12-01 at load 9. A budget between this and the cheapest render is swept, and
/// where it is below every measured time the answer says so.
pub const REFUSE_BELOW: f64 = 0.5;

/// The budgets (seconds) no configuration can render an image in: below [`REFUSE_BELOW`] × the
/// calibrated cheapest render.
pub fn impossible(budgets_s: &[f64], cheapest_s: f64) -> Vec<f64> {
    budgets_s.iter().copied().filter(|&b| b < REFUSE_BELOW * cheapest_s).collect()
}

#[cfg(test)]
mod tests;

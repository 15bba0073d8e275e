//! Pure: the configurations ranked at equal rays per pixel per frame — the budget a real-time
//! engine has (1, 2, 4 rays), not a millisecond budget of this machine. At one ray count every
//! configuration's replicates are paired (replicate r has the same seed in each), so a margin is
//! the paired difference of MSE over the replicates (`margin::paired`); the configurations whose
//! margin to the best is not significant at [`ALPHA`] (two-sided Student's t) are its near-ties,
//! listed beside it rather than ranked against it.

use crate::compare::margin::{self, Margin};
use crate::compare::model::Estimate;
use crate::results::JobResult;
use crate::sampling::Schedule;
use crate::spec::Row;
use crate::stats::mean_and_standard_error;

/// Two-sided level below which a configuration counts as behind the best, not a near-tie.
pub const ALPHA: f64 = 0.05;

/// What is ranked: a configuration under a per-frame schedule.
pub type Candidate = (Row, Schedule);

/// The winner's error split into the part a new seed changes and the part it does not, measured
/// from its replicates (`jobs::replicates`, the records' `bias_rmse`, `bias_se`, `noise_rmse`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Split {
    pub bias_rmse: f64,
    pub bias_se: f64,
    pub noise_rmse: f64,
}

/// One configuration at one ray count.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub row: Row,
    pub schedule: Schedule,
    /// √(mean MSE over the replicates), its σ by the delta method.
    pub rmse: Estimate,
    /// Each replicate's MSE, by replicate.
    pub mse: Vec<(u32, f64)>,
    /// Mean LDR-FLIP over the replicates and its standard error (NaN where not measured).
    pub flip: Estimate,
    /// Each replicate's FLIP, by replicate (paired like the MSE).
    pub flips: Vec<(u32, f64)>,
    /// Mean flicker over the replicates (`metrics::flicker`; NaN where not measured).
    pub flicker: f64,
    /// The bias/noise split of its error (NaN parts where the images were not kept).
    pub split: Split,
    /// Median over the records of one frame's CPU time (the records' times are per frame).
    pub time_s: f64,
    /// Its MSE over the best's, paired over replicates (`None` for the best itself).
    pub behind: Option<Margin>,
    /// Not significantly behind the best (the best is one of its own near-ties).
    pub near_tie: bool,
}

impl Entry {
    pub fn candidate(&self) -> Candidate {
        (self.row, self.schedule)
    }
}

/// Every configuration measured at `rays` by one camera, least mean MSE first.
#[derive(Debug, Clone, PartialEq)]
pub struct AtRays {
    pub rays: u32,
    /// The camera's name (results' `camera` column: `static` for the scene's still camera).
    pub camera: String,
    pub entries: Vec<Entry>,
}

impl AtRays {
    pub fn best(&self) -> Option<&Entry> {
        self.entries.first()
    }

    /// The configuration with the least mean FLIP, if FLIP was measured.
    pub fn best_flip(&self) -> Option<&Entry> {
        self.entries
            .iter()
            .filter(|e| e.flip.value.is_finite())
            .min_by(|a, b| a.flip.value.total_cmp(&b.flip.value))
    }

    /// The best and every configuration within its paired margin.
    pub fn near_ties(&self) -> impl Iterator<Item = &Entry> {
        self.entries.iter().filter(|e| e.near_tie)
    }

    pub fn entry(&self, row: Row) -> Option<&Entry> {
        self.entries.iter().find(|e| e.row == row)
    }

    /// `row` under `schedule`.
    pub fn entry_of(&self, c: Candidate) -> Option<&Entry> {
        self.entries.iter().find(|e| e.candidate() == c)
    }
}

/// First finite value of a column over records (the split columns hold one value per
/// configuration, repeated in each replicate's record).
fn first_finite(rs: &[&JobResult], f: impl Fn(&JobResult) -> f64) -> f64 {
    rs.iter().map(|r| f(r)).find(|v| v.is_finite()).unwrap_or(f64::NAN)
}

/// The ranking at `rays` of `records` (one frame each: `advice::pipeline::as_ranked`'s view) seen
/// by `camera`, of the candidates (configuration, schedule).
pub fn rank(records: &[JobResult], candidates: &[Candidate], rays: u32, camera: &str) -> AtRays {
    let mut entries: Vec<Entry> = candidates
        .iter()
        .filter_map(|&(row, schedule)| {
            let mine: Vec<&JobResult> = records
                .iter()
                .filter(|r| {
                    r.rays == rays && r.is_row(row) && r.camera == camera && r.schedule == schedule.name()
                })
                .collect();
            if mine.is_empty() {
                return None;
            }
            let by_rep = |f: &dyn Fn(&JobResult) -> f64| {
                let mut v: Vec<(u32, f64)> = mine.iter().map(|r| (r.replicate, f(r))).collect();
                v.sort_by_key(|m| m.0);
                v
            };
            let mse = by_rep(&|r| r.rmse * r.rmse);
            let (m, se) = mean_and_standard_error(&mse.iter().map(|x| x.1).collect::<Vec<_>>());
            let rmse = m.sqrt();
            let rmse_se = if rmse > 0.0 { se / (2.0 * rmse) } else { f64::NAN };
            let flips = by_rep(&|r| r.flip);
            let (flip, flip_se) = if flips.iter().all(|f| f.1.is_finite()) {
                mean_and_standard_error(&flips.iter().map(|x| x.1).collect::<Vec<_>>())
            } else {
                (f64::NAN, f64::NAN)
            };
            let flicker: Vec<f64> = mine.iter().filter_map(|r| r.flicker).filter(|f| f.is_finite()).collect();
            let times: Vec<f64> = mine.iter().map(|r| r.time_s).filter(|t| t.is_finite()).collect();
            Some(Entry {
                row,
                schedule,
                rmse: Estimate { value: rmse, se: rmse_se },
                mse,
                flip: Estimate { value: flip, se: flip_se },
                flips,
                flicker: if flicker.is_empty() {
                    f64::NAN
                } else {
                    flicker.iter().sum::<f64>() / flicker.len() as f64
                },
                split: Split {
                    bias_rmse: first_finite(&mine, |r| r.bias_rmse),
                    bias_se: first_finite(&mine, |r| r.bias_se),
                    noise_rmse: first_finite(&mine, |r| r.noise_rmse),
                },
                time_s: if times.is_empty() { f64::NAN } else { crate::stats::median(&times) },
                behind: None,
                near_tie: false,
            })
        })
        .collect();
    entries.sort_by(|a, b| {
        a.rmse.value.total_cmp(&b.rmse.value).then(a.row.cmp(&b.row)).then(a.schedule.cmp(&b.schedule))
    });
    if let Some(best) = entries.first().map(|e| e.mse.clone()) {
        for (i, e) in entries.iter_mut().enumerate() {
            if i == 0 {
                e.near_tie = true;
                continue;
            }
            let m = margin::paired(&best, &e.mse);
            e.near_tie = m.sign(ALPHA) <= 0;
            e.behind = Some(m);
        }
    }
    AtRays { rays, camera: camera.to_string(), entries }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Distribution, SeedMode, Sequence};

    fn rec(row: Row, rays: u32, rep: u32, rmse: f64) -> JobResult {
        let mut r = JobResult::for_test("s", row, rays, rep, rmse, 1.0);
        r.add_time(1e-3 * rays as f64, 0.0);
        r
    }

    #[test]
    fn ranks_by_mse_and_lists_the_best_within_its_paired_margin() {
        let a = Row::new(Distribution::SineCosine, Sequence::Fibonacci, SeedMode::BlueNoise);
        let b = Row::new(Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Rotation);
        let c = Row::new(Distribution::SineCosine, Sequence::Random, SeedMode::Rotation);
        let mut records = Vec::new();
        for rep in 0..6u32 {
            let wobble = if rep % 2 == 0 { 1e-4 } else { -1e-4 };
            records.push(rec(a, 1, rep, 0.100 + wobble));
            // b: a hair worse on average, with a spread that does not tell it from a.
            records.push(rec(b, 1, rep, 0.100 - wobble + 2e-5));
            // c: clearly worse in every replicate.
            records.push(rec(c, 1, rep, 0.130 + wobble));
            records.push(rec(a, 2, rep, 0.07));
        }
        let ind = |r: Row| (r, Schedule::Independent);
        let r = rank(&records, &[ind(c), ind(b), ind(a)], 1, "static");
        assert_eq!(r.rays, 1);
        assert_eq!(r.entries.iter().map(|e| e.row).collect::<Vec<_>>(), [a, b, c]);
        assert_eq!(r.near_ties().map(|e| e.row).collect::<Vec<_>>(), [a, b]);
        let m = r.entry(c).unwrap().behind.unwrap();
        assert!(m.mean > 0.0 && m.sign(ALPHA) == 1, "{m:?}");
        assert!((r.best().unwrap().time_s - 1e-3).abs() < 1e-12);
        // Only the records at the ray count asked for.
        assert_eq!(rank(&records, &[ind(a), ind(b), ind(c)], 2, "static").entries.len(), 1);
        assert!(rank(&records, &[ind(a)], 4, "static").entries.is_empty());
        // Another camera's or schedule's records are not this ranking's.
        assert!(rank(&records, &[ind(a)], 1, "orbit").entries.is_empty());
        assert!(rank(&records, &[(a, Schedule::R1)], 1, "static").entries.is_empty());
        // FLIP not measured: no FLIP winner.
        assert!(r.best_flip().is_none());
    }
}

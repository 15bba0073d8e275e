//! Pure: the configurations ranked at equal rays per pixel per frame — the budget a real-time
//! engine has (1, 2, 4 rays), not a millisecond budget of this machine. At one ray count every
//! configuration's replicates are paired (replicate r has the same seed in each), so a margin is
//! the paired difference of MSE over the replicates (`margin::paired`); the configurations whose
//! margin to the best is not significant at [`ALPHA`] (two-sided Student's t) are its near-ties,
//! listed beside it rather than ranked against it.

use crate::compare::margin::{self, Margin};
use crate::compare::model::Estimate;
use crate::results::JobResult;
use crate::spec::Row;
use crate::stats::mean_and_standard_error;

/// Two-sided level below which a configuration counts as behind the best, not a near-tie.
pub const ALPHA: f64 = 0.05;

/// One configuration at one ray count.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub row: Row,
    /// √(mean MSE over the replicates), its σ by the delta method.
    pub rmse: Estimate,
    /// Each replicate's MSE, by replicate.
    pub mse: Vec<(u32, f64)>,
    /// Median over the records of one frame's CPU time (the records' times are per frame).
    pub time_s: f64,
    /// Its MSE over the best's, paired over replicates (`None` for the best itself).
    pub behind: Option<Margin>,
    /// Not significantly behind the best (the best is one of its own near-ties).
    pub near_tie: bool,
}

/// Every configuration measured at `rays`, least mean MSE first.
#[derive(Debug, Clone, PartialEq)]
pub struct AtRays {
    pub rays: u32,
    pub entries: Vec<Entry>,
}

impl AtRays {
    pub fn best(&self) -> Option<&Entry> {
        self.entries.first()
    }

    /// The best and every configuration within its paired margin.
    pub fn near_ties(&self) -> impl Iterator<Item = &Entry> {
        self.entries.iter().filter(|e| e.near_tie)
    }

    pub fn entry(&self, row: Row) -> Option<&Entry> {
        self.entries.iter().find(|e| e.row == row)
    }
}

/// The ranking at `rays` of `records` (one frame each: `advice::pipeline::as_ranked`'s view), of
/// the configurations `rows`.
pub fn rank(records: &[JobResult], rows: &[Row], rays: u32) -> AtRays {
    let mut entries: Vec<Entry> = rows
        .iter()
        .filter_map(|&row| {
            let mine: Vec<&JobResult> = records.iter().filter(|r| r.rays == rays && r.is_row(row)).collect();
            if mine.is_empty() {
                return None;
            }
            let mut mse: Vec<(u32, f64)> = mine.iter().map(|r| (r.replicate, r.rmse * r.rmse)).collect();
            mse.sort_by_key(|m| m.0);
            let (m, se) = mean_and_standard_error(&mse.iter().map(|x| x.1).collect::<Vec<_>>());
            let rmse = m.sqrt();
            let rmse_se = if rmse > 0.0 { se / (2.0 * rmse) } else { f64::NAN };
            let times: Vec<f64> = mine.iter().map(|r| r.time_s).filter(|t| t.is_finite()).collect();
            Some(Entry {
                row,
                rmse: Estimate { value: rmse, se: rmse_se },
                mse,
                time_s: if times.is_empty() { f64::NAN } else { crate::stats::median(&times) },
                behind: None,
                near_tie: false,
            })
        })
        .collect();
    entries.sort_by(|a, b| a.rmse.value.total_cmp(&b.rmse.value).then(a.row.cmp(&b.row)));
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
    AtRays { rays, entries }
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
        let r = rank(&records, &[c, b, a], 1);
        assert_eq!(r.rays, 1);
        assert_eq!(r.entries.iter().map(|e| e.row).collect::<Vec<_>>(), [a, b, c]);
        assert_eq!(r.near_ties().map(|e| e.row).collect::<Vec<_>>(), [a, b]);
        let m = r.entry(c).unwrap().behind.unwrap();
        assert!(m.mean > 0.0 && m.sign(ALPHA) == 1, "{m:?}");
        assert!((r.best().unwrap().time_s - 1e-3).abs() < 1e-12);
        // Only the records at the ray count asked for.
        assert_eq!(rank(&records, &[a, b, c], 2).entries.len(), 1);
        assert!(rank(&records, &[a], 4).entries.is_empty());
    }
}

//! What advise ships at a budget, measured at the ray count it names.
//!
//! The sweep's interpolation (`compare::budget::rank`) ranks every configuration at the budget, but it is
//! not what is shipped: the shipped ray count is an integer, and a lattice's error depends on its
//! count itself — measured, the shifted Fibonacci lattice's MSE differs from the log-log
//! interpolation between its neighbours by ×0.85–1.13 (replicate σ about 1 %), about the gaps
//! between the best configurations. So each budget's *finalists* ([`finalists`]: the
//! [`FINALISTS`] best by the interpolation, the best two unstructured ones, the best by low-pass
//! RMSE and the paper's default) are rendered again at the integer count that fits the budget
//! ([`rays_for`]), replicated and timed in one session, and the answer is decided on those numbers
//! ([`Answer::recommended`]). Their replicates have seeds of their own (`setup::verify_jobs`), so
//! the numbers reported are independent of the sweep the finalists were picked on: picking the
//! least of several noisy estimates biases that estimate low, a fresh measurement does not.
//!
//! Without those renders (`advise --from` at a new budget) a budget's answer is the sweep's
//! interpolation, and says so (`Answer::measured` false).
//!
//! Every gain, error and distance an answer states is computed once, when the answer is made
//! (`Scored`, `RankScored`): the page, advice.json and the printed lines read the same numbers.

use crate::compare::budget::{AtBudget, Metric, Ranking};
use crate::compare::model::{self, Estimate, Gain, Side};
use crate::compare::{PAPER_DEFAULT, structure};
use crate::results::JobResult;
use crate::spec::Row;
use crate::timing::Summary;

/// Configurations measured per budget besides those always measured: the best by interpolated
/// RMSE. The winner map compares the same ones (beyond them the image-level gap is large, and a
/// legend of 50 colours unreadable).
pub const FINALISTS: usize = 6;

/// Where the configuration's time line crosses the budget, rounded down (at least 1): the most
/// rays the sweep's interpolation says fit.
pub fn rays_for(a: &AtBudget) -> u32 {
    (a.rays.floor() as u32).max(1)
}

/// How many σ of the session factor (`model::RUN_FACTOR`) a measured time may be above the budget
/// and still fit it (`Candidate::fits`).
pub const FITS_SIGMA: f64 = 2.0;

/// The ray counts a finalist is measured at, most first: [`rays_for`]; the multiple of the packet
/// width below it (`scene::packet::PACKET`: rays are traced 32 to a packet, so a render's time
/// steps up at every 32 rays and the line between two measured counts under-predicts it there —
/// measured on the kitchen, 41 rays took 13–16 % longer than the line between 32 and 64 said); and
/// the sweep's measured count below the budget. What is shipped is the most of them whose
/// measured time fits the budget (`Answer::measure`).
pub fn counts(a: &AtBudget) -> Vec<u32> {
    let n = rays_for(a);
    let packet = crate::scene::packet::PACKET as u32;
    let mut out = vec![n, a.lo_rays.min(n).max(1)];
    if n > packet {
        out.push(n / packet * packet);
    }
    out.sort_unstable_by(|x, y| y.cmp(x));
    out.dedup();
    out
}

/// The configurations a budget's answer measures, in ranking order, each once: the [`FINALISTS`]
/// best by interpolated RMSE, the best two whose error is not structured (the recommendation and
/// its runner-up, were the interpolation right), the best by low-pass RMSE and the paper's
/// default (every gain is against it). None when no configuration is inside its measured times.
pub fn finalists<'a>(r: &'a Ranking, low: &'a Ranking) -> Vec<&'a AtBudget> {
    let mut out: Vec<&AtBudget> = r.ranked.iter().take(FINALISTS).collect();
    let extra = r.ranked.iter().filter(|a| !a.structured()).take(2);
    let more = extra.chain(low.ranked.first().and_then(|l| r.ranked.iter().find(|a| a.row == l.row)));
    for a in more.chain(r.ranked.iter().find(|a| a.row == PAPER_DEFAULT)) {
        if !out.iter().any(|o| o.row == a.row) {
            out.push(a);
        }
    }
    out
}

/// One configuration at a budget: measured at its integer ray count, or interpolated there.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    pub row: Row,
    /// The integer ray count shipped, and where the sweep's line crossed the budget.
    pub rays: u32,
    pub rays_interpolated: f64,
    /// The numbers below were measured at `rays`; else interpolated at the budget from the sweep.
    pub measured: bool,
    /// The finalist's other measured counts (`counts`) that were not shipped: (rays, median time,
    /// mean MSE).
    pub others: Vec<(u32, f64, f64)>,
    /// Median time per image at `rays` (the budget itself when interpolated), the σ of its ln
    /// within the session, and the timed renders behind it.
    pub time_s: f64,
    pub time_sigma_ln: f64,
    pub timings: usize,
    /// Per replicate: id, MSE, low-pass MSE, structure measure.
    pub replicates: Vec<u32>,
    pub mse: Vec<f64>,
    pub lowpass_mse: Vec<f64>,
    pub structure: Vec<f64>,
    /// d ln MSE / d ln time of its sweep at the budget, and the same for the low-pass MSE.
    pub slope: f64,
    pub lowpass_slope: f64,
}

impl Candidate {
    /// The sweep's interpolation at the budget.
    pub fn interpolated(a: &AtBudget, budget_s: f64) -> Self {
        Self {
            row: a.row,
            rays: rays_for(a),
            rays_interpolated: a.rays,
            measured: false,
            others: vec![],
            time_s: budget_s,
            time_sigma_ln: a.time_sigma_ln,
            timings: 0,
            replicates: a.replicates.clone(),
            mse: a.mse.clone(),
            lowpass_mse: a.lowpass_mse.clone(),
            structure: vec![a.structure; a.replicates.len()],
            slope: a.slope,
            lowpass_slope: a.lowpass_slope,
        }
    }

    /// Measured from `records` (its jobs at `rays`, every timed render of them); `None` without a
    /// timed record.
    pub fn measured(a: &AtBudget, rays: u32, records: &[&JobResult]) -> Option<Self> {
        let times: Vec<f64> = records.iter().flat_map(|r| r.times.iter().copied()).collect();
        let t = Summary::of(&times)?;
        Some(Self {
            measured: true,
            rays,
            time_s: t.median,
            time_sigma_ln: model::median_sigma_ln(&times),
            timings: t.n,
            replicates: records.iter().map(|r| r.replicate).collect(),
            mse: records.iter().map(|r| r.rmse * r.rmse).collect(),
            lowpass_mse: records.iter().map(|r| r.lowpass_rmse * r.lowpass_rmse).collect(),
            structure: records.iter().map(|r| structure::of(r)).collect(),
            ..Self::interpolated(a, f64::NAN)
        })
    }

    pub fn side(&self, m: Metric) -> Side<'_> {
        let (values, slope) = match m {
            Metric::Rmse => (&self.mse, self.slope),
            Metric::Lowpass => (&self.lowpass_mse, self.lowpass_slope),
        };
        Side { row: self.row, replicates: &self.replicates, values, slope, time_sigma_ln: self.time_sigma_ln }
    }

    /// Mean MSE ± 1 σ: at its ray count when measured (replicates), at the budget when
    /// interpolated (replicates and time).
    pub fn mean_mse(&self, m: Metric) -> Estimate {
        model::mean_mse(&self.side(m), !self.measured)
    }

    pub fn rmse(&self, m: Metric) -> Estimate {
        model::rmse(self.mean_mse(m))
    }

    /// The structure measure's mean over the replicates.
    pub fn structure_mean(&self) -> f64 {
        self.structure.iter().sum::<f64>() / self.structure.len().max(1) as f64
    }

    pub fn structured(&self) -> bool {
        structure::structured(self.structure_mean())
    }

    /// σ of ln(its time) on its own: the session's factor and the median's scatter.
    pub fn time_sigma_ln_total(&self) -> f64 {
        model::time_sigma_ln(self.time_sigma_ln)
    }

    /// Whether its measured time fits `budget_s`: put on the sweep's time scale (divided by
    /// `session_ratio`, the finalists' session's times over the sweep's at the counts both timed),
    /// it is not above the budget by more than [`FITS_SIGMA`] σ of the session factor. Every
    /// finalist is held to the same bound — the median's own scatter is left out, so a noisier
    /// median does not fit more easily — and a time 1–5 % over, noise on a busy machine, does
    /// not send the count down to the next one measured (far more error than the 1 %); the
    /// packet step above 32 rays (13–16 %) does.
    pub fn fits(&self, budget_s: f64, session_ratio: f64) -> bool {
        (self.time_s / session_ratio / budget_s).ln() <= FITS_SIGMA * model::RUN_FACTOR
    }
}

/// The answer at one budget.
#[derive(Debug, Clone, PartialEq)]
pub struct Answer {
    pub budget_s: f64,
    /// The sweep's interpolated rankings, by RMSE and by low-pass RMSE.
    pub ranking: Ranking,
    pub lowpass: Ranking,
    /// Every finalist was measured at its ray count (else all are interpolated).
    pub measured: bool,
    /// The finalists, least mean MSE first.
    pub finalists: Vec<Candidate>,
    /// The finalists' session's times over the sweep's (`Candidate::fits`); 1 when interpolated.
    pub session_ratio: f64,
    /// Per finalist, in the same order: what is said of it.
    pub scores: Vec<Scored>,
    /// Per configuration of `ranking` and of `lowpass`, in their order: what is said of it.
    pub ranking_scores: Vec<RankScored>,
    pub lowpass_scores: Vec<RankScored>,
}

/// What the page and advice.json say of one finalist: its time, RMSE and low-pass RMSE ± 1 σ, its
/// gains over the paper's default at the budget (`model::gain`; `None` without the default among
/// the finalists) and how far it trails the recommendation (`model::behind`; `None` for the
/// recommendation itself, or without one).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scored {
    /// Its time per image in ms ± 1 σ (the session's factor and the median's scatter).
    pub time_ms: Estimate,
    pub rmse: Estimate,
    pub lowpass_rmse: Estimate,
    pub gain: Option<Gain>,
    pub lowpass_gain: Option<Gain>,
    pub behind: Option<f64>,
}

/// What the page and advice.json say of one configuration of an interpolated ranking: its RMSE
/// and low-pass RMSE ± 1 σ, and, by the ranking's metric, its gain over the paper's default and
/// how far it trails the first (`None` for the first itself).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RankScored {
    pub rmse: Estimate,
    pub lowpass_rmse: Estimate,
    pub gain: Option<Gain>,
    pub behind_best: Option<f64>,
}

/// Every configuration of `r` scored against the paper's default and the first.
fn rank_scores(r: &Ranking) -> Vec<RankScored> {
    let m = r.metric;
    let default = r.ranked.iter().find(|d| d.row == PAPER_DEFAULT);
    r.ranked
        .iter()
        .map(|x| RankScored {
            rmse: x.rmse(Metric::Rmse),
            lowpass_rmse: x.rmse(Metric::Lowpass),
            gain: default.map(|d| model::gain(&d.side(m), &x.side(m))),
            behind_best: r
                .ranked
                .first()
                .filter(|b| b.row != x.row)
                .map(|b| model::behind(&b.side(m), &x.side(m))),
        })
        .collect()
}

impl Answer {
    /// The sweep's answer, every finalist interpolated.
    pub fn interpolated(ranking: Ranking, lowpass: Ranking) -> Self {
        let b = ranking.budget_s;
        let finalists =
            finalists(&ranking, &lowpass).into_iter().map(|a| Candidate::interpolated(a, b)).collect();
        let (ranking_scores, lowpass_scores) = (rank_scores(&ranking), rank_scores(&lowpass));
        Self::sorted(Self {
            budget_s: b,
            ranking,
            lowpass,
            measured: false,
            finalists,
            session_ratio: 1.0,
            scores: Vec::new(),
            ranking_scores,
            lowpass_scores,
        })
    }

    /// The answer from the finalists' measurements: `records(row, rays)` are a configuration's
    /// records at a ray count, of which `replicates` are wanted. Each finalist is shipped at the
    /// most of its `counts` whose measured time fits the budget (`Candidate::fits`; the fewest if
    /// none does).
    /// Interpolated when any finalist lacks records (nothing was rendered for this budget).
    pub fn measure<'r>(
        self,
        records: &dyn Fn(Row, u32) -> Vec<&'r JobResult>,
        replicates: usize,
        session_ratio: f64,
    ) -> Self {
        let budget = self.budget_s;
        let measured: Option<Vec<Candidate>> = finalists(&self.ranking, &self.lowpass)
            .into_iter()
            .map(|a| {
                let mut at: Vec<Candidate> = counts(a)
                    .into_iter()
                    .map(|n| {
                        let rs = records(a.row, n);
                        if rs.len() < replicates { None } else { Candidate::measured(a, n, &rs) }
                    })
                    .collect::<Option<_>>()?;
                let pick = at.iter().position(|c| c.fits(budget, session_ratio)).unwrap_or(at.len() - 1);
                let mut c = at.remove(pick);
                c.others = at.iter().map(|o| (o.rays, o.time_s, o.mean_mse(Metric::Rmse).value)).collect();
                Some(c)
            })
            .collect();
        match measured {
            Some(finalists) if !finalists.is_empty() => {
                Self::sorted(Self { measured: true, finalists, session_ratio, ..self })
            }
            _ => self,
        }
    }

    /// The finalists least MSE first, and what is said of each (`Scored`).
    fn sorted(mut self) -> Self {
        let m = |c: &Candidate| c.mean_mse(Metric::Rmse).value;
        self.finalists.sort_by(|a, b| m(a).total_cmp(&m(b)));
        let gain =
            |c: &Candidate, m: Metric| self.paper_default().map(|d| model::gain(&d.side(m), &c.side(m)));
        let best = self.recommended().map(|b| b.side(Metric::Rmse));
        self.scores = self
            .finalists
            .iter()
            .map(|c| Scored {
                time_ms: Estimate { value: c.time_s * 1e3, se: c.time_s * 1e3 * c.time_sigma_ln_total() },
                rmse: c.rmse(Metric::Rmse),
                lowpass_rmse: c.rmse(Metric::Lowpass),
                gain: gain(c, Metric::Rmse),
                lowpass_gain: gain(c, Metric::Lowpass),
                behind: best.filter(|b| b.row != c.row).map(|b| model::behind(&b, &c.side(Metric::Rmse))),
            })
            .collect();
        self
    }

    /// What is said of `c`, one of this answer's finalists.
    pub fn score(&self, c: &Candidate) -> &Scored {
        let i = self.finalists.iter().position(|f| f.row == c.row).expect("a finalist of this answer");
        &self.scores[i]
    }

    /// What to ship: the finalist with the least MSE whose error is not structured, because a
    /// sampler with visible bands or moiré is not an answer a renderer can ship however low its
    /// RMSE; the least overall when every one is structured.
    pub fn recommended(&self) -> Option<&Candidate> {
        self.finalists.iter().find(|c| !c.structured()).or_else(|| self.finalists.first())
    }

    /// The next finalist after the recommendation whose error is not structured; when every
    /// finalist's is structured (the recommendation then is too), the next finalist, so that the
    /// runner-up is never left blank while there is one.
    pub fn runner_up(&self) -> Option<&Candidate> {
        let best = self.recommended()?.row;
        let other = |c: &&Candidate| c.row != best;
        self.finalists.iter().filter(other).find(|c| !c.structured()).or_else(|| {
            self.recommended().filter(|b| b.structured()).and_then(|_| self.finalists.iter().find(other))
        })
    }

    /// The least-MSE finalist when it is structured and so not recommended.
    pub fn least_structured(&self) -> Option<&Candidate> {
        let best = self.recommended()?.row;
        self.finalists.first().filter(|c| c.row != best)
    }

    pub fn paper_default(&self) -> Option<&Candidate> {
        self.finalists.iter().find(|c| c.row == PAPER_DEFAULT)
    }

    /// The finalist with the least low-pass MSE.
    pub fn best_lowpass(&self) -> Option<&Candidate> {
        let m = |c: &&Candidate| c.mean_mse(Metric::Lowpass).value;
        self.finalists.iter().min_by(|a, b| m(a).total_cmp(&m(b)))
    }

    /// Whether `c`'s measured time fits this budget (`Candidate::fits`).
    pub fn fits(&self, c: &Candidate) -> bool {
        c.fits(self.budget_s, self.session_ratio)
    }
}

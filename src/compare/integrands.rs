//! The integrand verdicts, as plain data (`report::run::integrands` words them): the paper's three
//! statements about which distribution suits which integrand, each against its closed-form theory
//! (`Integrand::closed_room_variance`, the per-ray variance where every ray is blocked) and its
//! measured margin on every scene of a run with `integrands`: the paired difference of RMSE over
//! the replicates (`margin::paired`; replicate r shares its seed across distributions), with
//! pseudo-random numbers at `RAYS` rays (the independent rays the theory is about). Positive: the
//! statement holds on that scene.
//!
//! The infinite-variance cells (sine-cosine and concentric-cosine on unweighted visibility, weight
//! 1/(2 cos θ)) are never ranked: they are listed with the fitted slope of log RMSE against log
//! rays of a sweep that measured them (`stats::loglog_fit`), beside the matched distribution's. And
//! the Fibonacci lattice's gain per integrand: RMSE with pseudo-random numbers over RMSE with the
//! lattice (per-pixel seed) for the integrand's matched distribution.

use crate::compare::margin::{Margin, paired};
use crate::results::JobResult;
use crate::sampling::{Distribution, Integrand, SeedMode, Sequence};
use crate::spec::Row;

/// The ray count the verdicts are read at (the paper's largest table column).
pub const RAYS: u32 = 32;

/// One statement tested on one integrand: `better` has less error than `worse`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Statement {
    pub paper: &'static str,
    pub integrand: Integrand,
    pub better: Distribution,
    pub worse: Distribution,
}

const POLE: &str = "uniform in the angles crowds points at the pole: suits functions largest at the pole";
const EVEN: &str = "sine spreads points evenly: suits functions equal in every direction";
const BETWEEN: &str =
    "sine-cosine thins out towards the horizon: suits functions largest between pole and horizon";

/// The statements as the integrands test them: a sharp lobe for the pole, unweighted visibility for
/// "every direction", AO and a wide lobe for sine-cosine (the wide lobe, against uniform, is the
/// crossover's other side). Sine-cosine on visibility is the infinite cell: not a ranking.
pub const STATEMENTS: [Statement; 6] = [
    s(POLE, Integrand::CosLobe(32), Distribution::Uniform, Distribution::SineCosine),
    s(POLE, Integrand::CosLobe(32), Distribution::Uniform, Distribution::Sine),
    s(EVEN, Integrand::Visibility, Distribution::Sine, Distribution::Uniform),
    s(BETWEEN, Integrand::Ao, Distribution::SineCosine, Distribution::Uniform),
    s(BETWEEN, Integrand::Ao, Distribution::SineCosine, Distribution::Sine),
    s(BETWEEN, Integrand::CosLobe(4), Distribution::SineCosine, Distribution::Uniform),
];

const fn s(
    paper: &'static str,
    integrand: Integrand,
    better: Distribution,
    worse: Distribution,
) -> Statement {
    Statement { paper, integrand, better, worse }
}

/// The name a scene is measured under for an integrand (`SceneRef::integrand`).
pub fn scene_name(base: &str, integrand: Integrand) -> String {
    if integrand == Integrand::Ao { base.to_string() } else { format!("{base}-{integrand}") }
}

/// Of the scenes `bases` (their own names: those measured under AO), the one a record of
/// integrand `i` names `scene`: built forwards by `scene_name`, never cut out of the name (`None`
/// when no base gives `scene`).
fn base_name<'a>(scene: &str, i: Integrand, bases: &[&'a str]) -> Option<&'a str> {
    bases.iter().copied().find(|b| scene_name(b, i) == scene)
}

/// A record's integrand, typed: its `Measurement`'s (`None` for a record whose measurement does
/// not parse, which no statement reads).
fn integrand(r: &JobResult) -> Option<Integrand> {
    r.measurement().map(|m| m.integrand)
}

/// The scenes measured under AO and another integrand, by their own names, in record order.
pub fn scenes(results: &[JobResult]) -> Vec<String> {
    let mut bases: Vec<&str> = Vec::new();
    for r in results.iter().filter(|r| integrand(r) == Some(Integrand::Ao)) {
        if !bases.contains(&r.scene.as_str()) {
            bases.push(&r.scene);
        }
    }
    let mut out: Vec<String> = Vec::new();
    for r in results {
        let Some(i) = integrand(r).filter(|i| *i != Integrand::Ao) else { continue };
        if let Some(base) = base_name(&r.scene, i, &bases)
            && !out.iter().any(|b| b == base)
        {
            out.push(base.to_string());
        }
    }
    out
}

/// (replicate, RMSE) of one configuration.
pub fn values(results: &[JobResult], scene: &str, i: Integrand, row: Row, rays: u32) -> Vec<(u32, f64)> {
    let name = scene_name(scene, i);
    results
        .iter()
        .filter(|r| integrand(r) == Some(i) && r.is(&name, row, rays))
        .map(|r| (r.replicate, r.rmse))
        .collect()
}

fn random(d: Distribution) -> Row {
    Row::new(d, Sequence::Random, SeedMode::Rotation)
}

fn mean(v: &[(u32, f64)]) -> f64 {
    v.iter().map(|x| x.1).sum::<f64>() / v.len() as f64
}

/// The measured margin of a statement on a scene (`better` first: positive when it holds), paired
/// by replicate (`margin::paired`); `None` below two pairs.
pub fn margin(results: &[JobResult], scene: &str, st: &Statement, rays: u32) -> Option<Margin> {
    let b = values(results, scene, st.integrand, random(st.better), rays);
    let w = values(results, scene, st.integrand, random(st.worse), rays);
    paired(&b, &w).measured()
}

/// Fitted slope of log mean RMSE against log rays over every ray count measured (least squares,
/// `stats::loglog_fit`); `None` below three ray counts.
pub fn slope(results: &[JobResult], scene: &str, i: Integrand, row: Row) -> Option<f64> {
    let mut rays: Vec<u32> = results
        .iter()
        .filter(|r| integrand(r) == Some(i) && r.scene == scene_name(scene, i) && r.is_row(row))
        .map(|r| r.rays)
        .collect();
    rays.sort_unstable();
    rays.dedup();
    let (x, y): (Vec<f64>, Vec<f64>) = rays
        .iter()
        .map(|&n| (n, values(results, scene, i, row, n)))
        .filter(|(_, v)| !v.is_empty())
        .map(|(n, v)| (n as f64, mean(&v)))
        .unzip();
    if x.len() < 3 {
        return None;
    }
    crate::stats::loglog_fit(&x, &y).map(|f| f.slope)
}

/// The integrands measured, in the order of `Integrand`'s.
fn integrands(results: &[JobResult]) -> Vec<Integrand> {
    let mut v: Vec<Integrand> = results.iter().filter_map(integrand).collect();
    v.sort();
    v.dedup();
    v
}

/// A statement on one scene at `RAYS` rays: its margin and the two mean RMSEs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    pub margin: Margin,
    pub better: f64,
    pub worse: f64,
}

/// A statement with its closed-form per-ray variances (better's, worse's) and its cell per scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Judged {
    pub statement: Statement,
    pub theory: (f64, f64),
    pub cells: Vec<Option<Cell>>,
}

/// An infinite-variance cell (`distribution` on `integrand`): per scene the fitted slopes of it
/// and of the integrand's matched distribution.
#[derive(Debug, Clone, PartialEq)]
pub struct Infinite {
    pub integrand: Integrand,
    pub distribution: Distribution,
    pub matched: Distribution,
    pub slopes: Vec<(Option<f64>, Option<f64>)>,
}

/// An integrand's Fibonacci gain: its matched distribution, and per scene the mean RMSE with
/// pseudo-random numbers over the lattice's (per-pixel seed) at `RAYS` rays.
#[derive(Debug, Clone, PartialEq)]
pub struct LatticeGain {
    pub integrand: Integrand,
    pub matched: Distribution,
    pub gains: Vec<Option<f64>>,
}

/// Everything the integrand tables say, over the scenes measured under more than one integrand.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdicts {
    pub scenes: Vec<String>,
    /// The statements the first scene measured.
    pub statements: Vec<Judged>,
    pub infinite: Vec<Infinite>,
    pub gains: Vec<LatticeGain>,
}

/// The integrand verdicts; `None` when the run measured a single integrand.
pub fn verdicts(results: &[JobResult]) -> Option<Verdicts> {
    let scenes = scenes(results);
    if scenes.is_empty() {
        return None;
    }
    let cell = |scene: &str, st: &Statement| {
        margin(results, scene, st, RAYS).map(|m| Cell {
            margin: m,
            better: mean(&values(results, scene, st.integrand, random(st.better), RAYS)),
            worse: mean(&values(results, scene, st.integrand, random(st.worse), RAYS)),
        })
    };
    let statements = STATEMENTS
        .iter()
        .filter(|st| !values(results, &scenes[0], st.integrand, random(st.better), RAYS).is_empty())
        .map(|st| {
            let v = |d| st.integrand.closed_room_variance(d);
            Judged {
                statement: *st,
                theory: (v(st.better), v(st.worse)),
                cells: scenes.iter().map(|sc| cell(sc, st)).collect(),
            }
        })
        .collect();
    let mut infinite = Vec::new();
    for i in integrands(results) {
        for &d in Distribution::ALL.iter().filter(|d| i.closed_room_variance(**d).is_infinite()) {
            let matched = i.matched_distribution();
            let slopes = scenes
                .iter()
                .map(|sc| (slope(results, sc, i, random(d)), slope(results, sc, i, random(matched))))
                .collect();
            infinite.push(Infinite { integrand: i, distribution: d, matched, slopes });
        }
    }
    let lattice = |d| Row::new(d, Sequence::Fibonacci, SeedMode::Rotation);
    let gains = integrands(results)
        .into_iter()
        .map(|i| {
            let d = i.matched_distribution();
            let gains = scenes
                .iter()
                .map(|sc| {
                    let (r, f) =
                        (values(results, sc, i, random(d), RAYS), values(results, sc, i, lattice(d), RAYS));
                    (!r.is_empty() && !f.is_empty()).then(|| mean(&r) / mean(&f))
                })
                .collect();
            LatticeGain { integrand: i, matched: d, gains }
        })
        .collect();
    Some(Verdicts { scenes, statements, infinite, gains })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base_name_inverts_scene_name_for_every_integrand() {
        let bases = ["kitchen", "cornell-box", "a-visibility"];
        for i in [Integrand::Ao, Integrand::Visibility, Integrand::CosLobe(4), Integrand::CosLobe(32)] {
            for base in bases {
                assert_eq!(base_name(&scene_name(base, i), i, &bases), Some(base), "{base} under {i}");
            }
        }
        // A name that no base gives under the integrand is no scene measured under it.
        assert_eq!(base_name("kitchen", Integrand::Visibility, &bases), None);
        assert_eq!(base_name("kitchen-cos-lobe-4", Integrand::CosLobe(32), &bases), None);
        assert_eq!(base_name("kitchenvisibility", Integrand::Visibility, &bases), None);
        assert_eq!(
            base_name("sponza-visibility", Integrand::Visibility, &bases),
            None,
            "not measured under AO"
        );
    }
}

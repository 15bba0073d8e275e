//! The integrand verdicts (issue 27): the paper's three statements about which distribution suits
//! which integrand, each against its closed-form theory (`Integrand::closed_room_variance`, the
//! per-ray variance where every ray is blocked) and its measured margin on every scene of a run
//! with `integrands`: the paired difference of RMSE over the replicates (replicate r shares its
//! seed across distributions), in standard errors, with pseudo-random numbers at `RAYS` rays (the
//! independent rays the theory is about). Positive: the statement holds on that scene.
//!
//! The infinite-variance cells (sine-cosine and concentric-cosine on unweighted visibility, weight
//! 1/(2 cos θ)) are never ranked: they are listed with the fitted slope of log RMSE against log
//! rays of a sweep that measured them, beside the matched distribution's. And the Fibonacci
//! lattice's gain per integrand: RMSE with pseudo-random numbers over RMSE with the lattice
//! (per-pixel seed) for the integrand's matched distribution.

use crate::compare::claims::{self, Margin};
use crate::report::Table;
use crate::results::JobResult;
use crate::sampling::{Distribution, Integrand, SeedMode, Sequence};
use crate::spec::Row;
use std::fmt::Write as _;

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

/// The scenes measured under more than one integrand, by their own names, in record order.
pub fn scenes(results: &[JobResult]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for r in results.iter().filter(|r| r.integrand != "ao") {
        if let Some(base) = r.scene.strip_suffix(&format!("-{}", r.integrand))
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
    let i = i.to_string();
    results
        .iter()
        .filter(|r| r.integrand == i && r.is(&name, row, rays))
        .map(|r| (r.replicate, r.rmse))
        .collect()
}

fn random(d: Distribution) -> Row {
    Row::new(d, Sequence::Random, SeedMode::Rotation)
}

fn mean(v: &[(u32, f64)]) -> f64 {
    v.iter().map(|x| x.1).sum::<f64>() / v.len() as f64
}

/// The measured margin of a statement on a scene (`better` first: positive when it holds).
pub fn margin(results: &[JobResult], scene: &str, st: &Statement, rays: u32) -> Option<Margin> {
    let b = values(results, scene, st.integrand, random(st.better), rays);
    let w = values(results, scene, st.integrand, random(st.worse), rays);
    claims::paired(&b, &w)
}

fn theory(st: &Statement) -> String {
    let v = |d| st.integrand.closed_room_variance(d);
    format!("per-ray variance {:.3} < {:.3}", v(st.better), v(st.worse))
}

fn cell(results: &[JobResult], scene: &str, st: &Statement) -> String {
    match margin(results, scene, st, RAYS) {
        Some(m) => {
            let b = mean(&values(results, scene, st.integrand, random(st.better), RAYS));
            let w = mean(&values(results, scene, st.integrand, random(st.worse), RAYS));
            format!("{:+.1} SE ({b:.4} vs {w:.4})", m.in_se())
        }
        None => "–".into(),
    }
}

/// Fitted slope of log mean RMSE against log rays over every ray count measured (least squares).
pub fn slope(results: &[JobResult], scene: &str, i: Integrand, row: Row) -> Option<f64> {
    let mut rays: Vec<u32> = results
        .iter()
        .filter(|r| r.integrand == i.to_string() && r.scene == scene_name(scene, i) && r.is_row(row))
        .map(|r| r.rays)
        .collect();
    rays.sort_unstable();
    rays.dedup();
    let pts: Vec<(f64, f64)> = rays
        .iter()
        .map(|&n| (n, values(results, scene, i, row, n)))
        .filter(|(_, v)| !v.is_empty())
        .map(|(n, v)| ((n as f64).ln(), mean(&v).ln()))
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let k = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / k, pts.iter().map(|p| p.1).sum::<f64>() / k);
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    Some(sxy / sxx)
}

/// The integrands measured, in the order of `Integrand`'s.
fn integrands(results: &[JobResult]) -> Vec<Integrand> {
    let mut v: Vec<Integrand> = results.iter().filter_map(|r| Integrand::parse(&r.integrand).ok()).collect();
    v.sort();
    v.dedup();
    v
}

/// The three tables (verdicts, infinite cells, Fibonacci gain) as rows of text; empty when the run
/// measured a single integrand.
fn rows(results: &[JobResult]) -> Vec<(String, Vec<String>, Vec<Vec<String>>)> {
    let scenes = scenes(results);
    if scenes.is_empty() {
        return Vec::new();
    }
    let mut header = vec!["the paper's statement".to_string(), "closed-form theory".to_string()];
    header.extend(scenes.iter().map(|s| format!("{s}: margin, RMSE at {RAYS} rays")));
    let verdicts = STATEMENTS
        .iter()
        .filter(|st| !values(results, &scenes[0], st.integrand, random(st.better), RAYS).is_empty())
        .map(|st| {
            let mut row =
                vec![format!("{} — {}: {} < {}", st.paper, st.integrand, st.better, st.worse), theory(st)];
            row.extend(scenes.iter().map(|sc| cell(results, sc, st)));
            row
        })
        .collect();
    let mut infinite = Vec::new();
    for i in integrands(results) {
        for &d in Distribution::ALL.iter().filter(|d| i.closed_room_variance(**d).is_infinite()) {
            let mut row = vec![format!("{d} on {i} (weight unbounded: not ranked)")];
            let matched = i.matched_distribution();
            for sc in &scenes {
                let f = |d| slope(results, sc, i, random(d)).map_or("–".into(), |k| format!("{k:+.2}"));
                row.push(format!("{} (matched {matched}: {})", f(d), f(matched)));
            }
            infinite.push(row);
        }
    }
    let mut gains = Vec::new();
    for i in integrands(results) {
        let d = i.matched_distribution();
        let mut row = vec![format!("{i} ({d})")];
        for sc in &scenes {
            let r = values(results, sc, i, random(d), RAYS);
            let f = values(results, sc, i, Row::new(d, Sequence::Fibonacci, SeedMode::Rotation), RAYS);
            row.push(if r.is_empty() || f.is_empty() {
                "–".into()
            } else {
                format!("× {:.2}", mean(&r) / mean(&f))
            });
        }
        gains.push(row);
    }
    let scene_cols = |first: &str| {
        let mut h = vec![first.to_string()];
        h.extend(scenes.iter().cloned());
        h
    };
    let mut out = vec![(
        "Integrands: the paper's statements, theory and measured margins".to_string(),
        header,
        verdicts,
    )];
    if !infinite.is_empty() {
        out.push((
            "Integrands: infinite-variance cells, fitted slope of RMSE against rays (−0.5 for finite variance)".into(),
            scene_cols("cell"),
            infinite,
        ));
    }
    out.push((
        format!("Integrands: the Fibonacci lattice's gain, RMSE pseudo-random / Fibonacci per-pixel seed at {RAYS} rays"),
        scene_cols("integrand (matched distribution)"),
        gains,
    ));
    out
}

/// The report's tables (none for a run of one integrand).
pub fn tables(results: &[JobResult]) -> Vec<Table> {
    rows(results).into_iter().map(|(title, header, rows)| Table { title, header, rows }).collect()
}

/// The same tables in Markdown, for `quotes.md` (empty for a run of one integrand).
pub fn markdown(results: &[JobResult]) -> String {
    let mut s = String::new();
    for (title, header, rows) in rows(results) {
        let _ = writeln!(s, "{title}:\n");
        let _ = writeln!(s, "| {} |", header.join(" | "));
        let _ = writeln!(s, "|{}", "---|".repeat(header.len()));
        for r in rows {
            let _ = writeln!(s, "| {} |", r.join(" | "));
        }
        s.push('\n');
    }
    s
}

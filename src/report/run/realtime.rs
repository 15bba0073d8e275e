//! The real-time verdicts (issue 26): the records of a spec's `frames`/`pipelines`/`schedules`
//! groups (`JobResult::is_single_frame` false, plus the raw frame-1 records beside them) read as
//! two questions, with measured margins and their standard errors. (1) After each pipeline, at its
//! last measured frame, does the paper's sine-cosine × Fibonacci × per-pixel seed (independent
//! schedule) still have the least error of every configuration measured with it? (2) Under the
//! EMA pipelines, does spatiotemporal blue noise (Wolfe, Morrical & Ramamoorthi 2022) beat the 2-D
//! blue-noise mask drawn afresh each frame (the same sequence, the independent schedule), as its
//! paper reports for AO?
//!
//! Both are read on the RMSE against the reference (what the user sees) and on the noise RMSE
//! against the equally filtered reference (`noise_rmse`): after a spatial filter the first holds the
//! filter's bias, which is the same for every sampler, so a small margin there with a large one in
//! the noise part says the filter, not the sampler, sets the error. A margin is the paired
//! difference over replicates (replicate i of every configuration shares its seed), relative to the
//! paper's (or blue noise's) mean, with its standard error; a verdict is called only beyond
//! Student's t at 5 % two-sided, else "tie". The "best other" is the least mean of many, so its
//! margin is biased towards it (the winner's curse): a tie there is a tie.

use crate::report::Table;
use crate::results::JobResult;
use crate::stats::{mean_and_standard_error, paired_difference, student_t_quantile};
use std::collections::BTreeMap;

/// One record's errors: (replicate, RMSE against the reference, against the filtered reference).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Measured {
    replicate: u32,
    rmse: f64,
    noise: f64,
}

/// (scene, rays, pipeline, frame) → configuration label (`distribution/sequence/seed_mode/schedule`)
/// → its replicates, in replicate order.
type Cells<'a> = BTreeMap<(&'a str, u32, &'a str, u32), BTreeMap<String, Vec<Measured>>>;

fn cells(results: &[JobResult]) -> Cells<'_> {
    let mut out: Cells = BTreeMap::new();
    for r in results {
        let label = format!("{}/{}/{}/{}", r.distribution, r.sequence, r.seed_mode, r.schedule);
        out.entry((&r.scene, r.rays, &r.pipeline, r.frame))
            .or_default()
            .entry(label)
            .or_default()
            .push(Measured { replicate: r.replicate, rmse: r.rmse, noise: r.noise_rmse });
    }
    for configs in out.values_mut() {
        configs.values_mut().for_each(|v| v.sort_by_key(|m| m.replicate));
    }
    out
}

/// The paper's configuration, as `cells` labels it.
pub const PAPER: &str = "sine-cosine/fibonacci/rotation/independent";

/// Whether the spec measured anything real-time (more than one frame, schedule or pipeline).
pub fn any(results: &[JobResult]) -> bool {
    results.iter().any(|r| !r.is_single_frame())
}

/// `b` against `a` over the replicates both have: b̄/ā − 1 and its standard error (the paired
/// difference's, over ā), and the verdict at 5 % two-sided.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Margin {
    pub relative: f64,
    pub se: f64,
    pub pairs: usize,
}

impl Margin {
    fn of(a: &[Measured], b: &[Measured], value: fn(&Measured) -> f64) -> Self {
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        for m in a {
            if let Some(n) = b.iter().find(|n| n.replicate == m.replicate) {
                xs.push(value(m));
                ys.push(value(n));
            }
        }
        let (d, se) = paired_difference(&xs, &ys);
        let (mean_a, _) = mean_and_standard_error(&xs);
        Self { relative: d / mean_a, se: se / mean_a, pairs: xs.len() }
    }

    /// +1: `b` has more error than `a` beyond the 5 % critical t; −1: less; 0: a tie (or too few pairs).
    pub fn sign(&self) -> i32 {
        if self.pairs < 2 || !self.se.is_finite() {
            return 0;
        }
        let crit = student_t_quantile(0.05, self.pairs as f64 - 1.0);
        let t = if self.se > 0.0 { self.relative / self.se } else { self.relative.signum() * f64::INFINITY };
        if t > crit {
            1
        } else if t < -crit {
            -1
        } else {
            0
        }
    }

    fn text(&self) -> String {
        format!("{:+.1} ± {:.1} %", 100.0 * self.relative, 100.0 * self.se)
    }
}

fn pm(v: &[Measured], value: fn(&Measured) -> f64) -> String {
    let (m, se) = mean_and_standard_error(&v.iter().map(value).collect::<Vec<_>>());
    if se.is_finite() { format!("{m:.4} ± {se:.4}") } else { format!("{m:.4}") }
}

fn mean_rmse(v: &[Measured]) -> f64 {
    v.iter().map(|m| m.rmse).sum::<f64>() / v.len() as f64
}

const RMSE: fn(&Measured) -> f64 = |m| m.rmse;
const NOISE: fn(&Measured) -> f64 = |m| m.noise;

/// The verdict column's words for `sign` (of b against a): b more error → a wins.
fn verdict(sign: i32, a: &str, b: &str) -> String {
    match sign {
        1 => format!("{a} wins"),
        -1 => format!("{b} wins"),
        _ => "tie".into(),
    }
}

/// Question (1): one row per (scene, rays, pipeline at its last frame): the paper's RMSE, the best
/// other estimator and its RMSE, both margins (best other against the paper: positive, the
/// paper's has less error) and the verdict on the RMSE.
pub fn paper_table(results: &[JobResult]) -> Option<Table> {
    if !any(results) {
        return None;
    }
    let cells = cells(results);
    let last = |scene: &str, rays: u32, p: &str| {
        cells.keys().filter(|k| k.0 == scene && k.1 == rays && k.2 == p).map(|k| k.3).max()
    };
    let mut rows = Vec::new();
    for (&(scene, rays, pipeline, frame), configs) in &cells {
        if Some(frame) != last(scene, rays, pipeline) {
            continue;
        }
        let Some(paper) = configs.get(PAPER) else { continue };
        // Other estimators only: the paper's under another schedule is still the paper's (and at
        // frame 1 the very same image).
        let estimator = |l: &str| l.rsplit_once('/').map_or("", |x| x.0).to_string();
        let others = configs.iter().filter(|(l, _)| estimator(l) != estimator(PAPER));
        let Some((best, b)) = others.min_by(|x, y| mean_rmse(x.1).total_cmp(&mean_rmse(y.1))) else {
            continue;
        };
        let (m, n) = (Margin::of(paper, b, RMSE), Margin::of(paper, b, NOISE));
        rows.push(vec![
            scene.to_string(),
            rays.to_string(),
            format!("{pipeline} (frame {frame})"),
            pm(paper, RMSE),
            best.clone(),
            pm(b, RMSE),
            m.text(),
            n.text(),
            verdict(m.sign(), "paper", "best other"),
            verdict(n.sign(), "paper", "best other"),
        ]);
    }
    Some(Table {
        title: "Real-time: does sine-cosine × Fibonacci × per-pixel seed still win after the pipeline?"
            .into(),
        header: [
            "scene",
            "rays/frame",
            "pipeline",
            "paper's RMSE",
            "best other",
            "its RMSE",
            "margin (RMSE)",
            "margin (noise RMSE)",
            "verdict (RMSE, 5 %)",
            "verdict (noise RMSE)",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// Question (2): under every accumulating pipeline at its last frame, per (scene, rays, sequence,
/// distribution): RMSE with `stbn` against RMSE with per-frame-independent `blue-noise`.
pub fn stbn_table(results: &[JobResult]) -> Option<Table> {
    let cells = cells(results);
    let mut rows = Vec::new();
    for (&(scene, rays, pipeline, frame), configs) in &cells {
        if !pipeline.starts_with("ema") && !pipeline.starts_with("mean") {
            continue;
        }
        if cells.keys().any(|k| k.0 == scene && k.1 == rays && k.2 == pipeline && k.3 > frame) {
            continue;
        }
        for (label, bn) in configs {
            let Some(prefix) = label.strip_suffix("/blue-noise/independent") else { continue };
            let Some(st) = configs.get(&format!("{prefix}/stbn/independent")) else { continue };
            let (m, n) = (Margin::of(bn, st, RMSE), Margin::of(bn, st, NOISE));
            rows.push(vec![
                scene.to_string(),
                rays.to_string(),
                format!("{pipeline} (frame {frame})"),
                prefix.to_string(),
                pm(bn, RMSE),
                pm(st, RMSE),
                m.text(),
                n.text(),
                verdict(m.sign(), "blue noise", "stbn"),
                verdict(n.sign(), "blue noise", "stbn"),
            ]);
        }
    }
    (!rows.is_empty()).then(|| Table {
        title: "Real-time: does spatiotemporal blue noise beat per-frame-independent blue noise under EMA?"
            .into(),
        header: [
            "scene",
            "rays/frame",
            "pipeline",
            "distribution/sequence",
            "blue-noise RMSE",
            "stbn RMSE",
            "stbn against blue noise (RMSE)",
            "(noise RMSE)",
            "verdict (RMSE, 5 %)",
            "verdict (noise RMSE)",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// At the fewest rays per frame, under every accumulating pipeline at its last frame: the noise
/// RMSE of each sequence with a per-pixel rotation, the 2-D blue-noise offsets and spatiotemporal
/// blue noise (independent schedule). A rotation leaves a lattice's elevations where they are, so
/// with one or two points per pixel no number of frames moves them: its accumulated image keeps a
/// bias that an offset, new each frame, averages away.
pub fn seeds_table(results: &[JobResult]) -> Option<Table> {
    let cells = cells(results);
    let fewest = cells.keys().filter(|k| k.2 != "raw").map(|k| k.1).min()?;
    let mut rows = Vec::new();
    for (&(scene, rays, pipeline, frame), configs) in &cells {
        let accumulating = pipeline.starts_with("ema") || pipeline.starts_with("mean");
        if rays != fewest || !accumulating {
            continue;
        }
        if cells.keys().any(|k| k.0 == scene && k.1 == rays && k.2 == pipeline && k.3 > frame) {
            continue;
        }
        for (label, rot) in configs {
            let Some(prefix) = label.strip_suffix("/rotation/independent") else { continue };
            let get = |mode: &str| configs.get(&format!("{prefix}/{mode}/independent"));
            let (Some(bn), Some(st)) = (get("blue-noise"), get("stbn")) else { continue };
            rows.push(vec![
                scene.to_string(),
                format!("{pipeline} (frame {frame})"),
                prefix.to_string(),
                pm(rot, NOISE),
                pm(bn, NOISE),
                pm(st, NOISE),
                Margin::of(rot, bn, NOISE).text(),
            ]);
        }
    }
    let per = if fewest == 1 { "ray" } else { "rays" };
    (!rows.is_empty()).then(|| Table {
        title: format!(
            "Real-time at {fewest} {per} per frame: the noise left after accumulation, by seed mode"
        ),
        header: [
            "scene",
            "pipeline",
            "distribution/sequence",
            "rotation",
            "blue-noise",
            "stbn",
            "blue-noise against rotation",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// How many of `rows` have each verdict in column `col`: (first named wins, tie, second named wins).
fn tally(rows: &[&Vec<String>], col: usize, first: &str) -> (usize, usize, usize) {
    let wins = rows.iter().filter(|r| r[col] == format!("{first} wins")).count();
    let ties = rows.iter().filter(|r| r[col] == "tie").count();
    (wins, ties, rows.len() - wins - ties)
}

/// Per pipeline (at its last frame), how often the paper's configuration wins, ties and loses, and
/// the median margins: the short form the README quotes.
pub fn summary_table(results: &[JobResult]) -> Option<Table> {
    let t = paper_table(results)?;
    let mut by: BTreeMap<String, Vec<&Vec<String>>> = BTreeMap::new();
    for r in &t.rows {
        by.entry(r[2].clone()).or_default().push(r);
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        if v.is_empty() { f64::NAN } else { (v[(v.len() - 1) / 2] + v[v.len() / 2]) / 2.0 }
    };
    let pct = |s: &str| s.split_whitespace().next().and_then(|x| x.parse::<f64>().ok()).unwrap_or(f64::NAN);
    let rows = by
        .into_iter()
        .map(|(pipeline, rs)| {
            let (w, t, l) = tally(&rs, 8, "paper");
            let (nw, nt, nl) = tally(&rs, 9, "paper");
            let mut m: Vec<f64> = rs.iter().map(|r| pct(&r[6])).collect();
            let mut n: Vec<f64> = rs.iter().map(|r| pct(&r[7])).collect();
            vec![
                pipeline,
                rs.len().to_string(),
                format!("{w} / {t} / {l}"),
                format!("{:+.1} %", median(&mut m)),
                format!("{nw} / {nt} / {nl}"),
                format!("{:+.1} %", median(&mut n)),
            ]
        })
        .collect();
    Some(Table {
        title: "Real-time, in short: the paper's configuration against the best other, per pipeline".into(),
        header: [
            "pipeline",
            "cells",
            "RMSE: paper wins / tie / best other wins",
            "median margin",
            "noise RMSE: paper wins / tie / best other wins",
            "median margin",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// One sentence per question: in how many cells each verdict was reached, on the RMSE and on the
/// noise RMSE.
pub fn text(results: &[JobResult]) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(t) = paper_table(results) {
        let rows: Vec<&Vec<String>> = t.rows.iter().collect();
        let ((w, tie, l), (nw, ntie, nl)) = (tally(&rows, 8, "paper"), tally(&rows, 9, "paper"));
        out.push(format!(
            "Real-time: after the pipeline, sine-cosine × Fibonacci × per-pixel seed has significantly less RMSE \
             than every other configuration in {w} of {} cells, ties the best other in {tie} and loses in {l}; \
             on the noise RMSE it wins {nw}, ties {ntie} and loses {nl} (scene × rays per frame × pipeline at \
             its last frame; 5 % two-sided, paired over replicates).",
            rows.len()
        ));
    }
    if let Some(t) = stbn_table(results) {
        let rows: Vec<&Vec<String>> = t.rows.iter().collect();
        let ((bn, tie, st), (nbn, ntie, nst)) =
            (tally(&rows, 8, "blue noise"), tally(&rows, 9, "blue noise"));
        out.push(format!(
            "Under EMA, spatiotemporal blue noise has significantly less RMSE than per-frame-independent blue \
             noise in {st} of {} cells, ties in {tie} and has more in {bn}; on the noise RMSE it has less in \
             {nst}, ties in {ntie} and has more in {nbn}.",
            rows.len()
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Distribution as D, SeedMode as M, Sequence as S};
    use crate::spec::Row;

    /// Two replicates of a configuration at `rmse` ± `d`.
    fn recs(seq: S, mode: M, pipeline: &str, frame: u32, rmse: f64, d: f64) -> Vec<JobResult> {
        (0..2)
            .map(|rep| {
                let v = rmse + if rep == 0 { -d } else { d };
                let mut r = JobResult::for_test("k", Row::new(D::SineCosine, seq, mode), 2, rep, v, 1.0);
                r.pipeline = pipeline.into();
                r.frame = frame;
                r.noise_rmse = v / 2.0;
                r
            })
            .collect()
    }

    #[test]
    fn verdicts_read_the_last_frame_and_say_the_margin_with_its_error() {
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
        let t = paper_table(&rs).unwrap();
        assert_eq!(t.rows.len(), 2, "{:?}", t.rows);
        assert_eq!(t.rows[0][2], "ema0.1+atrous (frame 16)");
        // Best other: stbn at 0.015 against 0.02; the paired differences are exactly −0.005 twice.
        assert_eq!(t.rows[0][3], "0.0200 ± 0.0010");
        assert_eq!((t.rows[0][6].as_str(), t.rows[0][8].as_str()), ("-25.0 ± 0.0 %", "best other wins"));
        assert_eq!(t.rows[0][9], "best other wins", "noise RMSE: the same halves");
        assert_eq!((t.rows[1][6].as_str(), t.rows[1][8].as_str()), ("+20.0 ± 0.0 %", "paper wins"));
        let s = stbn_table(&rs).unwrap();
        assert_eq!(s.rows.len(), 1);
        // stbn − blue noise: −0.016 and −0.014 → −50 % ± 3.3 % of 0.03: beyond t(1 dof) = 12.7 SE.
        assert_eq!((s.rows[0][6].as_str(), s.rows[0][8].as_str()), ("-50.0 ± 3.3 %", "stbn wins"));
        let sum = summary_table(&rs).unwrap();
        assert_eq!(sum.rows.len(), 2);
        assert_eq!(
            sum.rows[0][..4],
            ["ema0.1+atrous (frame 16)", "1", "0 / 0 / 1", "-25.0 %"].map(String::from)
        );
        let seeds = seeds_table(&rs);
        assert!(seeds.is_none(), "no rotation/blue-noise/stbn triple at the fewest rays");
        assert!(paper_table(&rs[..4]).is_none(), "single frames only: no section");
    }

    #[test]
    fn a_margin_within_the_critical_t_is_a_tie() {
        let m = |rep, rmse| Measured { replicate: rep, rmse, noise: rmse };
        let a = [m(0, 1.0), m(1, 1.0), m(2, 1.0)];
        // Differences 0.1, −0.05, 0.1: mean 0.05, se 0.05 → t 1 < t(2 dof, 5 %) = 4.3.
        let b = [m(0, 1.1), m(1, 0.95), m(2, 1.1)];
        let g = Margin::of(&a, &b, RMSE);
        assert!((g.relative - 0.05).abs() < 1e-12 && (g.se - 0.05).abs() < 1e-12, "{g:?}");
        assert_eq!(g.sign(), 0);
        // A replicate only one side has is left out.
        let b = [m(0, 2.0), m(1, 2.01), m(2, 1.99), m(3, 9.0)];
        assert_eq!(Margin::of(&a, &b, RMSE).pairs, 3);
        assert_eq!(Margin::of(&a, &b, RMSE).sign(), 1);
    }
}

//! The real-time verdicts as the page's and `quotes.md`'s tables and sentences: after each
//! pipeline, does the paper's configuration still win; under accumulation, does spatiotemporal blue
//! noise beat per-frame-independent blue noise; does what engines ship (their rotation patterns)
//! match the masks and the paper's; and the noise each seed mode leaves. The cells,
//! margins and verdicts are `compare::realtime`'s (paired over replicates, 5 % two-sided); this
//! file words and formats them.

use crate::compare::margin::Margin;
use crate::compare::model::Estimate;
use crate::compare::realtime::{engine_cells, paper_cells, seeds_cells, stbn_cells};
use crate::report::Table;
use crate::results::JobResult;
use std::collections::BTreeMap;

/// "+12.3 ± 1.4 %": a margin relative to its base, with its standard error.
fn margin_text(m: &Margin) -> String {
    format!("{:+.1} ± {:.1} %", 100.0 * m.relative(), 100.0 * m.relative_se())
}

/// "0.0123 ± 0.0004", or the mean alone when it has no error (one replicate).
fn pm(e: Estimate) -> String {
    if e.se.is_finite() { format!("{:.4} ± {:.4}", e.value, e.se) } else { format!("{:.4}", e.value) }
}

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
    let rows = paper_cells(results)?
        .into_iter()
        .map(|c| {
            vec![
                c.scene,
                c.rays.to_string(),
                format!("{} (frame {})", c.pipeline, c.frame),
                pm(c.paper),
                c.best,
                pm(c.best_rmse),
                margin_text(&c.rmse.margin),
                margin_text(&c.noise.margin),
                verdict(c.rmse.sign, "paper", "best other"),
                verdict(c.noise.sign, "paper", "best other"),
            ]
        })
        .collect();
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
    let rows: Vec<Vec<String>> = stbn_cells(results)
        .into_iter()
        .map(|c| {
            vec![
                c.scene,
                c.rays.to_string(),
                format!("{} (frame {})", c.pipeline, c.frame),
                c.prefix,
                pm(c.blue_noise),
                pm(c.stbn),
                margin_text(&c.rmse.margin),
                margin_text(&c.noise.margin),
                verdict(c.rmse.sign, "blue noise", "stbn"),
                verdict(c.noise.sign, "blue noise", "stbn"),
            ]
        })
        .collect();
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
/// RMSE each seed mode leaves (`compare::realtime::seeds_cells`).
pub fn seeds_table(results: &[JobResult]) -> Option<Table> {
    let (fewest, cells) = seeds_cells(results)?;
    let rows: Vec<Vec<String>> = cells
        .into_iter()
        .map(|c| {
            vec![
                c.scene,
                format!("{} (frame {})", c.pipeline, c.frame),
                c.prefix,
                pm(c.rotation),
                pm(c.blue_noise),
                pm(c.stbn),
                margin_text(&c.blue_noise_vs_rotation),
            ]
        })
        .collect();
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

/// Question (3): per (scene, rays, pipeline at its last frame), the best engine pattern's
/// configuration against the best of every other seed mode (`compare::realtime::engine_cells`).
pub fn engine_table(results: &[JobResult]) -> Option<Table> {
    let rows: Vec<Vec<String>> = engine_cells(results)
        .into_iter()
        .map(|c| {
            vec![
                c.scene,
                c.rays.to_string(),
                format!("{} (frame {})", c.pipeline, c.frame),
                c.engine,
                pm(c.engine_rmse),
                c.other,
                pm(c.other_rmse),
                margin_text(&c.rmse.margin),
                margin_text(&c.noise.margin),
                verdict(c.rmse.sign, "engine", "other"),
                verdict(c.noise.sign, "engine", "other"),
            ]
        })
        .collect();
    (!rows.is_empty()).then(|| Table {
        title: "Real-time: the best engine pattern (ign, bayer, magic-square, r2-dither) against the best other seed mode"
            .into(),
        header: [
            "scene",
            "rays/frame",
            "pipeline",
            "best engine pattern",
            "its RMSE",
            "best other",
            "its RMSE",
            "other against engine (RMSE)",
            "(noise RMSE)",
            "verdict (RMSE, 5 %)",
            "verdict (noise RMSE)",
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
    // The margins as the table prints them (to 0.1 %), so that the median is one of its cells.
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
    if let Some(t) = engine_table(results) {
        let rows: Vec<&Vec<String>> = t.rows.iter().collect();
        let ((e, tie, o), (ne, ntie, no)) = (tally(&rows, 9, "engine"), tally(&rows, 10, "engine"));
        out.push(format!(
            "The engines' rotation patterns: the best of them has significantly less RMSE than the best other \
             seed mode in {e} of {} cells, ties in {tie} and has more in {o}; on the noise RMSE less in {ne}, \
             ties in {ntie} and more in {no}.",
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
}

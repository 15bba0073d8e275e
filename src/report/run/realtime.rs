//! The real-time verdicts as the page's and `quotes.md`'s tables and sentences: after each
//! pipeline, does the paper's configuration still win; under accumulation, does spatiotemporal blue
//! noise beat per-frame-independent blue noise; does what engines ship (their rotation patterns)
//! match the masks and the paper's; and the noise each seed mode leaves. The cells,
//! margins and verdicts are `compare::realtime`'s (paired over replicates, 5 % two-sided); this
//! file words and formats them. Every cell shows each side's error split from its replicates: bias
//! (± its jackknife standard error) and noise; "—" where a configuration has one replicate (the
//! split is undefined there). An RMSE verdict that is the two sides' biases at work is printed as
//! a "bias interaction", never a win.

use crate::compare::margin::Margin;
use crate::compare::model::Estimate;
use crate::compare::realtime::{Parts, engine_cells, paper_cells, seeds_cells, stbn_cells};
use crate::report::Table;
use crate::results::JobResult;
use std::collections::BTreeMap;

/// "+12.3 ± 1.4 %": a margin relative to its base, with its standard error.
fn margin_text(m: &Margin) -> String {
    if !m.relative().is_finite() {
        return "—".into();
    }
    format!("{:+.1} ± {:.1} %", 100.0 * m.relative(), 100.0 * m.relative_se())
}

/// "0.0123 ± 0.0004", or the mean alone when it has no error (one replicate).
fn pm(e: Estimate) -> String {
    if e.se.is_finite() { format!("{:.4} ± {:.4}", e.value, e.se) } else { format!("{:.4}", e.value) }
}

/// The verdict column's words for `sign` (of b against a): b more error → a wins; "—" where the
/// margin was not measured (a moving camera's noise part).
fn verdict(sign: i32, a: &str, b: &str) -> String {
    verdict_of(sign, true, a, b)
}

fn verdict_of(sign: i32, measured: bool, a: &str, b: &str) -> String {
    if !measured {
        return "—".into();
    }
    match sign {
        1 => format!("{a} wins"),
        -1 => format!("{b} wins"),
        _ => "tie".into(),
    }
}

/// The floor as a cell prints it ("0.0123", "—" where none was measured).
fn floor_text(f: f64) -> String {
    if f.is_finite() { format!("{f:.4}") } else { "—".into() }
}

/// The RMSE verdict's words, "below floor" where a mean RMSE is below the pipeline's floor (the
/// filter's bias cancelling a sampler's: never a win), "bias interaction" where the margin is
/// within the two sides' biases and their noise ranks the other way (`compare::realtime`).
fn rmse_verdict(sign: i32, below_floor: bool, bias_interaction: bool, a: &str, b: &str) -> String {
    if below_floor && sign != 0 {
        "below floor".into()
    } else if bias_interaction {
        "bias interaction".into()
    } else {
        verdict(sign, a, b)
    }
}

/// "0.0123 ± 0.0004 / 0.0101": a side's bias (with its standard error) and noise, "—" unmeasured.
fn parts_text(p: Parts) -> String {
    if !p.noise.is_finite() {
        return "—".into();
    }
    let bias = if p.bias.se.is_finite() {
        format!("{:.4} ± {:.4}", p.bias.value, p.bias.se)
    } else {
        format!("{:.4}", p.bias.value)
    };
    format!("{bias} / {:.4}", p.noise)
}

/// Column indices of `paper_table` the summary and sentences read.
const P_PIPELINE: usize = 3;
const P_FLOOR: usize = 4;
const P_MARGIN: usize = 10;
const P_NOISE_MARGIN: usize = 11;
const P_VERDICT: usize = 12;
const P_NOISE_VERDICT: usize = 13;

/// Question (1): one row per (scene, rays, camera, pipeline at its last frame): the floor, the
/// paper's RMSE, the best other estimator and its RMSE, both margins (best other against the paper:
/// positive, the paper's has less error) and the verdicts; a 1-ray cell is marked degenerate (a
/// lattice of one point is one point: the sequence axis says nothing there).
pub fn paper_table(results: &[JobResult]) -> Option<Table> {
    let rows = paper_cells(results)?
        .into_iter()
        .map(|c| {
            vec![
                c.place.scene.clone(),
                c.place.rays.to_string(),
                c.place.camera.clone(),
                c.place.pipeline_text(),
                floor_text(c.place.floor),
                pm(c.paper),
                c.best.to_string(),
                pm(c.best_rmse),
                parts_text(c.paper_parts),
                parts_text(c.best_parts),
                margin_text(&c.rmse.margin),
                margin_text(&c.noise.margin),
                rmse_verdict(c.rmse.sign, c.below_floor, c.bias_interaction, "paper", "best other"),
                verdict_of(c.noise.sign, c.noise.margin.relative().is_finite(), "paper", "best other"),
                if c.degenerate { "1 ray: sequence axis degenerate".into() } else { String::new() },
            ]
        })
        .collect();
    Some(Table {
        title: "Real-time: does sine-cosine × Fibonacci × per-pixel seed still win after the pipeline?"
            .into(),
        header: [
            "scene",
            "rays/frame",
            "camera",
            "pipeline",
            "floor",
            "paper's RMSE",
            "best other",
            "its RMSE",
            "paper's bias / noise",
            "best other's bias / noise",
            "margin (RMSE)",
            "margin (noise RMSE)",
            "verdict (RMSE, 5 %)",
            "verdict (noise RMSE)",
            "note",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// Column indices of `stbn_table` the sentences read.
const S_VERDICT: usize = 10;
const S_NOISE_VERDICT: usize = 11;

/// Question (2): under every accumulating pipeline at its last frame, per (scene, rays, camera,
/// sequence, distribution): RMSE with `stbn` against RMSE with per-frame-independent `blue-noise`.
pub fn stbn_table(results: &[JobResult]) -> Option<Table> {
    let rows: Vec<Vec<String>> = stbn_cells(results)
        .into_iter()
        .map(|c| {
            vec![
                c.place.scene.clone(),
                c.place.rays.to_string(),
                c.place.camera.clone(),
                c.place.pipeline_text(),
                floor_text(c.place.floor),
                c.prefix,
                pm(c.blue_noise),
                pm(c.stbn),
                margin_text(&c.rmse.margin),
                margin_text(&c.noise.margin),
                rmse_verdict(c.rmse.sign, c.below_floor, c.bias_interaction, "blue noise", "stbn"),
                verdict_of(c.noise.sign, c.noise.margin.relative().is_finite(), "blue noise", "stbn"),
            ]
        })
        .collect();
    (!rows.is_empty()).then(|| Table {
        title: "Real-time: does spatiotemporal blue noise beat per-frame-independent blue noise under \
                temporal accumulation?"
            .into(),
        header: [
            "scene",
            "rays/frame",
            "camera",
            "pipeline",
            "floor",
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
                c.place.scene.clone(),
                c.place.camera.clone(),
                c.place.pipeline_text(),
                c.prefix,
                pm(c.rotation),
                pm(c.blue_noise),
                pm(c.stbn),
                margin_text(&c.blue_noise_vs_rotation),
                c.bias
                    .map(|b| if b.value.is_finite() { format!("{:.4}", b.value) } else { "—".into() })
                    .join(" / "),
            ]
        })
        .collect();
    let per = if fewest == 1 { "ray" } else { "rays" };
    (!rows.is_empty()).then(|| Table {
        title: format!(
            "Real-time at {fewest} {per} per frame: the noise (and bias) left after accumulation, by seed mode"
        ),
        header: [
            "scene",
            "camera",
            "pipeline",
            "distribution/sequence",
            "rotation",
            "blue-noise",
            "stbn",
            "blue-noise against rotation",
            "bias (rotation / blue-noise / stbn)",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// Column of `engine_table`'s RMSE verdict (the noise verdict follows it).
const E_VERDICT: usize = 11;

/// Question (3): per (scene, rays, pipeline at its last frame), the best engine pattern's
/// configuration against the best of every other seed mode (`compare::realtime::engine_cells`).
pub fn engine_table(results: &[JobResult]) -> Option<Table> {
    let rows: Vec<Vec<String>> = engine_cells(results)
        .into_iter()
        .map(|c| {
            vec![
                c.place.scene.clone(),
                c.place.rays.to_string(),
                c.place.camera.clone(),
                c.place.pipeline_text(),
                floor_text(c.place.floor),
                c.engine.to_string(),
                pm(c.engine_rmse),
                c.other.to_string(),
                pm(c.other_rmse),
                margin_text(&c.rmse.margin),
                margin_text(&c.noise.margin),
                rmse_verdict(c.rmse.sign, c.below_floor, c.bias_interaction, "engine", "other"),
                verdict_of(c.noise.sign, c.noise.margin.relative().is_finite(), "engine", "other"),
            ]
        })
        .collect();
    (!rows.is_empty()).then(|| Table {
        title: "Real-time: the best engine pattern (ign, bayer, magic-square, r2-dither) against the best other seed mode"
            .into(),
        header: [
            "scene",
            "rays/frame",
            "camera",
            "pipeline",
            "floor",
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

/// How many of `rows` have each verdict in column `col`: (first named wins, tie, the other wins,
/// below floor, bias interaction); rows whose margin was not measured ("—") are in none.
fn tally(rows: &[&Vec<String>], col: usize, first: &str) -> (usize, usize, usize, usize, usize) {
    let count = |w: &str| rows.iter().filter(|r| r[col] == w).count();
    let wins = count(&format!("{first} wins"));
    let (ties, below, bias) = (count("tie"), count("below floor"), count("bias interaction"));
    let others = rows.len() - wins - ties - below - bias - count("—");
    (wins, ties, others, below, bias)
}

/// Per pipeline × rays per frame × camera (at the pipeline's last frame), how often the paper's
/// configuration wins, ties and loses, the cells below the floor, the median margins and the
/// floor: the short form the README quotes.
pub fn summary_table(results: &[JobResult]) -> Option<Table> {
    let t = paper_table(results)?;
    let mut by: BTreeMap<(String, u32, String), Vec<&Vec<String>>> = BTreeMap::new();
    for r in &t.rows {
        let rays = r[1].parse::<u32>().unwrap_or(0);
        by.entry((r[P_PIPELINE].clone(), rays, r[2].clone())).or_default().push(r);
    }
    let median = |v: &mut Vec<f64>| {
        v.retain(|x| x.is_finite());
        v.sort_by(f64::total_cmp);
        if v.is_empty() { f64::NAN } else { (v[(v.len() - 1) / 2] + v[v.len() / 2]) / 2.0 }
    };
    // The margins as the table prints them (to 0.1 %), so that the median is one of its cells.
    let pct = |s: &str| s.split_whitespace().next().and_then(|x| x.parse::<f64>().ok()).unwrap_or(f64::NAN);
    let pct_text = |x: f64| if x.is_finite() { format!("{x:+.1} %") } else { "—".into() };
    let rows = by
        .into_iter()
        .map(|((pipeline, rays, camera), rs)| {
            let (w, t, l, b, x) = tally(&rs, P_VERDICT, "paper");
            let (nw, nt, nl, _, _) = tally(&rs, P_NOISE_VERDICT, "paper");
            let mut m: Vec<f64> = rs.iter().map(|r| pct(&r[P_MARGIN])).collect();
            let mut n: Vec<f64> = rs.iter().map(|r| pct(&r[P_NOISE_MARGIN])).collect();
            let mut floors: Vec<&str> = rs.iter().map(|r| r[P_FLOOR].as_str()).collect();
            floors.sort_by(|a, b| {
                a.parse::<f64>().unwrap_or(f64::NAN).total_cmp(&b.parse::<f64>().unwrap_or(f64::NAN))
            });
            let floor = match (floors.first(), floors.last()) {
                (Some(a), Some(z)) if a == z => a.to_string(),
                (Some(a), Some(z)) => format!("{a}–{z}"),
                _ => "—".into(),
            };
            vec![
                pipeline,
                rays.to_string(),
                camera,
                rs.len().to_string(),
                floor,
                format!("{w} / {t} / {l} / {b} / {x}"),
                pct_text(median(&mut m)),
                format!("{nw} / {nt} / {nl}"),
                pct_text(median(&mut n)),
            ]
        })
        .collect();
    Some(Table {
        title: "Real-time, in short: the paper's configuration against the best other, per pipeline, rays \
                per frame and camera"
            .into(),
        header: [
            "pipeline",
            "rays/frame",
            "camera",
            "cells",
            "floor",
            "RMSE: paper wins / tie / best other wins / below floor / bias interaction",
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
        let ((w, tie, l, b, x), (nw, ntie, nl, _, _)) =
            (tally(&rows, P_VERDICT, "paper"), tally(&rows, P_NOISE_VERDICT, "paper"));
        out.push(format!(
            "Real-time: after the pipeline, sine-cosine × Fibonacci × per-pixel seed has significantly less RMSE \
             than every other configuration in {w} of {} cells, ties the best other in {tie}, loses in {l}, \
             is below the filter's floor in {b} and a bias interaction in {x} (no verdict there); on the noise \
             part (from the replicates) it wins {nw}, ties {ntie} and loses {nl} (scene × rays per frame × \
             camera × pipeline at its last frame; 5 % two-sided, paired over replicates).",
            rows.len()
        ));
    }
    if let Some(t) = stbn_table(results) {
        let rows: Vec<&Vec<String>> = t.rows.iter().collect();
        let ((bn, tie, st, b, x), (nbn, ntie, nst, _, _)) =
            (tally(&rows, S_VERDICT, "blue noise"), tally(&rows, S_NOISE_VERDICT, "blue noise"));
        out.push(format!(
            "Under temporal accumulation, spatiotemporal blue noise has significantly less RMSE than \
             per-frame-independent blue noise in {st} of {} cells, ties in {tie}, has more in {bn}, is below \
             the floor in {b} and a bias interaction in {x}; on the noise part it has less in {nst}, ties in \
             {ntie} and has more in {nbn}.",
            rows.len()
        ));
    }
    if let Some(t) = engine_table(results) {
        let rows: Vec<&Vec<String>> = t.rows.iter().collect();
        let ((e, tie, o, b, x), (ne, ntie, no, _, _)) =
            (tally(&rows, E_VERDICT, "engine"), tally(&rows, E_VERDICT + 1, "engine"));
        out.push(format!(
            "The engines' rotation patterns: the best of them has significantly less RMSE than the best other \
             seed mode in {e} of {} cells, ties in {tie}, has more in {o}, is below the floor in {b} and a bias \
             interaction in {x}; on the noise part less in {ne}, ties in {ntie} and more in {no}.",
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
                r.bias_rmse = 0.0;
                r.noise_rmse = rmse;
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
        assert_eq!(t.rows[0][P_PIPELINE], "ema0.1+atrous (frame 16)");
        assert_eq!(t.rows[0][2], "static");
        // Best other: stbn at 0.015 against 0.02; the paired differences are exactly −0.005 twice.
        assert_eq!(t.rows[0][5], "0.0200 ± 0.0010");
        assert_eq!(
            (t.rows[0][P_MARGIN].as_str(), t.rows[0][P_VERDICT].as_str()),
            ("-25.0 ± 0.0 %", "best other wins")
        );
        assert_eq!(t.rows[0][8], "0.0000 / 0.0200", "the paper's bias / noise (no standard error)");
        assert_eq!(t.rows[0][P_NOISE_VERDICT], "best other wins", "noise RMSE: the same halves");
        assert_eq!(
            (t.rows[1][P_MARGIN].as_str(), t.rows[1][P_VERDICT].as_str()),
            ("+20.0 ± 0.0 %", "paper wins")
        );
        let s = stbn_table(&rs).unwrap();
        assert_eq!(s.rows.len(), 1);
        // stbn − blue noise: −0.016 and −0.014 → −50 % ± 3.3 % of 0.03: beyond t(1 dof) = 12.7 SE.
        assert_eq!((s.rows[0][8].as_str(), s.rows[0][S_VERDICT].as_str()), ("-50.0 ± 3.3 %", "stbn wins"));
        let sum = summary_table(&rs).unwrap();
        assert_eq!(sum.rows.len(), 2);
        assert_eq!(
            sum.rows[0][..7],
            ["ema0.1+atrous (frame 16)", "2", "static", "1", "—", "0 / 0 / 1 / 0 / 0", "-25.0 %"]
                .map(String::from)
        );
        // A floor above both means: the verdict is withheld.
        let mut floored = rs.clone();
        floored.iter_mut().filter(|r| r.frame == 16).for_each(|r| r.floor = Some(0.05));
        let t = paper_table(&floored).unwrap();
        assert_eq!((t.rows[0][4].as_str(), t.rows[0][P_VERDICT].as_str()), ("0.0500", "below floor"));
        let seeds = seeds_table(&rs);
        assert!(seeds.is_none(), "no rotation/blue-noise/stbn triple at the fewest rays");
        assert!(paper_table(&rs[..4]).is_none(), "single frames only: no section");
    }
}

//! The real-time verdicts as the page's and `quotes.md`'s tables and sentences: after each
//! pipeline, does the paper's configuration still win; under accumulation, does spatiotemporal blue
//! noise beat per-frame-independent blue noise; does what engines ship (their rotation patterns)
//! match the masks and the paper's; and the noise each seed mode leaves. The cells,
//! margins and verdicts are `compare::realtime`'s (paired over replicates, 5 % two-sided); this
//! file words and formats them. Every cell shows each side's error split from its replicates: bias
//! (± its jackknife standard error) and noise; "—" where a configuration has one replicate (the
//! split is undefined there). An RMSE verdict that is the two sides' biases at work is printed as
//! a "bias interaction", never a win. Every verdict is also read on mean LDR-FLIP ("—" in records
//! made before the column), and the sentences say, per conclusion, where RMSE and FLIP disagree.

use crate::compare::margin::Margin;
use crate::compare::model::Estimate;
use crate::compare::realtime::{Parts, Place, Versus, engine_cells, paper_cells, seeds_cells, stbn_cells};
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

/// The FLIP verdict's words: "—" where a side's records have no `flip` (made before the column).
fn flip_verdict(v: &Versus, a: &str, b: &str) -> String {
    verdict_of(v.sign, v.measured(), a, b)
}

/// The RMSE verdict as the tables word it, for a cell's `Versus`.
fn rmse_words(v: &Versus, below_floor: bool, bias_interaction: bool, a: &str, b: &str) -> String {
    rmse_verdict(v.sign, below_floor, bias_interaction, a, b)
}

/// One conclusion's sentence on where RMSE and FLIP disagree (`rmse_flip_disagree` of its cells):
/// each such cell's place with both verdicts, or that FLIP was not measured; nothing without cells.
fn disagreement(what: &str, cells: &[(Place, bool, String, String)]) -> Option<String> {
    if cells.is_empty() {
        return None;
    }
    let with_flip = cells.iter().filter(|c| c.3 != "—").count();
    if with_flip == 0 {
        return Some(format!(
            "{what}: FLIP was not measured in these records (made before the column), so no cell has a FLIP verdict."
        ));
    }
    let said: Vec<String> = cells
        .iter()
        .filter(|c| c.1)
        .map(|(p, _, r, f)| {
            let per = if p.rays == 1 { "ray" } else { "rays" };
            format!(
                "{}, {} {per}, {} camera, {}: RMSE {r}, FLIP {f}",
                p.scene,
                p.rays,
                p.camera,
                p.pipeline_text()
            )
        })
        .collect();
    Some(if said.is_empty() {
        format!("{what}: RMSE and FLIP agree in all {with_flip} cells with FLIP.")
    } else {
        format!(
            "{what}: RMSE and FLIP disagree in {} of {with_flip} cells with FLIP ({}).",
            said.len(),
            said.join("; ")
        )
    })
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
const P_FLIP_MARGIN: usize = 14;
const P_FLIP_VERDICT: usize = 15;

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
                margin_text(&c.flip.margin),
                flip_verdict(&c.flip, "paper", "best other"),
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
            "margin (FLIP)",
            "verdict (FLIP, 5 %)",
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
const S_FLIP_VERDICT: usize = 13;

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
                margin_text(&c.flip.margin),
                flip_verdict(&c.flip, "blue noise", "stbn"),
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
            "stbn against blue noise (FLIP)",
            "verdict (FLIP, 5 %)",
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
                margin_text(&c.blue_noise_vs_rotation_flip),
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
            "blue-noise against rotation (FLIP)",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// Column of `engine_table`'s RMSE verdict (the noise verdict follows it).
const E_VERDICT: usize = 11;
const E_FLIP_VERDICT: usize = 14;

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
                margin_text(&c.flip.margin),
                flip_verdict(&c.flip, "engine", "other"),
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
            "other against engine (FLIP)",
            "verdict (FLIP, 5 %)",
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
            let (fw, ft, fl, _, _) = tally(&rs, P_FLIP_VERDICT, "paper");
            let mut f: Vec<f64> = rs.iter().map(|r| pct(&r[P_FLIP_MARGIN])).collect();
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
                format!("{fw} / {ft} / {fl}"),
                pct_text(median(&mut f)),
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
            "FLIP: paper wins / tie / best other wins",
            "median margin",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// Per question: one sentence with the counts of each verdict on the RMSE, the noise RMSE and
/// FLIP, and one saying in which cells RMSE and FLIP disagree.
pub fn text(results: &[JobResult]) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(t) = paper_table(results) {
        let rows: Vec<&Vec<String>> = t.rows.iter().collect();
        let ((w, tie, l, b, x), (nw, ntie, nl, _, _), (fw, ftie, fl, _, _)) = (
            tally(&rows, P_VERDICT, "paper"),
            tally(&rows, P_NOISE_VERDICT, "paper"),
            tally(&rows, P_FLIP_VERDICT, "paper"),
        );
        out.push(format!(
            "Real-time: after the pipeline, sine-cosine × Fibonacci × per-pixel seed has significantly less RMSE \
             than every other configuration in {w} of {} cells, ties the best other in {tie}, loses in {l}, \
             is below the filter's floor in {b} and a bias interaction in {x} (no verdict there); on the noise \
             part (from the replicates) it wins {nw}, ties {ntie} and loses {nl}; on FLIP it wins {fw}, ties \
             {ftie} and loses {fl} (scene × rays per frame × camera × pipeline at its last frame; 5 % \
             two-sided, paired over replicates).",
            rows.len()
        ));
        let cells: Vec<_> = paper_cells(results)
            .unwrap_or_default()
            .into_iter()
            .map(|c| {
                let r = rmse_words(&c.rmse, c.below_floor, c.bias_interaction, "paper", "best other");
                (c.place.clone(), c.rmse_flip_disagree(), r, flip_verdict(&c.flip, "paper", "best other"))
            })
            .collect();
        out.extend(disagreement("The paper's configuration against the best other", &cells));
    }
    if let Some(t) = stbn_table(results) {
        let rows: Vec<&Vec<String>> = t.rows.iter().collect();
        let ((bn, tie, st, b, x), (nbn, ntie, nst, _, _), (fbn, ftie, fst, _, _)) = (
            tally(&rows, S_VERDICT, "blue noise"),
            tally(&rows, S_NOISE_VERDICT, "blue noise"),
            tally(&rows, S_FLIP_VERDICT, "blue noise"),
        );
        out.push(format!(
            "Under temporal accumulation, spatiotemporal blue noise has significantly less RMSE than \
             per-frame-independent blue noise in {st} of {} cells, ties in {tie}, has more in {bn}, is below \
             the floor in {b} and a bias interaction in {x}; on the noise part it has less in {nst}, ties in \
             {ntie} and has more in {nbn}; on FLIP it has less in {fst}, ties in {ftie} and has more in {fbn}.",
            rows.len()
        ));
        let cells: Vec<_> = stbn_cells(results)
            .into_iter()
            .map(|c| {
                let r = rmse_words(&c.rmse, c.below_floor, c.bias_interaction, "blue noise", "stbn");
                (c.place.clone(), c.rmse_flip_disagree(), r, flip_verdict(&c.flip, "blue noise", "stbn"))
            })
            .collect();
        out.extend(disagreement("Spatiotemporal blue noise against the 2-D mask", &cells));
    }
    if let Some(t) = engine_table(results) {
        let rows: Vec<&Vec<String>> = t.rows.iter().collect();
        let ((e, tie, o, b, x), (ne, ntie, no, _, _), (fe, ftie, fo, _, _)) = (
            tally(&rows, E_VERDICT, "engine"),
            tally(&rows, E_VERDICT + 1, "engine"),
            tally(&rows, E_FLIP_VERDICT, "engine"),
        );
        out.push(format!(
            "The engines' rotation patterns: the best of them has significantly less RMSE than the best other \
             seed mode in {e} of {} cells, ties in {tie}, has more in {o}, is below the floor in {b} and a bias \
             interaction in {x}; on the noise part less in {ne}, ties in {ntie} and more in {no}; on FLIP less \
             in {fe}, ties in {ftie} and more in {fo}.",
            rows.len()
        ));
        let cells: Vec<_> = engine_cells(results)
            .into_iter()
            .map(|c| {
                let r = rmse_words(&c.rmse, c.below_floor, c.bias_interaction, "engine", "other");
                (c.place.clone(), c.rmse_flip_disagree(), r, flip_verdict(&c.flip, "engine", "other"))
            })
            .collect();
        out.extend(disagreement("The best engine pattern against the best other seed mode", &cells));
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

    #[test]
    fn flip_verdicts_are_dashes_without_the_column_and_disagreements_are_named() {
        let mut rs: Vec<JobResult> = [
            recs(S::Fibonacci, M::BlueNoise, "ema0.1+atrous", 16, 0.050, 0.001),
            recs(S::Fibonacci, M::Stbn, "ema0.1+atrous", 16, 0.040, 0.001),
        ]
        .concat();
        let s = stbn_table(&rs).unwrap();
        assert_eq!((s.rows[0][S_VERDICT].as_str(), s.rows[0][S_FLIP_VERDICT].as_str()), ("stbn wins", "—"));
        assert_eq!(s.rows[0][12], "—");
        let said = text(&rs);
        assert!(said[1].contains("on FLIP it has less in 0, ties in 0 and has more in 0"), "{}", said[1]);
        assert!(said[2].contains("FLIP was not measured"), "{}", said[2]);
        // RMSE says stbn wins; FLIP (mask 0.10, stbn 0.11 in both replicates) says the mask wins.
        for r in &mut rs {
            r.flip = if r.seed_mode == "stbn" { 0.11 } else { 0.10 } + 0.001 * r.replicate as f64;
        }
        let s = stbn_table(&rs).unwrap();
        assert_eq!(
            (s.rows[0][12].as_str(), s.rows[0][S_FLIP_VERDICT].as_str()),
            ("+10.0 ± 0.0 %", "blue noise wins")
        );
        let said = text(&rs);
        assert!(said[1].contains("on FLIP it has less in 0, ties in 0 and has more in 1"), "{}", said[1]);
        assert_eq!(
            said[2],
            "Spatiotemporal blue noise against the 2-D mask: RMSE and FLIP disagree in 1 of 1 cells with FLIP \
             (k, 2 rays, static camera, ema0.1+atrous (frame 16): RMSE stbn wins, FLIP blue noise wins)."
        );
    }
}

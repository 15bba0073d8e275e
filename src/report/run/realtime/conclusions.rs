//! The conclusions the README states, each per pipeline, camera and metric, so that no sentence
//! about them is typed by hand: spatiotemporal blue noise against the 2-D mask in short (the
//! question where RMSE and FLIP can rank the two the other way), and which verdicts change between
//! SVGF's default iteration count and another (`compare::realtime::iterations_pairs`).

use super::{
    P_FLIP_VERDICT, P_PIPELINE, P_VERDICT, S_FLIP_VERDICT, S_NOISE_VERDICT, S_VERDICT, paper_table,
    stbn_table,
    summary::{place_text, tally},
};
use crate::compare::realtime::{Call, IterationsPair, Question, iterations_pairs};
use crate::report::Table;
use crate::results::JobResult;
use std::collections::BTreeMap;

/// Per pipeline × camera × rays per frame (at the pipeline's last frame, over the scenes and
/// sequences measured with both masks): how often stbn beats the 2-D mask on the RMSE, its noise
/// part and FLIP.
pub fn stbn_summary_table(results: &[JobResult]) -> Option<Table> {
    let t = stbn_table(results)?;
    let mut by: BTreeMap<(String, String, u32), Vec<&Vec<String>>> = BTreeMap::new();
    for r in &t.rows {
        let rays = r[1].parse::<u32>().unwrap_or(0);
        by.entry((r[3].clone(), r[2].clone(), rays)).or_default().push(r);
    }
    let rows = by
        .into_iter()
        .map(|((pipeline, camera, rays), rs)| {
            let (bn, tie, st, b, x) = tally(&rs, S_VERDICT, "blue noise");
            let (nbn, ntie, nst, _, _) = tally(&rs, S_NOISE_VERDICT, "blue noise");
            let (fbn, ftie, fst, _, _) = tally(&rs, S_FLIP_VERDICT, "blue noise");
            vec![
                pipeline,
                camera,
                rays.to_string(),
                rs.len().to_string(),
                format!("{st} / {tie} / {bn} / {b} / {x}"),
                format!("{nst} / {ntie} / {nbn}"),
                format!("{fst} / {ftie} / {fbn}"),
            ]
        })
        .collect();
    Some(Table {
        title:
            "Real-time, in short: spatiotemporal blue noise against the 2-D blue-noise mask, per pipeline, \
                camera and rays per frame"
                .into(),
        header: [
            "pipeline",
            "camera",
            "rays/frame",
            "cells",
            "RMSE: stbn wins / tie / mask wins / below floor / bias interaction",
            "noise RMSE: stbn wins / tie / mask wins",
            "FLIP: stbn wins / tie / mask wins",
        ]
        .map(String::from)
        .to_vec(),
        rows,
    })
}

/// One cell of a compact table: "RMSE 0/1/2 · FLIP 0/0/3" (first side wins / tie / the other
/// wins, over the rows), with the RMSE verdicts withheld (below floor, bias interaction) counted
/// apart and FLIP "—" where no row has it.
fn compact_cell(rows: &[&Vec<String>], rmse: usize, flip: usize, first: &str) -> String {
    let (w, t, l, b, x) = tally(rows, rmse, first);
    let (fw, ft, fl, _, _) = tally(rows, flip, first);
    let withheld = if b + x > 0 { format!(" ({} withheld)", b + x) } else { String::new() };
    let flip = if fw + ft + fl == 0 { "—".to_string() } else { format!("{fw}/{ft}/{fl}") };
    format!("RMSE {w}/{t}/{l}{withheld} · FLIP {flip}")
}

/// A (pipeline, camera)'s table rows by rays per frame.
type ByRays<'t> = BTreeMap<u32, Vec<&'t Vec<String>>>;

/// A question's rows as pipeline × camera by rays per frame, each cell `compact_cell`.
fn compact(
    t: &Table,
    (pipeline, camera, rays): (usize, usize, usize),
    (rmse, flip): (usize, usize),
    first: &str,
) -> (Vec<u32>, Vec<Vec<String>>) {
    let mut by: BTreeMap<(String, String), ByRays> = BTreeMap::new();
    let mut all_rays = std::collections::BTreeSet::new();
    for r in &t.rows {
        let n = r[rays].parse::<u32>().unwrap_or(0);
        all_rays.insert(n);
        by.entry((r[pipeline].clone(), r[camera].clone())).or_default().entry(n).or_default().push(r);
    }
    let all_rays: Vec<u32> = all_rays.into_iter().collect();
    let rows = by
        .into_iter()
        .map(|((p, c), per)| {
            let mut row = vec![p, c];
            row.extend(
                all_rays
                    .iter()
                    .map(|n| per.get(n).map_or("—".into(), |rs| compact_cell(rs, rmse, flip, first))),
            );
            row
        })
        .collect();
    (all_rays, rows)
}

fn rays_header(fixed: [&str; 2], rays: &[u32]) -> Vec<String> {
    let mut h: Vec<String> = fixed.map(String::from).to_vec();
    h.extend(
        rays.iter().map(|n| if *n == 1 { "1 ray/frame".to_string() } else { format!("{n} rays/frame") }),
    );
    h
}

/// The paper's configuration against the best other, per pipeline and camera (rows) and rays per
/// frame (columns), each cell the verdicts over the scenes on RMSE and on FLIP: the conclusion the
/// README states, per metric, in one table.
pub fn paper_compact_table(results: &[JobResult]) -> Option<Table> {
    let t = paper_table(results)?;
    let (rays, rows) = compact(&t, (P_PIPELINE, 2, 1), (P_VERDICT, P_FLIP_VERDICT), "paper");
    Some(Table {
        title: "The paper's configuration against the best other: paper wins / tie / best other wins, over the                 scenes, on RMSE and on FLIP"
            .into(),
        header: rays_header(["pipeline", "camera"], &rays),
        rows,
    })
}

/// Spatiotemporal blue noise against the 2-D mask, per pipeline and camera by rays per frame, on
/// RMSE and on FLIP (the conclusion where the two metrics can disagree).
pub fn stbn_compact_table(results: &[JobResult]) -> Option<Table> {
    let t = stbn_table(results)?;
    let (rays, rows) = compact(&t, (3, 2, 1), (S_VERDICT, S_FLIP_VERDICT), "stbn");
    Some(Table {
        title: "STBN against the 2-D blue-noise mask: stbn wins / tie / mask wins, over the scenes and sequences,                 on RMSE and on FLIP"
            .into(),
        header: rays_header(["pipeline", "camera"], &rays),
        rows,
    })
}

/// A call in words, for the sides of its question.
fn call_text(c: Call, q: &Question) -> &'static str {
    let (a, b) = match q {
        Question::Paper => ("paper wins", "best other wins"),
        Question::Stbn(_) => ("mask wins", "stbn wins"),
    };
    match c {
        Call::Sign(1) => a,
        Call::Sign(-1) => b,
        Call::Sign(_) => "tie",
        Call::Withheld => "withheld",
        Call::Unmeasured => "—",
    }
}

/// The sentences on SVGF's iteration count: per question, in how many cells each metric's verdict
/// changes between the two counts, and which; nothing when the spec did not measure two counts.
pub fn iterations_text(results: &[JobResult]) -> Vec<String> {
    let pairs = iterations_pairs(results);
    let Some(first) = pairs.first() else { return Vec::new() };
    let (a, b) = (&first.places[0].pipeline, &first.places[1].pipeline);
    let mut out = Vec::new();
    for (name, paper) in
        [("The paper's configuration against the best other", true), ("STBN against the 2-D mask", false)]
    {
        let of: Vec<&IterationsPair> =
            pairs.iter().filter(|p| matches!(p.question, Question::Paper) == paper).collect();
        if of.is_empty() {
            continue;
        }
        let changed =
            |f: fn(&IterationsPair) -> bool, calls: fn(&IterationsPair) -> [Call; 2]| -> Vec<String> {
                of.iter()
                    .filter(|p| f(p))
                    .map(|p| {
                        let [x, y] = calls(p);
                        let mut at = place_text(&p.places[0]);
                        if let Question::Stbn(prefix) = &p.question {
                            at = format!("{at}, {prefix}");
                        }
                        format!("{at}: {} → {}", call_text(x, &p.question), call_text(y, &p.question))
                    })
                    .collect()
            };
        let rmse = changed(IterationsPair::rmse_changes, |p| p.rmse);
        let flip = changed(IterationsPair::flip_changes, |p| p.flip);
        let list = |v: &[String]| if v.is_empty() { String::new() } else { format!(" ({})", v.join("; ")) };
        out.push(format!(
            "SVGF's iteration count ({a} against {b}, otherwise the same): {name}: the RMSE verdict changes in \
             {} of {} cells{}; the FLIP verdict in {}{}.",
            rmse.len(),
            of.len(),
            list(&rmse),
            flip.len(),
            list(&flip)
        ));
    }
    out
}

//! The verdicts in short: the summary table the README quotes, and the sentences (per question the
//! counts on every metric, and where RMSE and FLIP disagree).

use super::*;

/// "kitchen, 1 ray, static camera, svgf (frame 64)": where a cell is, as the sentences name it.
pub(super) fn place_text(p: &Place) -> String {
    let per = if p.rays == 1 { "ray" } else { "rays" };
    format!("{}, {} {per}, {} camera, {}", p.scene, p.rays, p.camera, p.pipeline_text())
}

/// One conclusion's sentence on where RMSE and FLIP disagree (`rmse_flip_disagree` of its cells):
/// each such cell's place with both verdicts, or that FLIP was not measured; nothing without cells.
fn disagreement(what: &str, cells: &[(String, bool, String, String)]) -> Option<String> {
    if cells.is_empty() {
        return None;
    }
    let with_flip = cells.iter().filter(|c| c.3 != "—").count();
    if with_flip == 0 {
        return Some(format!(
            "{what}: FLIP was not measured in these records (made before the column), so no cell has a FLIP verdict."
        ));
    }
    let said: Vec<String> =
        cells.iter().filter(|c| c.1).map(|(at, _, r, f)| format!("{at}: RMSE {r}, FLIP {f}")).collect();
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

/// How many of `rows` have each verdict in column `col`: (first named wins, tie, the other wins,
/// below floor, bias interaction); rows whose margin was not measured ("—") are in none.
pub(super) fn tally(rows: &[&Vec<String>], col: usize, first: &str) -> (usize, usize, usize, usize, usize) {
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
                (
                    place_text(&c.place),
                    c.rmse_flip_disagree(),
                    r,
                    flip_verdict(&c.flip, "paper", "best other"),
                )
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
                (
                    format!("{}, {}", place_text(&c.place), c.prefix),
                    c.rmse_flip_disagree(),
                    r,
                    flip_verdict(&c.flip, "blue noise", "stbn"),
                )
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
                (place_text(&c.place), c.rmse_flip_disagree(), r, flip_verdict(&c.flip, "engine", "other"))
            })
            .collect();
        out.extend(disagreement("The best engine pattern against the best other seed mode", &cells));
    }
    out.extend(super::iterations_text(results));
    out
}

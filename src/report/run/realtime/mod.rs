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

mod conclusions;
mod summary;
#[cfg(test)]
mod tests;

pub use conclusions::{iterations_text, paper_compact_table, stbn_compact_table, stbn_summary_table};
pub use summary::{summary_table, text};

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
            let mut row = place_columns(&c.place);
            row.extend([
                pm(c.paper),
                c.best.to_string(),
                pm(c.best_rmse),
                parts_text(c.paper_parts),
                parts_text(c.best_parts),
            ]);
            row.extend(verdict_columns(
                (&c.rmse, &c.noise, &c.flip),
                (c.below_floor, c.bias_interaction),
                ("paper", "best other"),
            ));
            row.extend([if c.degenerate { "1 ray: sequence axis degenerate".into() } else { String::new() }]);
            row
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

/// The six verdict columns every real-time question's table has, in this order: the margin on
/// RMSE and on the noise part, their verdicts (the RMSE's withheld below floor or as a bias
/// interaction), the margin on FLIP and its verdict; `a` and `b` name the two sides.
fn verdict_columns(
    (rmse, noise, flip): (&Versus, &Versus, &Versus),
    (below_floor, bias_interaction): (bool, bool),
    (a, b): (&str, &str),
) -> [String; 6] {
    [
        margin_text(&rmse.margin),
        margin_text(&noise.margin),
        rmse_verdict(rmse.sign, below_floor, bias_interaction, a, b),
        verdict_of(noise.sign, noise.margin.relative().is_finite(), a, b),
        margin_text(&flip.margin),
        flip_verdict(flip, a, b),
    ]
}

/// The columns every real-time table opens with: where the cell is, and that place's floor.
fn place_columns(p: &Place) -> Vec<String> {
    vec![p.scene.clone(), p.rays.to_string(), p.camera.clone(), p.pipeline_text(), floor_text(p.floor)]
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
            let mut row = place_columns(&c.place);
            row.extend([c.prefix, pm(c.blue_noise), pm(c.stbn)]);
            row.extend(verdict_columns(
                (&c.rmse, &c.noise, &c.flip),
                (c.below_floor, c.bias_interaction),
                ("blue noise", "stbn"),
            ));
            row
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
            let mut row = place_columns(&c.place);
            row.extend([c.engine.to_string(), pm(c.engine_rmse), c.other.to_string(), pm(c.other_rmse)]);
            row.extend(verdict_columns(
                (&c.rmse, &c.noise, &c.flip),
                (c.below_floor, c.bias_interaction),
                ("engine", "other"),
            ));
            row
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

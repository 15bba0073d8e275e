//! advise's figures: RMSE and low-pass RMSE against time for every configuration, and the winner
//! maps (which configuration has the least error in each pixel at each budget, `advice::winner`),
//! as bytes.

use super::text::label;
use crate::advice::analysis::{Analysis, Map, Measured};
use crate::advice::winner::{self, Pixel};
use crate::compare::PAPER_DEFAULT;
use crate::compare::budget::{Metric, Point, round_significant};
use crate::error::{Error, Result};
use crate::metrics::covered;
use crate::outdir::File;
use crate::report::advise::figures::{
    self as fig, OTHER_WINNER, Panel, TimeCurve, UNRESOLVED, WINNER_COLOURS,
};
use crate::report::colormap::{BACKGROUND, grey};
use crate::report::{Figure, Format};
use crate::spec::Row;

/// The winner map figure.
pub const WINNER_MAP: &str = "winner_map.png";

/// A configuration's colour in the winner map and its legend.
pub type Colours = [(Row, [u8; 3])];

/// Colours for the configurations that win pixels, most pixels over all maps first; those beyond
/// the palette share `OTHER_WINNER`.
pub fn colours(maps: &[Map]) -> Vec<(Row, [u8; 3])> {
    let mut won: Vec<(Row, usize)> = Vec::new();
    for map in maps {
        let (counts, _, _) = winner::tally(&map.pixels, map.rows.len());
        for (row, n) in map.rows.iter().zip(counts).filter(|(_, n)| *n > 0) {
            match won.iter_mut().find(|(r, _)| r == row) {
                Some(w) => w.1 += n,
                None => won.push((*row, n)),
            }
        }
    }
    won.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    won.into_iter()
        .enumerate()
        .map(|(i, (row, _))| (row, WINNER_COLOURS.get(i).copied().unwrap_or(OTHER_WINNER)))
        .collect()
}

/// error_time.png, lowpass_time.png and winner_map.png (when there is a map, in `colours`), added
/// to `files`.
pub fn figures(m: &Measured, a: &Analysis, colours: &Colours, files: &mut Vec<File>) -> Result<Vec<Figure>> {
    let [w, h] = m.setup.loaded.spec.resolution.unwrap_or([0, 0]);
    let mut highlight: Vec<Row> = vec![PAPER_DEFAULT];
    for x in &a.answers {
        let rows = [x.recommended().map(|c| c.row), x.ranking.ranked.first().map(|b| b.row)];
        for row in rows.into_iter().chain([x.lowpass.ranked.first().map(|b| b.row)]).flatten() {
            if !highlight.contains(&row) {
                highlight.push(row);
            }
        }
    }
    let budgets_ms: Vec<f64> = a.budgets_s.iter().map(|b| b * 1e3).collect();
    let mut figs = Vec::new();
    for (metric, file, what) in [
        (Metric::Rmse, "error_time.png", "RMSE"),
        (Metric::Lowpass, "lowpass_time.png", "low-pass RMSE (σ = 1.5 px)"),
    ] {
        let mut curves: Vec<TimeCurve> = a
            .curves
            .iter()
            .map(|c| TimeCurve {
                label: label(c.row),
                points: c.points.iter().map(|p| point(p, metric)).collect(),
                highlight: highlight.contains(&c.row),
            })
            .collect();
        curves.sort_by_key(|c| (!c.highlight, highlight.iter().position(|r| label(*r) == c.label)));
        let title = format!("{what} against time per image, {} at {w}x{h}", m.setup.stem);
        let png =
            fig::error_time_plot(&title, what, &curves, &budgets_ms, Format::Png).map_err(Error::Refused)?;
        files.push(File::new(file, png));
        figs.push(Figure {
            path: file.into(),
            caption: format!(
                "{what} (± 1 σ over the replicates) against the median time per image of every \
                 configuration at {} … {} rays (the sweep); the paper's default and each budget's best in \
                 colour, the rest grey; dashed: the budgets. What is shipped is measured again at its own ray \
                 count (the tables).",
                m.setup.rays.first().copied().unwrap_or(0),
                m.setup.rays.last().copied().unwrap_or(0)
            ),
            links: vec![],
        });
    }
    // No budget to map: no map (the caller removes one an earlier advise left: it would mislead).
    if !a.maps.is_empty() {
        files.push(File::new(WINNER_MAP, winner_png(m, a, colours)?));
        figs.push(Figure { path: WINNER_MAP.into(), caption: winner_note(m), links: vec![] });
    }
    Ok(figs)
}
/// (median time in ms, √(mean MSE), its σ over the replicates: `Point::rmse`).
fn point(p: &Point, metric: Metric) -> (f64, f64, f64) {
    let e = p.rmse(metric);
    (p.time_s * 1e3, e.value, if e.se.is_finite() { e.se } else { 0.0 })
}
/// What a coloured pixel means on the map.
pub fn winner_note(m: &Measured) -> String {
    format!(
        "Winner map: per pixel, which of the budget's finalists (each measured at its own ray count, {} \
         replicates) has the least MSE, the squared error pooled over the pixel's 3x3 neighbourhood. The first \
         half of the replicates picks each pixel's winner and runner-up; the second half tests them (paired by \
         seed, one-sided Student's t); a pixel is coloured when Benjamini-Hochberg over the map's pixels keeps \
         it at a false discovery rate of {:.0} % — at most that share of the coloured pixels are expected to \
         be chance, and where no configuration differs nothing is coloured in at least {:.0} % of maps. Grey: \
         no discovery; slate: no surface. The first panel is the reference.",
        m.replicates,
        100.0 * winner::FDR,
        100.0 * (1.0 - winner::FDR)
    )
}
fn winner_png(m: &Measured, a: &Analysis, colours: &Colours) -> Result<Vec<u8>> {
    let r = &m.reference;
    let (w, h) = (r.mean.width, r.mean.height);
    let mut panels = vec![Panel {
        caption: "reference AO".into(),
        width: w,
        height: h,
        rgb: (0..r.mean.len())
            .map(|i| if covered(&r.coverage, i) { grey(r.mean.data[i]) } else { BACKGROUND })
            .collect(),
    }];
    for map in &a.maps {
        let colour_of = |row: Row| colours.iter().find(|(r, _)| *r == row).map_or(OTHER_WINNER, |c| c.1);
        let rgb = map
            .pixels
            .iter()
            .map(|p| match p {
                Pixel::Background => BACKGROUND,
                Pixel::Unresolved => UNRESOLVED,
                Pixel::Won(i) => colour_of(map.rows[*i]),
            })
            .collect();
        let (_, unresolved, cov) = winner::tally(&map.pixels, map.rows.len());
        let share = 100.0 * (cov - unresolved) as f64 / cov.max(1) as f64;
        panels.push(Panel {
            caption: format!(
                "{} ms: {share:.0} % of pixels resolved",
                round_significant(map.budget_s * 1e3, 3)
            ),
            width: w,
            height: h,
            rgb,
        });
    }
    let mut legend: Vec<(String, [u8; 3])> = Vec::new();
    for (i, (row, c)) in colours.iter().enumerate() {
        if i < WINNER_COLOURS.len() {
            legend.push((label(*row), *c));
        }
    }
    if colours.len() > WINNER_COLOURS.len() {
        legend.push((format!("{} other configurations", colours.len() - WINNER_COLOURS.len()), OTHER_WINNER));
    }
    legend.push(("no discovery".into(), UNRESOLVED));
    legend.push(("no surface".into(), BACKGROUND));
    let title = format!("Where each configuration wins: {} at {w}x{h}, equal time per image", m.setup.stem);
    let note = format!(
        "Least MSE among each budget's finalists at their ray counts, {} replicates (3x3 pooled; half pick, \
         half test); coloured: Benjamini-Hochberg discoveries at FDR {:.0} %.",
        m.replicates,
        100.0 * winner::FDR
    );
    fig::winner_map(&title, &panels, &legend, &note).map_err(Error::Refused)
}

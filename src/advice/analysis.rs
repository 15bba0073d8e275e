//! advise's analysis and figures: the measured records → each configuration's ladder (`Curve`) →
//! the budgets' rankings (`advice`) → the winner maps and the error-against-time figures; then
//! `advise_page` writes advice.json, advice.md and index.html.

use crate::advice::setup::Setup;
use crate::advice::winner::{self, Pixel};
use crate::advice::{self, AtBudget, Curve, Metric, PAPER_DEFAULT, Point, Ranking};
use crate::error::{Error, Result};
use crate::jobs::executor::Session;
use crate::metrics::covered;
use crate::outdir;
use crate::reference::store::Reference;
use crate::report::advise::figures::{
    self as fig, OTHER_WINNER, Panel, TimeCurve, UNRESOLVED, WINNER_COLOURS,
};
use crate::report::advise::page;
use crate::report::colormap::{BACKGROUND, grey};
use crate::report::{Figure, Format};
use crate::results::JobResult;
use crate::spec::Row;
use crate::timing::{Protocol, Summary};
use std::collections::HashMap;
use std::path::Path;

/// What advise measured.
pub struct Measured<'a> {
    pub setup: &'a Setup,
    pub reference: &'a Reference,
    /// By plan index.
    pub results: Vec<JobResult>,
    /// By (configuration, rays, replicate): image − reference on covered pixels (0 elsewhere), for
    /// every timed job and every extra replicate rendered for the winner map.
    pub errors: HashMap<(Row, u32, u32), Vec<f32>>,
    /// Replicates the winner map uses (the timed ones and extra ones, `MAP_REPLICATES` at least).
    pub map_replicates: u32,
    pub session: Session,
    pub protocol: Protocol,
}

/// The winner map compares, per budget, this many of the best configurations (and the paper's
/// default): beyond them the image-level gap is large, and a legend of 50 colours unreadable.
/// The winner map figure.
const WINNER_MAP: &str = "winner_map.png";

pub const MAP_CANDIDATES: usize = 6;
/// Replicates per pixel comparison, at least: with a handful, a pixel's MSE is too noisy to order
/// anything (the timed replicates are reused; the rest are rendered untimed, for the map only).
pub const MAP_REPLICATES: u32 = 16;

/// The winner map at one budget.
pub struct Map {
    pub budget_s: f64,
    /// The compared configurations, in ranking order; `Pixel::Won(i)` indexes this.
    pub rows: Vec<Row>,
    pub pixels: Vec<Pixel>,
}

/// Everything the page and advice.json are made from.
pub struct Analysis {
    pub curves: Vec<Curve>,
    pub budgets_s: Vec<f64>,
    /// The budgets were chosen by advise (`advice::default_budgets`), not given.
    pub default_budgets: bool,
    /// Per budget: by RMSE and by low-pass RMSE.
    pub rankings: Vec<(Ranking, Ranking)>,
    pub maps: Vec<Map>,
    /// Configurations coloured in the winner map, most pixels first, with their colours.
    pub colours: Vec<(Row, [u8; 3])>,
    /// Paired standard errors a pixel's win must exceed.
    pub threshold: f64,
}

/// Ladders, budgets and rankings (no maps yet).
pub fn analyse(m: &Measured, budgets_ms: &[f64]) -> Analysis {
    let curves = curves(m);
    let default = curves.iter().find(|c| c.row == PAPER_DEFAULT).expect("the paper default is always run");
    let (budgets_s, defaulted) = if budgets_ms.is_empty() {
        (advice::default_budgets(default), true)
    } else {
        (budgets_ms.iter().map(|b| b * 1e-3).collect(), false)
    };
    let rankings: Vec<(Ranking, Ranking)> = budgets_s
        .iter()
        .map(|&b| (advice::rank(&curves, b, Metric::Rmse), advice::rank(&curves, b, Metric::Lowpass)))
        .collect();
    let threshold = winner::threshold(m.map_replicates as usize);
    Analysis {
        curves,
        budgets_s,
        default_budgets: defaulted,
        rankings,
        maps: vec![],
        colours: vec![],
        threshold,
    }
}

/// The configurations a budget's map compares: its `MAP_CANDIDATES` best by RMSE, and the paper's
/// default; none when fewer than two are inside their measured times.
fn candidates(r: &Ranking) -> Vec<&AtBudget> {
    if r.ranked.len() < 2 {
        return Vec::new();
    }
    let mut c: Vec<&AtBudget> = r.ranked.iter().take(MAP_CANDIDATES).collect();
    if let Some(d) = r.ranked.iter().skip(MAP_CANDIDATES).find(|a| a.row == PAPER_DEFAULT) {
        c.push(d);
    }
    c
}

/// (configuration, rays) the maps need at `MAP_REPLICATES` replicates: the two measured ray counts
/// around each budget of each candidate.
pub fn map_needs(a: &Analysis) -> Vec<(Row, u32)> {
    let mut out = Vec::new();
    for (r, _) in &a.rankings {
        for c in candidates(r) {
            let curve = a.curves.iter().find(|x| x.row == c.row).expect("ranked rows have curves");
            for p in [&curve.points[c.lo], &curve.points[c.lo + 1]] {
                if !out.contains(&(c.row, p.rays)) {
                    out.push((c.row, p.rays));
                }
            }
        }
    }
    out
}

/// The winner maps, then figures, advice.json, the pages and the records; returns the text to print.
pub fn finish(m: &Measured, mut a: Analysis, out: &Path) -> Result<String> {
    a.maps = winner_maps(m, &a.curves, &a.rankings);
    a.colours = colours(&a.maps);
    let figures = figures(m, &a, out)?;
    outdir::write_results(out, &m.results)?;
    page::write(m, &a, &figures, out)
}

/// Each configuration's ladder from its records: per ray count, the median of every timed render
/// of it and that median's spread, and each replicate's MSE and low-pass MSE.
fn curves(m: &Measured) -> Vec<Curve> {
    let is = |r: &JobResult, row: Row, n: u32| r.rays == n && r.is_row(row);
    m.setup
        .rows
        .iter()
        .map(|&row| {
            let points = m
                .setup
                .rays
                .iter()
                .filter_map(|&n| {
                    let rs: Vec<&JobResult> = m.results.iter().filter(|r| is(r, row, n)).collect();
                    let times: Vec<f64> = rs.iter().flat_map(|r| r.times.iter().copied()).collect();
                    let t = Summary::of(&times)?;
                    Some(Point {
                        rays: n,
                        time_s: t.median,
                        time_spread_s: t.spread(),
                        replicates: rs.iter().map(|r| r.replicate).collect(),
                        mse: rs.iter().map(|r| r.rmse * r.rmse).collect(),
                        lowpass_mse: rs.iter().map(|r| r.lowpass_rmse * r.lowpass_rmse).collect(),
                        whiteness_z: rs.iter().map(|r| r.whiteness_z).collect(),
                    })
                })
                .collect();
            Curve { row, points }
        })
        .collect()
}

/// Per budget with at least two configurations inside their measured times: every pixel's
/// winner by MSE among the budget's candidates (see `advice::winner`), at `map_replicates`
/// replicates, from the two measured ray counts around the budget.
fn winner_maps(m: &Measured, curves: &[Curve], rankings: &[(Ranking, Ranking)]) -> Vec<Map> {
    let reference = &m.reference.coverage;
    let cov: Vec<bool> = (0..reference.len()).map(|i| covered(reference, i)).collect();
    let width = reference.width as usize;
    let mut pooled: HashMap<(Row, u32, u32), Vec<f64>> = HashMap::new();
    let threshold = winner::threshold(m.map_replicates as usize);
    let mut maps = Vec::new();
    for (r, _) in rankings {
        let chosen = candidates(r);
        if chosen.is_empty() {
            continue;
        }
        let mut mse = Vec::new();
        for a in &chosen {
            let c = curves.iter().find(|c| c.row == a.row).expect("ranked rows have curves");
            let (lo, hi) = (c.points[a.lo].rays, c.points[a.lo + 1].rays);
            let mut pool = |rays: u32, rep: u32| -> Vec<f64> {
                let key = (a.row, rays, rep);
                let pooled_of = || match m.errors.get(&key) {
                    Some(err) => winner::pooled_squared_error(err, &cov, width),
                    None => vec![f64::NAN; cov.len()], // never rendered: no winner from it
                };
                pooled.entry(key).or_insert_with(pooled_of).clone()
            };
            let per_replicate: Vec<Vec<f64>> = (0..m.map_replicates)
                .map(|rep| winner::interpolate(&pool(lo, rep), &pool(hi, rep), a.w))
                .collect();
            mse.push(per_replicate);
        }
        let pixels = winner::winners(&mse, &cov, threshold);
        maps.push(Map { budget_s: r.budget_s, rows: chosen.iter().map(|a| a.row).collect(), pixels });
    }
    maps
}

/// Colours for the configurations that win pixels, most pixels over all maps first; those beyond
/// the palette share `OTHER_WINNER`.
fn colours(maps: &[Map]) -> Vec<(Row, [u8; 3])> {
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

/// A configuration's name in tables and legends.
pub fn label(row: Row) -> String {
    let l = row.name();
    if row == PAPER_DEFAULT { format!("{l} (paper default)") } else { l }
}

/// error_time.png, lowpass_time.png and winner_map.png (when there is a map).
fn figures(m: &Measured, a: &Analysis, out: &Path) -> Result<Vec<Figure>> {
    let [w, h] = m.setup.loaded.spec.resolution.unwrap_or([0, 0]);
    let mut highlight: Vec<Row> = vec![PAPER_DEFAULT];
    for (r, l) in &a.rankings {
        for best in [advice::recommended(r), r.ranked.first(), l.ranked.first()].into_iter().flatten() {
            if !highlight.contains(&best.row) {
                highlight.push(best.row);
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
        outdir::write_file(out, file, &png)?;
        figs.push(Figure {
            path: file.into(),
            caption: format!(
                "{what} (mean ± sd over the replicates) against the median time per image of every \
                 configuration at 1 … {} rays; the paper's default and each budget's best in colour, the \
                 rest grey; dashed: the budgets.",
                m.setup.rays.last().copied().unwrap_or(0)
            ),
            links: vec![],
        });
    }
    if a.maps.is_empty() {
        // No budget to map: a map left by an earlier advise in this directory would mislead.
        outdir::remove_file(out, WINNER_MAP)?;
    } else {
        let png = winner_png(m, a)?;
        outdir::write_file(out, WINNER_MAP, &png)?;
        figs.push(Figure { path: WINNER_MAP.into(), caption: winner_note(m, a), links: vec![] });
    }
    Ok(figs)
}

/// (median time in ms, √(mean MSE), its sd over replicates by the delta method).
fn point(p: &Point, metric: Metric) -> (f64, f64, f64) {
    let v = match metric {
        Metric::Rmse => &p.mse,
        Metric::Lowpass => &p.lowpass_mse,
    };
    let (mean, sd) = crate::metrics::mean_sd(v);
    let rmse = mean.sqrt();
    (p.time_s * 1e3, rmse, if rmse > 0.0 { sd / (2.0 * rmse) } else { 0.0 })
}

/// What "significant" means on the map.
pub fn winner_note(m: &Measured, a: &Analysis) -> String {
    format!(
        "Winner map: per pixel, which of the budget's {MAP_CANDIDATES} best configurations and the paper's default \
         has the least MSE at the budget over {} replicates (squared error pooled over the pixel's 3x3 neighbourhood, interpolated between the \
         two measured ray counts around the budget). Coloured where the runner-up's MSE is higher by \
         more than {:.2} paired standard errors (Student's t, one-sided 1 %, replicates paired by \
         seed); grey where no win is that clear (equal configurations colour 0.2-1.4 % of pixels by \
         chance); slate: no surface. The first panel is the reference.",
        m.map_replicates, a.threshold
    )
}

fn winner_png(m: &Measured, a: &Analysis) -> Result<Vec<u8>> {
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
        let colour_of = |row: Row| a.colours.iter().find(|(r, _)| *r == row).map_or(OTHER_WINNER, |c| c.1);
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
                advice::round_significant(map.budget_s * 1e3, 3)
            ),
            width: w,
            height: h,
            rgb,
        });
    }
    let mut legend: Vec<(String, [u8; 3])> = Vec::new();
    for (i, (row, c)) in a.colours.iter().enumerate() {
        if i < WINNER_COLOURS.len() {
            legend.push((label(*row), *c));
        }
    }
    if a.colours.len() > WINNER_COLOURS.len() {
        legend
            .push((format!("{} other configurations", a.colours.len() - WINNER_COLOURS.len()), OTHER_WINNER));
    }
    legend.push(("no significant winner".into(), UNRESOLVED));
    legend.push(("no surface".into(), BACKGROUND));
    let title = format!("Where each configuration wins: {} at {w}x{h}, equal time per image", m.setup.stem);
    let note = format!(
        "Least MSE among each budget's {MAP_CANDIDATES} best and the paper default, over {} replicates (3x3 pooled); \
         coloured if ahead of the runner-up by > {:.2} paired SE.",
        m.map_replicates, a.threshold
    );
    fig::winner_map(&title, &panels, &legend, &note).map_err(Error::Refused)
}

//! The run's figures, one function per figure: every `[[table]]` as AO images and signed-error
//! grids (the paper's Tables 2 and 3), every `[[convergence]]` as MSE at equal time (the key figure:
//! what the answer says), RMSE against rays and against render time and its efficiency against rays, the banding metric of the tables' configurations,
//! and the paper's point figures when the spec asks. Drawing is `report`'s job; this module picks
//! the data from `data::ReportInput` and adds the bytes to the report's files. The page (`page.rs`)
//! lists what it returns.

use crate::compare::equal_time::{Entry, TimeView};
use crate::error::{Error, Result};
use crate::image::Image;
use crate::metrics::{LOWPASS_SIGMA, STRUCTURED_RATIO};
use crate::outdir::File;
use crate::report::figure_rows;
use crate::report::run::data::{
    ReportInput, banding_stat, has_single_frames, lowfreq_stat, row_label, sweep_points, sweep_slope,
    table_configs,
};
use crate::report::run::draw::{LogLog, add_figure, drawn, grid_cells, log_log};
use crate::report::{self, Figure, Format, GridCell, Guide, Series};
use crate::results;
use crate::sampling::{Distribution, SeedMode, Sequence};
use crate::spec::{Group, GroupKind, Row};

/// Point counts of the paper's Table 1 and Figures 2-4.
const POINT_COUNTS: [u32; 3] = [500, 1000, 5000];
/// Point counts of the samplers' Table 1-style panels: powers of two, where the (0,2) sequences'
/// prefixes are nets (pmj02bn's table ends at 4096).
const SAMPLER_COUNTS: [u32; 3] = [256, 1024, 4096];
/// The run's figures: the key figure that shows the answer (the first sweep's MSE at equal time),
/// and the others in page order.
pub struct Figures {
    pub key: Vec<Figure>,
    pub other: Vec<Figure>,
}

/// Every figure of the run, its files added to `files`.
pub fn all(data: &ReportInput, files: &mut Vec<File>) -> Result<Figures> {
    let spec = &data.loaded.spec;
    let mut figures = Vec::new();
    let mut key = Vec::new();
    if spec.point_figures {
        figures.extend(point_figures(spec.seed, files)?);
    }
    for g in &spec.groups {
        for &si in &g.scenes {
            let stem = if g.scenes.len() > 1 {
                format!("{}_{}", g.name, spec.scenes[si].name)
            } else {
                g.name.clone()
            };
            match g.kind {
                GroupKind::Table if has_single_frames(g) => {
                    figures.extend(table_figures(data, g, si, &stem, files)?)
                }
                GroupKind::Table => {}
                GroupKind::Convergence => {
                    let et = equal_time_figure(data, g, si, &stem, files)?;
                    if key.is_empty() {
                        key = et
                    } else {
                        figures.extend(et)
                    }
                    figures.extend(convergence_rays(data, g, si, &stem, files)?);
                    figures.extend(convergence_time(data, g, si, &stem, files)?);
                    figures.extend(efficiency_figure(data, g, si, &stem, files)?);
                }
            }
        }
    }
    figures.extend(banding_figure(data, files)?);
    Ok(Figures { key, other: figures })
}

/// Table 1 (Fibonacci lattice through the three distributions) and Figures 2-4 (pseudo-random
/// points, one figure per distribution), at 500 / 1000 / 5000 points.
fn point_figures(seed: u64, files: &mut Vec<File>) -> Result<Vec<Figure>> {
    let ds = [Distribution::Uniform, Distribution::Sine, Distribution::SineCosine];
    let mut figs = Vec::new();
    let rows = figure_rows(&ds, Sequence::Fibonacci, SeedMode::Static, &POINT_COUNTS, seed)?;
    let title = "Table 1: the Fibonacci lattice through the three distributions";
    let bytes = drawn("table1.png", report::point_panels(title, &rows, true, Format::Png));
    figs.push(add_figure(files, "table1.png", title.into(), vec![], bytes)?);
    // The same panels for the samplers beside the lattice: one row per sequence, sine-cosine.
    let mut rows = Vec::new();
    for seq in Sequence::shipped() {
        let mut r = figure_rows(&[Distribution::SineCosine], seq, SeedMode::Static, &SAMPLER_COUNTS, seed)?;
        rows.extend(r.drain(..).map(|(_, sets)| (seq.to_string(), sets)));
    }
    let title = "Table 1, the samplers beside the lattice: sine-cosine points of one pixel";
    let bytes = drawn("table1_samplers.png", report::point_panels(title, &rows, true, Format::Png));
    figs.push(add_figure(files, "table1_samplers.png", title.into(), vec![], bytes)?);
    for (k, d) in ds.iter().enumerate() {
        let name = format!("figure{}.png", k + 2);
        let rows = figure_rows(&[*d], Sequence::Random, SeedMode::Static, &POINT_COUNTS, seed)?;
        let title = format!("Figure {}: pseudo-random points, {} distribution", k + 2, d);
        let bytes = drawn(&name, report::point_panels(&title, &rows, true, Format::Png));
        figs.push(add_figure(files, &name, title, vec![], bytes)?);
    }
    Ok(figs)
}

/// The AO image of replicate 0 (the lowest replicate present) of a configuration, with its coverage.
fn cell_image(data: &ReportInput, scene: &str, row: Row, rays: u32) -> Result<(Image, Image)> {
    let r = data.results.iter().filter(|r| r.is(scene, row, rays)).min_by_key(|r| r.replicate).ok_or_else(
        || Error::Refused(format!("no result for {} at {rays} rays on '{scene}'", row.label())),
    )?;
    data.image(r)
}

fn caption(data: &ReportInput, scene: &str, row: Row, rays: u32) -> String {
    match results::lookup(&data.aggs, scene, row, rays) {
        Some(a) => {
            let (b, _) = banding_stat(data.results, scene, row, rays).unwrap_or((f64::NAN, 0.0));
            format!("RMSE {:.4} ± {:.4}  ρ {:+.2}  R {:.2}", a.rmse.mean, a.rmse.sd, b, a.lowfreq_ratio.mean)
        }
        None => "no result".into(),
    }
}

fn table_figures(
    data: &ReportInput,
    g: &Group,
    si: usize,
    stem: &str,
    files: &mut Vec<File>,
) -> Result<Vec<Figure>> {
    let scene = &data.loaded.spec.scenes[si].name;
    let reference = &data.references[si];
    let mut images: Vec<Vec<(Image, Image, String)>> = Vec::new();
    for &row in &g.rows {
        let mut cells = Vec::new();
        for &rays in &g.rays {
            let (img, cov) = cell_image(data, scene, row, rays)?;
            cells.push((img, cov, caption(data, scene, row, rays)));
        }
        images.push(cells);
    }
    let cells = grid_cells(&images);
    let m = &reference.manifest;
    let ref_cell = GridCell {
        image: &reference.mean,
        mask: Some(&reference.coverage),
        caption: match m.adaptive {
            Some(_) => format!("{} × adaptive rays, noise {:.1e}", m.replicates, reference.noise_floor()),
            None => format!("{} × {} rays, noise {:.1e}", m.replicates, m.rays, reference.noise_floor()),
        },
    };
    let row_labels: Vec<String> = g.rows.iter().map(|r| row_label(*r)).collect();
    let col_labels: Vec<String> = g.rays.iter().map(|r| format!("{r} rays")).collect();
    let reps = g.replicates;
    let title = format!("{}: ambient occlusion (1 = open), '{scene}', replicate 0", g.name);
    let name = format!("{stem}.png");
    let bytes = drawn(&name, report::image_grid(&title, &row_labels, &col_labels, &cells, Some(&ref_cell)));
    let cap = format!(
        "{}: AO images of replicate 0 on '{scene}' (rows × rays), the reference beside; captions: RMSE mean \
         ± sd over {reps} replicates, ρ, the mean lag-1 error autocorrelation (0 = noise, 1 = bands), and R, \
         the low-frequency ratio of the error (1 = noise, < 1 = blue noise, > {STRUCTURED_RATIO} = \
         structured).",
        g.name
    );
    let mut figs = vec![add_figure(files, &name, cap, vec![], bytes)?];
    let title = format!("{}: signed error (image − reference), replicate 0", g.name);
    let name = format!("{stem}_error.png");
    let bytes = drawn(&name, report::error_grid(&title, &row_labels, &col_labels, &cells, &ref_cell, None));
    let cap = format!(
        "{}: signed error of the images above (red = too open, blue = too occluded), one scale for the \
         whole table; structured error shows as blotches and bands, noise as speckle.",
        g.name
    );
    figs.push(add_figure(files, &name, cap, vec![], bytes)?);
    if let Some(flip) = data.flip {
        let maps: Vec<Vec<(Image, Image, String)>> = images
            .iter()
            .map(|row| {
                row.iter()
                    .map(|(img, cov, _)| {
                        let cov = report::viewer::layers::both(cov, &reference.coverage);
                        let map = flip.of(&reference.mean, img);
                        let mean = (flip.mean)(&map, &cov);
                        (map, cov, format!("mean FLIP {mean:.4}"))
                    })
                    .collect()
            })
            .collect();
        let title = format!("{}: FLIP maps (LDR-FLIP against the reference), replicate 0", g.name);
        let name = format!("{stem}_flip.png");
        let bytes = drawn(&name, report::flip_grid(&title, &row_labels, &col_labels, &grid_cells(&maps)));
        let cap = format!(
            "{}: where the images above differ visibly from the reference, as LDR-FLIP sees it at {} pixels \
             per degree (0 = no visible difference, black; 1 = the most, pale yellow), AO as linear grey; \
             captions give each map's mean over the covered pixels.",
            g.name, flip.ppd
        );
        figs.push(add_figure(files, &name, cap, vec![], bytes)?);
    }
    Ok(figs)
}

/// The reference's noise floor as a guide, when it is a positive number.
fn floor_guide(data: &ReportInput, si: usize) -> Vec<Guide> {
    let floor = data.references[si].noise_floor();
    if floor.is_finite() && floor > 0.0 {
        vec![Guide::Horizontal(floor, "reference noise floor".into())]
    } else {
        vec![]
    }
}

fn size(data: &ReportInput, si: usize) -> String {
    format!("{}x{} px", data.references[si].mean.width, data.references[si].mean.height)
}

/// Each configuration's MSE at equal total render time over the baseline's, against the time budget
/// (four budgets to each factor 2 of time, so the lines are the interpolation itself), ± 1 σ: the
/// answer's picture. Structured configurations say so in the legend.
fn equal_time_figure(
    data: &ReportInput,
    g: &Group,
    si: usize,
    stem: &str,
    files: &mut Vec<File>,
) -> Result<Vec<Figure>> {
    let scene = &data.loaded.spec.scenes[si].name;
    let et = data.equal_time(g, scene, TimeView::Total, 4);
    let series: Vec<Series> = et
        .curves
        .iter()
        .filter_map(|c| {
            let entries: Vec<(f64, &Entry)> =
                et.at.iter().filter_map(|at| at.entry(c.row).map(|e| (at.budget_s, e))).collect();
            let points: Vec<(f64, f64, f64)> = entries
                .iter()
                .filter_map(|(b, e)| {
                    e.vs_baseline.map(|r| (b * 1e3, r.value, if r.se.is_finite() { r.se } else { 0.0 }))
                })
                .filter(|p| p.1 > 0.0 && p.1.is_finite())
                .collect();
            let structured = entries.iter().filter(|(_, e)| e.structured).count();
            let note = match structured {
                0 => None,
                n if n == entries.len() => Some("error structured: rejected".to_string()),
                _ => Some("error structured at some budgets".to_string()),
            };
            (!points.is_empty()).then(|| Series { note, ..Series::new(row_label(c.row), points) })
        })
        .collect();
    if series.is_empty() {
        return Ok(vec![]);
    }
    let title = format!("MSE at equal time, relative to {} ('{scene}')", row_label(et.baseline));
    let cap = format!(
        "{}: {title}, {}. x: a time budget per image (total render time, one thread); y: each configuration's \
         mean MSE at that budget over {}'s (below 1 = less error), its log MSE interpolated linearly in log \
         time between its two measured ray counts around the budget (never extrapolated), ± 1 σ from the \
         replicates (paired by seed) and both times' spread. Configurations whose error is structured \
         (mean low-frequency ratio above {STRUCTURED_RATIO}) say so in the legend: they are never the answer.",
        g.name,
        size(data, si),
        row_label(et.baseline)
    );
    let axes = ("time budget per image (ms, one thread)", "MSE over the baseline's at equal time");
    Ok(vec![log_log(
        files,
        &format!("{stem}_equal_time"),
        LogLog { title: &title, axes, series: &series, guides: &[] },
        cap,
    )?])
}

/// RMSE against rays per pixel, mean ± sd over replicates, slope and its 95 % interval in the legend.
fn convergence_rays(
    data: &ReportInput,
    g: &Group,
    si: usize,
    stem: &str,
    files: &mut Vec<File>,
) -> Result<Vec<Figure>> {
    let scene = &data.loaded.spec.scenes[si].name;
    let series: Vec<Series> = g
        .rows
        .iter()
        .filter_map(|&row| {
            let pts = sweep_points(data, g, scene, row);
            let points = pts.iter().map(|a| (a.rays as f64, a.rmse.mean, a.rmse.sd)).collect::<Vec<_>>();
            let note = sweep_slope(data, g, scene, row)
                .and_then(|s| s.vs_rays)
                .map(|f| format!("slope {}", f.text()));
            (!points.is_empty()).then(|| Series { note, ..Series::new(row_label(row), points) })
        })
        .collect();
    if series.is_empty() {
        return Ok(vec![]);
    }
    let title = format!("RMSE against rays per pixel ('{scene}', {})", size(data, si));
    let cap = format!(
        "{}: {title}; mean ± sd over {} replicates; least-squares log-log slope and its 95 % interval in \
         the legend; dashed: the reference's noise floor.",
        g.name, g.replicates
    );
    let axes = ("rays per pixel", "RMSE");
    Ok(vec![log_log(
        files,
        &format!("{stem}_rays"),
        LogLog { title: &title, axes, series: &series, guides: &floor_guide(data, si) },
        cap,
    )?])
}

/// RMSE against the median render time (min..max of the timed renders as x bars), the
/// no-AO-ray overhead as a wall; slope against AO time in the legend.
fn convergence_time(
    data: &ReportInput,
    g: &Group,
    si: usize,
    stem: &str,
    files: &mut Vec<File>,
) -> Result<Vec<Figure>> {
    let scene = &data.loaded.spec.scenes[si].name;
    let mut series = Vec::new();
    for &row in &g.rows {
        let mut pts: Vec<_> = sweep_points(data, g, scene, row)
            .into_iter()
            .filter_map(|a| a.time.filter(|t| t.min > 0.0).map(|t| (t, a)))
            .collect();
        pts.sort_by(|a, b| a.0.median.total_cmp(&b.0.median));
        if pts.is_empty() {
            continue;
        }
        let note = sweep_slope(data, g, scene, row)
            .and_then(|s| s.vs_ao_time)
            .map(|f| format!("slope vs AO time {}", f.text()));
        series.push(Series {
            label: row_label(row),
            points: pts.iter().map(|(t, a)| (t.median * 1e3, a.rmse.mean, a.rmse.sd)).collect(),
            x_range: pts.iter().map(|(t, _)| (t.min * 1e3, t.max * 1e3)).collect(),
            note,
        });
    }
    if series.is_empty() {
        return Ok(vec![]);
    }
    let mut guides = floor_guide(data, si);
    if let Some(o) = data.overhead[si].filter(|o| o.median > 0.0) {
        guides.push(Guide::Vertical(o.median * 1e3, "image with no AO rays (overhead)".into()));
    }
    let title = format!("RMSE against render time ('{scene}', {})", size(data, si));
    let cap = format!(
        "{}: {title}. x: median over every timed render of the configuration (bars: min..max); a time is \
         {}. y: mean ± sd over {} replicates. Dashed vertical: the overhead, the time of an image with no \
         AO rays; the legend's slope is fitted against the AO time (render time minus the overhead), \
         with its 95 % interval.",
        g.name,
        crate::timing::TIME_INCLUDES,
        g.replicates
    );
    let axes = ("render time per image (ms, one thread)", "RMSE");
    Ok(vec![log_log(
        files,
        &format!("{stem}_time"),
        LogLog { title: &title, axes, series: &series, guides: &guides },
        cap,
    )?])
}

/// Efficiency 1 / (MSE · AO time) against rays per pixel, ± its spread.
fn efficiency_figure(
    data: &ReportInput,
    g: &Group,
    si: usize,
    stem: &str,
    files: &mut Vec<File>,
) -> Result<Vec<Figure>> {
    let scene = &data.loaded.spec.scenes[si].name;
    let series: Vec<Series> = g
        .rows
        .iter()
        .filter_map(|&row| {
            let points: Vec<(f64, f64, f64)> = sweep_points(data, g, scene, row)
                .iter()
                .filter(|a| a.efficiency.is_finite() && a.efficiency > 0.0)
                .map(|a| (a.rays as f64, a.efficiency, a.efficiency_spread.max(0.0)))
                .collect();
            (!points.is_empty()).then(|| Series::new(row_label(row), points))
        })
        .collect();
    if series.is_empty() {
        return Ok(vec![]);
    }
    let title = format!("Efficiency against rays per pixel ('{scene}', {})", size(data, si));
    let cap = format!(
        "{}: {title}. Efficiency = 1 / (MSE · AO time) in 1/s, with MSE the mean over replicates of the \
         squared RMSE and AO time the median render time minus the per-image overhead, so the overhead \
         cannot dominate at low ray counts; higher is better. Bars: ± the spread (the standard error of \
         the MSE, and half the 95 % interval of the median time with the run-to-run scatter, combined).",
        g.name
    );
    let axes = ("rays per pixel", "efficiency (1/(MSE·s))");
    Ok(vec![log_log(
        files,
        &format!("{stem}_efficiency"),
        LogLog { title: &title, axes, series: &series, guides: &[] },
        cap,
    )?])
}

/// The structured-error metric of every table configuration — the low-frequency ratio, the measure
/// the verdicts use — so Table 3's banding is a number: one figure for a single scene
/// (`banding.png`), one per scene otherwise (`banding_<scene>.png`), so that no figure grows beyond
/// a screen or two.
fn banding_figure(data: &ReportInput, files: &mut Vec<File>) -> Result<Vec<Figure>> {
    let configs = table_configs(data);
    let mut scenes: Vec<String> = Vec::new();
    for (scene, _, _) in &configs {
        if !scenes.contains(scene) {
            scenes.push(scene.clone());
        }
    }
    let mut figs = Vec::new();
    for scene in &scenes {
        let bars: Vec<(String, f64, f64)> = configs
            .iter()
            .filter(|c| &c.0 == scene)
            .filter_map(|(scene, row, rays)| {
                let (m, sd) = lowfreq_stat(data.results, scene, *row, *rays)?;
                Some((format!("{}, {rays} rays", row_label(*row)), m, sd))
            })
            .collect();
        if bars.is_empty() {
            continue;
        }
        let stem = if scenes.len() > 1 { format!("banding_{scene}") } else { "banding".to_string() };
        let title = format!("Structured error of the tables' configurations ('{scene}')");
        let x_label = "low-frequency ratio of the error (white noise: 1)";
        let marks = [(1.0, "white".to_string()), (STRUCTURED_RATIO, "structured above".to_string())];
        let svg = format!("{stem}.svg");
        let plot = |f| report::banding_plot(&title, x_label, &bars, &marks, f);
        files.push(File::new(&svg, drawn(&svg, plot(Format::Svg))?));
        let png = format!("{stem}.png");
        let bytes = drawn(&png, plot(Format::Png));
        let cap = format!(
            "Banding on '{scene}': the low-frequency ratio of the error image — its energy after a Gaussian \
             blur of σ = {LOWPASS_SIGMA} px over the energy independent per-pixel errors of the same sizes \
             would keep — mean ± sd over replicates. Independent per-pixel noise reads 1 at any image size; \
             blue noise below 1 (neighbouring errors cancel, a blur removes them); blotches, bands and moiré \
             that a blur keeps read above {STRUCTURED_RATIO}, the report's and advise's threshold for \
             structured error, although their RMSE may be no worse. The whiteness z-score (a test of any \
             correlation, negative included) is in the tables."
        );
        figs.push(add_figure(files, &png, cap, vec![svg], bytes)?);
    }
    Ok(figs)
}

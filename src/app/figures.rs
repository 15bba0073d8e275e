//! The run's figures: every `[[table]]` as AO images and signed-error grids (the paper's Tables 2
//! and 3), every `[[convergence]]` as RMSE against rays and against time, the banding metric of the
//! tables' configurations, the paper's point figures when the spec asks, and one page linking them
//! all (`page.rs`). Drawing is `report`'s job; this module picks the data and writes the bytes.

use super::page;
use super::points::figure_rows;
use super::reference::Reference;
use super::run::Loaded;
use crate::error::{Error, Result};
use crate::image::Image;
use crate::io;
use crate::metrics::mean_sd;
use crate::metrics::whiteness::STRUCTURED_Z;
use crate::plan::Plan;
use crate::report::{self, Figure, Format, GridCell, Series};
use crate::results::{self, Aggregate, JobResult};
use crate::sampling::{Distribution, SeedMode, Sequence};
use crate::spec::{Group, GroupKind, Row};
use std::path::Path;

/// Point counts of the paper's Table 1 and Figures 2-4.
const POINT_COUNTS: [u32; 3] = [500, 1000, 5000];

/// Everything the figures and the page are drawn from.
pub struct Data<'a> {
    pub loaded: &'a Loaded,
    pub references: &'a [Reference],
    pub results: &'a [JobResult],
    pub aggs: Vec<Aggregate>,
}

pub fn write_all(
    loaded: &Loaded,
    _plan: &Plan,
    references: &[Reference],
    results: &[JobResult],
    out: &Path,
) -> Result<()> {
    let data = Data { loaded, references, results, aggs: results::aggregate(results) };
    let spec = &loaded.spec;
    let mut figures = Vec::new();
    if spec.point_figures {
        figures.extend(point_figures(spec.seed, out)?);
    }
    for g in &spec.groups {
        for &si in &g.scenes {
            let stem = if g.scenes.len() > 1 {
                format!("{}_{}", g.name, spec.scenes[si].name)
            } else {
                g.name.clone()
            };
            match g.kind {
                GroupKind::Table => figures.extend(table_figures(&data, g, si, &stem, out)?),
                GroupKind::Convergence => figures.extend(convergence_figures(&data, g, si, &stem, out)?),
            }
        }
    }
    figures.extend(banding_figure(&data, out)?);
    page::write(&data, &figures, out)
}

/// A readable name of a row, as the paper says it.
pub fn row_label(row: Row) -> String {
    let seq = match (row.sequence, row.seed_mode) {
        (Sequence::Random, SeedMode::Static) => "pseudo-random, static seed".to_string(),
        (Sequence::Random, SeedMode::BlueNoise) => "pseudo-random, blue-noise".to_string(),
        (Sequence::Random, _) => "pseudo-random".to_string(),
        (Sequence::Fibonacci, SeedMode::Rotation) => "Fibonacci, per-pixel seed".to_string(),
        (Sequence::Fibonacci, SeedMode::Static) => "Fibonacci, static seed".to_string(),
        (Sequence::Fibonacci, SeedMode::Shift) => "Fibonacci, shift".to_string(),
        (Sequence::Fibonacci, SeedMode::BlueNoise) => "Fibonacci, blue-noise".to_string(),
        (s, m) => format!("{s}, {m}"),
    };
    format!("{}, {seq}", row.distribution)
}

/// Whether a result belongs to (scene, row, rays).
fn is_config(r: &JobResult, scene: &str, row: Row, rays: u32) -> bool {
    let row = row.canonical();
    r.scene == scene
        && r.rays == rays
        && r.distribution == row.distribution.name()
        && r.sequence == row.sequence.name()
        && r.seed_mode == row.seed_mode.name()
}

/// The banding metric of one image: mean of the horizontal and vertical lag-1 error autocorrelation.
fn banding(r: &JobResult) -> f64 {
    0.5 * (r.autocorr_x + r.autocorr_y)
}

/// Mean ± sd of the banding metric over the replicates of a configuration.
pub fn banding_stat(results: &[JobResult], scene: &str, row: Row, rays: u32) -> Option<(f64, f64)> {
    let v: Vec<f64> = results
        .iter()
        .filter(|r| is_config(r, scene, row, rays))
        .map(banding)
        .filter(|b| b.is_finite())
        .collect();
    (!v.is_empty()).then(|| mean_sd(&v))
}

/// Mean ± sd of the whiteness z-score over the replicates of a configuration.
pub fn whiteness_stat(results: &[JobResult], scene: &str, row: Row, rays: u32) -> Option<(f64, f64)> {
    let v: Vec<f64> = results
        .iter()
        .filter(|r| is_config(r, scene, row, rays))
        .map(|r| r.whiteness_z)
        .filter(|z| z.is_finite())
        .collect();
    (!v.is_empty()).then(|| mean_sd(&v))
}

fn drawn(path: &Path, r: std::result::Result<Vec<u8>, String>) -> Result<Vec<u8>> {
    r.map_err(|e| Error::Refused(format!("{}: cannot draw the figure: {e}", path.display())))
}

fn write_figure(
    out: &Path,
    name: &str,
    caption: String,
    links: Vec<String>,
    bytes: Result<Vec<u8>>,
) -> Result<Figure> {
    io::write_atomic(&out.join(name), &bytes?)?;
    Ok(Figure { path: name.to_string(), caption, links })
}

/// Table 1 (Fibonacci lattice through the three distributions) and Figures 2-4 (pseudo-random
/// points, one figure per distribution), at 500 / 1000 / 5000 points.
fn point_figures(seed: u64, out: &Path) -> Result<Vec<Figure>> {
    let ds = [Distribution::Uniform, Distribution::Sine, Distribution::SineCosine];
    let mut figs = Vec::new();
    let rows = figure_rows(&ds, Sequence::Fibonacci, SeedMode::Static, &POINT_COUNTS, seed)?;
    let title = "Table 1: the Fibonacci lattice through the three distributions";
    let path = out.join("table1.png");
    let bytes = drawn(&path, report::point_panels(title, &rows, true, Format::Png));
    figs.push(write_figure(out, "table1.png", title.into(), vec![], bytes)?);
    for (k, d) in ds.iter().enumerate() {
        let name = format!("figure{}.png", k + 2);
        let rows = figure_rows(&[*d], Sequence::Random, SeedMode::Static, &POINT_COUNTS, seed)?;
        let title = format!("Figure {}: pseudo-random points, {} distribution", k + 2, d);
        let bytes = drawn(&out.join(&name), report::point_panels(&title, &rows, true, Format::Png));
        figs.push(write_figure(out, &name, title, vec![], bytes)?);
    }
    Ok(figs)
}

/// The AO image of replicate 0 (the lowest replicate present) of a configuration, with its coverage.
fn cell_image(data: &Data, out: &Path, scene: &str, row: Row, rays: u32) -> Result<(Image, Image)> {
    let r = data
        .results
        .iter()
        .filter(|r| is_config(r, scene, row, rays))
        .min_by_key(|r| r.replicate)
        .ok_or_else(|| {
            Error::Refused(format!("no result for {} at {rays} rays on '{scene}'", row.label()))
        })?;
    let path = out.join(&r.image);
    let channels = io::read_exr(&path)?;
    let take = |name: &str| {
        channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, img)| img.clone())
            .ok_or_else(|| Error::input(&path, format!("image lacks channel '{name}'")))
    };
    Ok((take("Y")?, take("A")?))
}

fn caption(data: &Data, scene: &str, row: Row, rays: u32) -> String {
    match results::lookup(&data.aggs, scene, row, rays) {
        Some(a) => {
            let (b, _) = banding_stat(data.results, scene, row, rays).unwrap_or((f64::NAN, 0.0));
            format!("RMSE {:.4} ± {:.4}  ρ {:+.2}  z {:.1}", a.rmse.mean, a.rmse.sd, b, a.whiteness_z.mean)
        }
        None => "no result".into(),
    }
}

fn table_figures(data: &Data, g: &Group, si: usize, stem: &str, out: &Path) -> Result<Vec<Figure>> {
    let scene = &data.loaded.spec.scenes[si].name;
    let reference = &data.references[si];
    let mut images: Vec<Vec<(Image, Image, String)>> = Vec::new();
    for &row in &g.rows {
        let mut cells = Vec::new();
        for &rays in &g.rays {
            let (img, cov) = cell_image(data, out, scene, row, rays)?;
            cells.push((img, cov, caption(data, scene, row, rays)));
        }
        images.push(cells);
    }
    let cells: Vec<Vec<GridCell>> = images
        .iter()
        .map(|row| {
            row.iter().map(|(i, m, c)| GridCell { image: i, mask: Some(m), caption: c.clone() }).collect()
        })
        .collect();
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
    let bytes = drawn(
        &out.join(&name),
        report::image_grid(&title, &row_labels, &col_labels, &cells, Some(&ref_cell)),
    );
    let cap = format!(
        "{}: AO images of replicate 0 on '{scene}' (rows × rays), the reference beside; captions: RMSE mean \
         ± sd over {reps} replicates, ρ, the mean lag-1 error autocorrelation (0 = noise, 1 = bands), and z, \
         the whiteness z-score of the error (0 ± 1 = noise, > {STRUCTURED_Z} = structured).",
        g.name
    );
    let mut figs = vec![write_figure(out, &name, cap, vec![], bytes)?];
    let title = format!("{}: signed error (image − reference), replicate 0", g.name);
    let name = format!("{stem}_error.png");
    let bytes = drawn(
        &out.join(&name),
        report::error_grid(&title, &row_labels, &col_labels, &cells, &ref_cell, None),
    );
    let cap = format!(
        "{}: signed error of the images above (red = too open, blue = too occluded), one scale for the \
         whole table; structured error shows as blotches and bands, noise as speckle.",
        g.name
    );
    figs.push(write_figure(out, &name, cap, vec![], bytes)?);
    Ok(figs)
}

/// The aggregates of one sweep row, in ray order.
fn sweep_points<'a>(data: &'a Data, g: &Group, scene: &str, row: Row) -> Vec<&'a Aggregate> {
    g.rays.iter().filter_map(|&rays| results::lookup(&data.aggs, scene, row, rays)).collect()
}

/// The fitted slopes of one sweep row, over the sweep's own ray counts.
pub fn sweep_slope(data: &Data, g: &Group, scene: &str, row: Row) -> Option<results::Slope> {
    let pts: Vec<Aggregate> = sweep_points(data, g, scene, row).into_iter().cloned().collect();
    results::convergence_slopes(&pts, &g.rays).into_iter().next()
}

fn convergence_figures(data: &Data, g: &Group, si: usize, stem: &str, out: &Path) -> Result<Vec<Figure>> {
    let scene = &data.loaded.spec.scenes[si].name;
    let floor = Some(data.references[si].noise_floor()).filter(|f| f.is_finite() && *f > 0.0);
    let mut by_rays = Vec::new();
    let mut by_time = Vec::new();
    for &row in &g.rows {
        let pts = sweep_points(data, g, scene, row);
        if pts.is_empty() {
            continue;
        }
        let slope = sweep_slope(data, g, scene, row);
        let label = row_label(row);
        by_rays.push(Series {
            label: label.clone(),
            points: pts.iter().map(|a| (a.rays as f64, a.rmse.mean, a.rmse.sd)).collect(),
            slope: slope.as_ref().and_then(|s| s.vs_rays),
        });
        let mut timed: Vec<(f64, f64, f64)> = pts
            .iter()
            .filter(|a| a.time_s.mean > 0.0 && a.time_s.mean.is_finite())
            .map(|a| (a.time_s.mean, a.rmse.mean, a.rmse.sd))
            .collect();
        timed.sort_by(|a, b| a.0.total_cmp(&b.0));
        if !timed.is_empty() {
            by_time.push(Series { label, points: timed, slope: slope.and_then(|s| s.vs_time) });
        }
    }
    let mut figs = Vec::new();
    if by_rays.is_empty() {
        return Ok(figs);
    }
    let reps = g.replicates;
    let plots = [
        ("rays", "rays per pixel", "RMSE against rays per pixel", &by_rays),
        ("time", "render time per image (s)", "RMSE against render time", &by_time),
    ];
    for (what, x_label, title, series) in plots {
        if series.is_empty() {
            continue;
        }
        let (w, h) = (data.references[si].mean.width, data.references[si].mean.height);
        let title = format!("{title} ('{scene}', {w}x{h} px)");
        let base = format!("{stem}_{what}");
        let svg = format!("{base}.svg");
        let bytes = drawn(
            &out.join(&svg),
            report::convergence_plot(&title, x_label, "RMSE", series, floor, Format::Svg),
        );
        io::write_atomic(&out.join(&svg), &bytes?)?;
        let png = format!("{base}.png");
        let bytes = drawn(
            &out.join(&png),
            report::convergence_plot(&title, x_label, "RMSE", series, floor, Format::Png),
        );
        let cap = format!(
            "{}: {title}; mean ± sd over {reps} replicates, least-squares log-log slope in the legend, \
             dashed: the reference's noise floor.",
            g.name
        );
        figs.push(write_figure(out, &png, cap, vec![svg], bytes)?);
    }
    Ok(figs)
}

/// Every (scene, row, rays) of the spec's tables, in file order, without duplicates.
pub fn table_configs(data: &Data) -> Vec<(String, Row, u32)> {
    let spec = &data.loaded.spec;
    let mut out: Vec<(String, Row, u32)> = Vec::new();
    for g in spec.groups.iter().filter(|g| g.kind == GroupKind::Table) {
        for &si in &g.scenes {
            for &row in &g.rows {
                for &rays in &g.rays {
                    let c = (spec.scenes[si].name.clone(), row.canonical(), rays);
                    if !out.contains(&c) {
                        out.push(c);
                    }
                }
            }
        }
    }
    out
}

/// The structured-error metric (whiteness z) of every table configuration, so Table 3's banding is
/// a number: one figure for a single scene (`banding.png`), one per scene otherwise
/// (`banding_<scene>.png`), so that no figure grows beyond a screen or two.
fn banding_figure(data: &Data, out: &Path) -> Result<Vec<Figure>> {
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
                let (m, sd) = whiteness_stat(data.results, scene, *row, *rays)?;
                Some((format!("{}, {rays} rays", row_label(*row)), m, sd))
            })
            .collect();
        if bars.is_empty() {
            continue;
        }
        let stem = if scenes.len() > 1 { format!("banding_{scene}") } else { "banding".to_string() };
        let title = format!("Structured error of the tables' configurations ('{scene}')");
        let x_label = "whiteness z-score of the error (white noise: 0 ± 1)";
        let svg = format!("{stem}.svg");
        let bytes = drawn(&out.join(&svg), report::banding_plot(&title, x_label, &bars, Format::Svg));
        io::write_atomic(&out.join(&svg), &bytes?)?;
        let png = format!("{stem}.png");
        let bytes = drawn(&out.join(&png), report::banding_plot(&title, x_label, &bars, Format::Png));
        let cap = format!(
            "Banding on '{scene}': the whiteness z-score of the error image (2-D Ljung–Box statistic over \
             every lag up to 4 pixels in every direction, against white noise), mean ± sd over replicates. \
             Independent per-pixel noise reads about 0 ± 1; bands, stripes and moiré of any orientation \
             read far above {STRUCTURED_Z}, although their RMSE may be no worse."
        );
        figs.push(write_figure(out, &png, cap, vec![svg], bytes)?);
    }
    Ok(figs)
}

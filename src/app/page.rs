//! `report.md` and `index.html`: one offline page with the run's numbers (the verdict on each claim,
//! references, each table's RMSE, convergence slopes), every figure, linked by relative paths, and
//! the long tables (verdict margins, every aggregate) folded at the end.

use super::figures::{Data, banding_stat, row_label, sweep_slope};
use crate::error::Result;
use crate::io;
use crate::metrics::whiteness::STRUCTURED_Z;
use crate::report::{self, Figure, Table};
use crate::results::{self, Stat};
use crate::spec::{GroupKind, Row};
use std::path::Path;

pub fn write(data: &Data, figures: &[Figure], out: &Path) -> Result<()> {
    let spec = &data.loaded.spec;
    let verdicts = super::verdicts::tables(data);
    let mut tables = Vec::new();
    let mut collapsed = Vec::new();
    if let Some((summary, details)) = verdicts {
        tables.push(summary);
        collapsed.push(details);
    }
    tables.push(reference_table(data));
    // With several scenes the per-scene tables would push the figures pages down: the verdict sums
    // them up, and they are folded after the figures.
    let many = spec.scenes.len() > 1;
    for g in spec.groups.iter().filter(|g| g.kind == GroupKind::Table) {
        for &si in &g.scenes {
            let t = rmse_table(data, &g.name, &spec.scenes[si].name, &g.rows, &g.rays, g.replicates);
            if many { collapsed.push(t) } else { tables.push(t) }
        }
    }
    let slopes = slope_table(data);
    if !slopes.rows.is_empty() {
        if many { collapsed.push(slopes) } else { tables.push(slopes) }
    }
    collapsed.push(aggregate_table(data));
    let title = format!("hemilab: {}", spec.name);
    let intro = format!(
        "Spec {} ({} jobs). Every number is measured against the reference of its scene over the \
         pixels that see a surface; mean ± sd over independent replicates (different seeds). \
         ρ is the lag-1 autocorrelation of the error image (horizontal / vertical): near 0 for \
         independent per-pixel noise, near 1 for banding. The whiteness z-score tests the error image \
         against white noise over every lag up to 4 pixels in every direction (a 2-D Ljung–Box \
         statistic): about 0 ± 1 for independent per-pixel noise, above 5 for structure of any \
         orientation or period — diagonal moiré and checkerboards included, which ρ misses. Lowpass RMSE is the RMSE after a small \
         Gaussian blur of the error: noise averages out under it, bands do not. Efficiency = \
         1 / (MSE × time). A claim that fails on a scene is a result, not a bug: the verdict table \
         says where the paper's findings carry over and where they do not.\n\nRaw numbers: results.csv, results.json (one record per image), \
         aggregates.csv, slopes.json.",
        spec.path.display(),
        data.results.len()
    );
    io::write_atomic(
        &out.join("index.html"),
        report::html_page(&title, &intro, &tables, figures, &collapsed).as_bytes(),
    )?;
    io::write_atomic(
        &out.join("report.md"),
        report::markdown_page(&title, &intro, &tables, figures, &collapsed).as_bytes(),
    )
}

fn pm(s: Stat, digits: usize) -> String {
    if s.mean.is_finite() { format!("{:.digits$} ± {:.digits$}", s.mean, s.sd) } else { "–".into() }
}

fn reference_table(data: &Data) -> Table {
    let header =
        ["scene", "size", "estimator", "replicates × rays", "noise floor", "smallest RMSE", "floor / RMSE"];
    let rows = data
        .references
        .iter()
        .enumerate()
        .map(|(si, r)| {
            let name = &data.loaded.spec.scenes[si].name;
            let smallest = data
                .aggs
                .iter()
                .filter(|a| &a.scene == name)
                .map(|a| a.rmse.mean)
                .fold(f64::INFINITY, f64::min);
            let floor = r.noise_floor();
            let m = &r.manifest;
            vec![
                name.clone(),
                format!("{}x{}", r.mean.width, r.mean.height),
                row_label(data.loaded.spec.reference.estimator),
                match &m.adaptive {
                    Some(a) => {
                        let pixels = crate::reference::noise_floor_pixels(&r.coverage).max(1) as f64;
                        let mean = a.total_rays.unwrap_or(0) as f64 / pixels;
                        format!(
                            "{} × adaptive, mean {mean:.0} (pilot {} × {})",
                            m.replicates, m.replicates, m.rays
                        )
                    }
                    None => format!("{} × {}", m.replicates, m.rays),
                },
                format!("{floor:.2e}"),
                format!("{smallest:.2e}"),
                format!("{:.3}", floor / smallest),
            ]
        })
        .collect();
    Table { title: "References".into(), header: header.map(String::from).to_vec(), rows }
}

fn rmse_table(data: &Data, name: &str, scene: &str, rows: &[Row], rays: &[u32], reps: u32) -> Table {
    let mut header = vec!["configuration".to_string()];
    header.extend(rays.iter().map(|r| format!("{r} rays")));
    let rows = rows
        .iter()
        .map(|&row| {
            let mut cells = vec![row_label(row)];
            for &n in rays {
                cells.push(match results::lookup(&data.aggs, scene, row, n) {
                    Some(a) => {
                        let b = banding_stat(data.results, scene, row, n).map_or(f64::NAN, |b| b.0);
                        format!("{}  (ρ {b:+.2}, z {:.1})", pm(a.rmse, 4), a.whiteness_z.mean)
                    }
                    None => "–".into(),
                });
            }
            cells
        })
        .collect();
    let title = format!(
        "{name} ('{scene}'): RMSE, mean ± sd over {reps} replicates (ρ: lag-1 autocorrelation; z: whiteness \
         z-score, > {STRUCTURED_Z} = structured)"
    );
    Table { title, header, rows }
}

fn slope_table(data: &Data) -> Table {
    let spec = &data.loaded.spec;
    let header = ["sweep", "scene", "configuration", "ray counts", "slope vs rays", "slope vs time"];
    let mut rows = Vec::new();
    for g in spec.groups.iter().filter(|g| g.kind == GroupKind::Convergence) {
        for &si in &g.scenes {
            let scene = &spec.scenes[si].name;
            for &row in &g.rows {
                let Some(s) = sweep_slope(data, g, scene, row) else { continue };
                let f = |v: Option<f64>| v.map_or("–".into(), |k| format!("{k:+.3}"));
                rows.push(vec![
                    g.name.clone(),
                    scene.clone(),
                    row_label(row),
                    s.points.to_string(),
                    f(s.vs_rays),
                    f(s.vs_time),
                ]);
            }
        }
    }
    Table {
        title: "Convergence: least-squares slope of log RMSE (−0.5 = plain Monte Carlo)".into(),
        header: header.map(String::from).to_vec(),
        rows,
    }
}

fn aggregate_table(data: &Data) -> Table {
    let header = [
        "scene",
        "configuration",
        "rays",
        "replicates",
        "RMSE",
        "bias",
        "ρ x",
        "ρ y",
        "lowpass RMSE",
        "whiteness z",
        "time (ms)",
        "M rays/s",
        "efficiency",
    ];
    let rows = data
        .aggs
        .iter()
        .map(|a| {
            let ms = Stat { mean: a.time_s.mean * 1e3, sd: a.time_s.sd * 1e3 };
            let label = format!("{}, {}, {}", a.distribution, a.sequence, a.seed_mode);
            vec![
                a.scene.clone(),
                label,
                a.rays.to_string(),
                a.replicates.to_string(),
                pm(a.rmse, 4),
                pm(a.bias, 4),
                pm(a.autocorr_x, 2),
                pm(a.autocorr_y, 2),
                pm(a.lowpass_rmse, 4),
                pm(a.whiteness_z, 1),
                pm(ms, 1),
                format!("{:.1}", a.rays_per_s.mean / 1e6),
                if a.efficiency.mean.is_finite() {
                    format!("{:.3e}", a.efficiency.mean)
                } else {
                    "–".into()
                },
            ]
        })
        .collect();
    Table {
        title: "All configurations (mean ± sd over replicates)".into(),
        header: header.map(String::from).to_vec(),
        rows,
    }
}

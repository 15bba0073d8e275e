//! The real-time figures, for every group with frames, schedules or pipelines: the noise
//! left after k accumulated frames, one plot per schedule, and a crop grid of the final frames
//! (every configuration × every pipeline at its last frame, the reference beside). Both at the
//! group's fewest rays per frame, where real-time engines work and samplers differ most.

use super::data::{ReportInput, row_label};
use super::draw::{LogLog, add_figure, drawn, grid_cells, log_log};
use crate::denoise::Pipeline;
use crate::error::{Error, Result};
use crate::image::Image;
use crate::outdir::File;
use crate::report::{self, Figure, GridCell, Series};
use crate::results::JobResult;
use crate::sampling::Schedule;
use crate::spec::{Group, Row};
use std::collections::BTreeMap;

/// Whether a group measures anything beyond the paper's one raw frame.
pub fn is_realtime(g: &Group) -> bool {
    g.frames > 1 || g.schedules.len() > 1 || g.pipelines.iter().any(|p| *p != Pipeline::RAW)
}

/// Every real-time group's figures, per scene, their files added to `files`.
pub fn all(data: &ReportInput, files: &mut Vec<File>) -> Result<Vec<Figure>> {
    let spec = &data.loaded.spec;
    let mut figs = Vec::new();
    for g in spec.groups.iter().filter(|g| is_realtime(g)) {
        let Some(&rays) = g.rays.iter().min() else { continue };
        for &si in &g.scenes {
            let scene = &spec.scenes[si].name;
            let stem = if g.scenes.len() > 1 { format!("{}_{scene}", g.name) } else { g.name.clone() };
            figs.extend(frame_curves(data, g, scene, rays, &stem, files)?);
            figs.extend(final_crops(data, g, si, rays, &stem, files)?);
        }
    }
    Ok(figs)
}

/// The records of one configuration under one pipeline and schedule.
fn records<'a>(
    data: &'a ReportInput,
    (scene, rays, row): (&'a str, u32, Row),
    pipeline: Pipeline,
    schedule: Schedule,
    denoiser: String,
) -> impl Iterator<Item = &'a JobResult> + 'a {
    let (p, s) = (pipeline.to_string(), schedule.name());
    // The figures show the scene's own camera without a user's denoiser: the runs whose noise part
    // is measured (a moving camera's is not), and one curve per configuration.
    data.results.iter().filter(move |r| {
        r.scene == scene
            && r.rays == rays
            && r.is_row(row)
            && r.pipeline == p
            && r.schedule == s
            && r.camera == crate::plan::CameraId::STATIC_NAME
            && r.denoiser == denoiser
    })
}

/// The denoiser whose images the figures show: the group's first, else none.
fn first_denoiser(g: &Group) -> String {
    g.denoisers.first().map_or(String::new(), |d| d.name())
}

/// Noise RMSE (against the equally filtered reference) against the frame index under the group's
/// first accumulating pipeline, one series per configuration, one plot per schedule.
fn frame_curves(
    data: &ReportInput,
    g: &Group,
    scene: &str,
    rays: u32,
    stem: &str,
    files: &mut Vec<File>,
) -> Result<Vec<Figure>> {
    let Some(&pipeline) = g.pipelines.iter().find(|p| p.is_temporal()) else { return Ok(vec![]) };
    let mut figs = Vec::new();
    for &schedule in &g.schedules {
        let mut series = Vec::new();
        for &row in &g.rows {
            let mut by_frame: BTreeMap<u32, Vec<f64>> = BTreeMap::new();
            for r in records(data, (scene, rays, row), pipeline, schedule, first_denoiser(g)) {
                if r.noise_rmse.is_finite() {
                    by_frame.entry(r.frame).or_default().push(r.noise_rmse);
                }
            }
            let points: Vec<(f64, f64, f64)> = by_frame
                .iter()
                .map(|(&f, v)| {
                    let (m, sd) = crate::metrics::mean_sd(v);
                    (f as f64, m, if sd.is_finite() { sd } else { 0.0 })
                })
                .collect();
            if !points.is_empty() {
                series.push(Series::new(row_label(row), points));
            }
        }
        if series.is_empty() {
            continue;
        }
        let per = if rays == 1 { "ray" } else { "rays" };
        let title =
            format!("'{scene}', {rays} {per}/frame, {pipeline}, {}: noise after k frames", schedule.name());
        let caption = format!(
            "{}: on '{scene}' at {rays} {per} per frame, the noise part of the error after {pipeline} (`noise_rmse`: \
             √ of the mean over pixels of each pixel's variance over the {} replicates; the bias left out), against \
             the number of frames accumulated; schedule {} (how each frame's seed moves). An EMA converges to a \
             floor set by α, not to zero.",
            g.name,
            g.replicates,
            schedule.name()
        );
        let base = format!("{stem}_frames_{}", schedule.name());
        figs.push(log_log(
            files,
            &base,
            LogLog {
                title: &title,
                axes: ("frames accumulated", "noise RMSE"),
                series: &series,
                guides: &[],
            },
            caption,
        )?);
    }
    Ok(figs)
}

/// The window of a third of the image's width and height where the reference changes most (the sum
/// of its squared differences between neighbours): contact shadows and edges, where filters blur
/// and samplers differ.
fn busiest_window(reference: &Image, coverage: &Image) -> (u32, u32, u32, u32) {
    let (w, h) = (reference.width, reference.height);
    let (cw, ch) = ((w / 3).max(1), (h / 3).max(1));
    let energy = |x: u32, y: u32| {
        let mut e = 0.0f64;
        for yy in y..(y + ch).min(h - 1) {
            for xx in x..(x + cw).min(w - 1) {
                if crate::image::covered(coverage, (yy * w + xx) as usize) {
                    let v = reference.at(xx, yy);
                    e += ((reference.at(xx + 1, yy) - v).powi(2) + (reference.at(xx, yy + 1) - v).powi(2))
                        as f64;
                }
            }
        }
        e
    };
    let step = 4;
    let mut best = (0, 0, f64::NEG_INFINITY);
    for y in (0..=h - ch).step_by(step) {
        for x in (0..=w - cw).step_by(step) {
            let e = energy(x, y);
            if e > best.2 {
                best = (x, y, e);
            }
        }
    }
    (best.0, best.1, cw, ch)
}

/// Replicate 0's final frame of every configuration (rows) after every pipeline at its last frame
/// (columns), first schedule, cropped to the reference's busiest window; the reference beside.
fn final_crops(
    data: &ReportInput,
    g: &Group,
    si: usize,
    rays: u32,
    stem: &str,
    files: &mut Vec<File>,
) -> Result<Vec<Figure>> {
    let scene = &data.loaded.spec.scenes[si].name;
    let Some(&schedule) = g.schedules.first() else { return Ok(vec![]) };
    let reference = &data.references[si];
    let (x, y, w, h) = busiest_window(&reference.mean, &reference.coverage);
    let mut images: Vec<Vec<(Image, Image, String)>> = Vec::new();
    for &row in &g.rows {
        let mut cells = Vec::new();
        for &p in &g.pipelines {
            let rs: Vec<&JobResult> =
                records(data, (scene, rays, row), p, schedule, first_denoiser(g)).collect();
            if rs.is_empty() && !g.cameras.contains(&crate::plan::CameraId::STATIC) {
                // Moving cameras only: no frame of the scene's view to crop beside its reference.
                return Ok(vec![]);
            }
            let last = rs.iter().map(|r| r.frame).max();
            let r =
                rs.iter().filter(|r| Some(r.frame) == last).min_by_key(|r| r.replicate).ok_or_else(|| {
                    Error::Refused(format!("no {p} result for {} at {rays} rays on '{scene}'", row.label()))
                })?;
            let (img, cov) = data.image(r)?;
            let caption = format!("frame {}: RMSE {:.4}, noise {:.4}", r.frame, r.rmse, r.noise_rmse);
            cells.push((img.crop(x, y, w, h), cov.crop(x, y, w, h), caption));
        }
        images.push(cells);
    }
    let cells = grid_cells(&images);
    let (ref_img, ref_cov) = (reference.mean.crop(x, y, w, h), reference.coverage.crop(x, y, w, h));
    let ref_cell = GridCell { image: &ref_img, mask: Some(&ref_cov), caption: "reference".into() };
    let row_labels: Vec<String> = g.rows.iter().map(|r| row_label(*r)).collect();
    let col_labels: Vec<String> = g.pipelines.iter().map(|p| p.to_string()).collect();
    let per = if rays == 1 { "ray" } else { "rays" };
    let title = format!(
        "{}: final frames, '{scene}', {rays} {per}/frame, {}, replicate 0 (crop)",
        g.name,
        schedule.name()
    );
    let name = format!("{stem}_final.png");
    let bytes = drawn(&name, report::image_grid(&title, &row_labels, &col_labels, &cells, Some(&ref_cell)));
    let caption = format!(
        "{}: what a real-time user sees on '{scene}' at {rays} {per} per frame — each configuration's last \
         measured frame after each pipeline (replicate 0, schedule {}), cropped to the {w}×{h} px window at \
         ({x}, {y}) where the reference changes most; captions give that image's RMSE against the reference \
         and its noise RMSE against the equally filtered reference.",
        g.name,
        schedule.name()
    );
    Ok(vec![add_figure(files, &name, caption, vec![], bytes)?])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_busiest_window_holds_the_edge() {
        // A step from 0 to 1 at x = 40 of a 60x30 image: the window (20x10) must contain it.
        let (w, h) = (60, 30);
        let img = Image::from_vec(w, h, (0..w * h).map(|i| if i % w >= 40 { 1.0 } else { 0.0 }).collect());
        let cov = Image::from_vec(w, h, vec![1.0; (w * h) as usize]);
        let (x, _, cw, ch) = busiest_window(&img, &cov);
        assert_eq!((cw, ch), (20, 10));
        assert!(x <= 39 && x + cw >= 40, "window at x {x}: it holds pixel 39, whose right neighbour differs");
        assert_eq!(img.crop(x, 0, cw, ch).data.len(), 200);
        assert_eq!(img.crop(55, 25, 20, 10).data.len(), 25, "clipped at the border");
    }
}

//! The real-time figures, for every group with frames, schedules or pipelines: the noise
//! left after k accumulated frames, one plot per schedule, and per camera a crop grid of the final
//! frames (every configuration × every pipeline at its last frame, the reference beside) with its
//! signed error and FLIP maps, cropped where the two best configurations differ most. All at the
//! group's fewest rays per frame, where real-time engines work and samplers differ most.

use super::data::{ReportInput, row_label};
use super::draw::{LogLog, add_figure, drawn, grid_cells, log_log};
use crate::denoise::Pipeline;
use crate::error::Result;
use crate::image::Image;
use crate::outdir::File;
use crate::plan::{CameraId, DenoiserId};
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
    per_scene(data, files, true)
}

/// Only the crop grids of the final frames (image, signed error, FLIP) of every real-time group, at
/// its fewest rays per frame, per scene and camera: what advise's page shows of its top
/// configurations (it measures one frame, so it has no frame curves).
pub fn final_frames(data: &ReportInput, files: &mut Vec<File>) -> Result<Vec<Figure>> {
    per_scene(data, files, false)
}

/// Per real-time group and scene, at the group's fewest rays: the frame curves (with `curves`)
/// and the final frames' crop grids.
fn per_scene(data: &ReportInput, files: &mut Vec<File>, curves: bool) -> Result<Vec<Figure>> {
    let spec = &data.loaded.spec;
    let mut figs = Vec::new();
    for g in spec.groups.iter().filter(|g| is_realtime(g)) {
        let Some(&rays) = g.rays.iter().min() else { continue };
        for &si in &g.scenes {
            let scene = &spec.scenes[si].name;
            let stem = if g.scenes.len() > 1 { format!("{}_{scene}", g.name) } else { g.name.clone() };
            if curves {
                figs.extend(frame_curves(data, g, scene, rays, &stem, files)?);
            }
            figs.extend(final_crops(data, g, si, rays, &stem, files)?);
        }
    }
    Ok(figs)
}

/// The records of one configuration under one pipeline and schedule, seen by `camera`.
fn records<'a>(
    data: &'a ReportInput,
    (scene, rays, row): (&'a str, u32, Row),
    pipeline: Pipeline,
    schedule: Schedule,
    (camera, denoiser): (CameraId, DenoiserId),
) -> impl Iterator<Item = &'a JobResult> + 'a {
    data.results.iter().filter(move |r| {
        r.scene == scene
            && r.rays == rays
            && r.is_row(row)
            && r.measurement().is_some_and(|m| {
                m.pipeline == pipeline
                    && m.schedule == schedule
                    && m.camera == camera
                    && m.denoiser == denoiser
            })
    })
}

/// The denoiser whose images the figures show: the group's first, else none.
fn first_denoiser(g: &Group) -> DenoiserId {
    g.denoisers.first().copied().unwrap_or(DenoiserId::NONE)
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
            // The scene's own camera: the one whose noise part is measured (a moving camera's is not).
            let view = (CameraId::STATIC, first_denoiser(g));
            for r in records(data, (scene, rays, row), pipeline, schedule, view) {
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

/// The window of a third of the image's width and height with the largest sum of `energy` (one
/// value per pixel, row by row), on a 4-pixel grid.
fn best_window(energy: &[f64], w: u32, h: u32) -> (u32, u32, u32, u32) {
    let (cw, ch) = ((w / 3).max(1), (h / 3).max(1));
    let (wu, hu) = (w as usize, h as usize);
    // A summed-area table: any window's sum in four reads.
    let mut sat = vec![0.0f64; (wu + 1) * (hu + 1)];
    for y in 0..hu {
        for x in 0..wu {
            sat[(y + 1) * (wu + 1) + x + 1] =
                energy[y * wu + x] + sat[y * (wu + 1) + x + 1] + sat[(y + 1) * (wu + 1) + x]
                    - sat[y * (wu + 1) + x];
        }
    }
    let (cwu, chu) = (cw as usize, ch as usize);
    let sum = |x: usize, y: usize| {
        let (x1, y1) = (x + cwu, y + chu);
        sat[y1 * (wu + 1) + x1] - sat[y * (wu + 1) + x1] - sat[y1 * (wu + 1) + x] + sat[y * (wu + 1) + x]
    };
    let mut best = (0, 0, f64::NEG_INFINITY);
    for y in (0..=hu - chu).step_by(4) {
        for x in (0..=wu - cwu).step_by(4) {
            let e = sum(x, y);
            if e > best.2 {
                best = (x, y, e);
            }
        }
    }
    (best.0 as u32, best.1 as u32, cw, ch)
}

/// Where the reference changes most (the sum of its squared differences between neighbours):
/// contact shadows and edges. The crop when there are no two configurations to tell apart.
fn busiest_window(reference: &Image, coverage: &Image) -> (u32, u32, u32, u32) {
    let (w, h) = (reference.width, reference.height);
    let energy: Vec<f64> = (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            if x + 1 >= w || y + 1 >= h || !crate::image::covered(coverage, i as usize) {
                return 0.0;
            }
            let v = reference.at(x, y);
            ((reference.at(x + 1, y) - v).powi(2) + (reference.at(x, y + 1) - v).powi(2)) as f64
        })
        .collect();
    best_window(&energy, w, h)
}

/// Where the two best configurations' images differ most: for each pair (one per pipeline), their
/// difference over the pixels both cover, blurred by a Gaussian of `LOWPASS_SIGMA` px so that
/// independent noise averages out and what differs in structure (a contact shadow one keeps and
/// the other loses, a band, a ghost) stays; squared and summed over the pairs. `None` without a
/// pair.
fn differing_window(pairs: &[(&Image, &Image, &Image)]) -> Option<(u32, u32, u32, u32)> {
    let (a0, _, _) = pairs.first()?;
    let (w, h) = (a0.width, a0.height);
    let mut energy = vec![0.0f64; (w * h) as usize];
    for (a, b, cov) in pairs {
        let diff = Image::from_vec(w, h, a.data.iter().zip(&b.data).map(|(x, y)| x - y).collect());
        let smooth = crate::denoise::gaussian::gaussian(&diff, cov, crate::metrics::LOWPASS_SIGMA);
        for (i, e) in energy.iter_mut().enumerate() {
            if crate::image::covered(cov, i) {
                *e += (smooth.data[i] as f64).powi(2);
            }
        }
    }
    Some(best_window(&energy, w, h))
}

/// Every camera's crops of the group's final frames (`camera_crops`).
fn final_crops(
    data: &ReportInput,
    g: &Group,
    si: usize,
    rays: u32,
    stem: &str,
    files: &mut Vec<File>,
) -> Result<Vec<Figure>> {
    let mut figs = Vec::new();
    for &camera in &g.cameras {
        figs.extend(camera_crops(data, g, (si, rays, camera), stem, files)?);
    }
    Ok(figs)
}

/// One cell of the crop grids: a configuration's final frame after a pipeline.
struct Final<'a> {
    record: &'a JobResult,
    /// Mean RMSE over the replicates at that frame: what "best" ranks by.
    mean_rmse: f64,
}

/// Replicate 0's final frame of every configuration (rows) after every pipeline at its last frame
/// (columns; a moving camera: the pipelines measured at the group's last frame, so every crop is
/// one view), first schedule, seen by `camera`, cropped to the window where the two best
/// configurations differ most; the reference beside. Then the same crops as signed error and, when
/// the run makes them, as FLIP maps.
fn camera_crops(
    data: &ReportInput,
    g: &Group,
    (si, rays, camera): (usize, u32, CameraId),
    stem: &str,
    files: &mut Vec<File>,
) -> Result<Vec<Figure>> {
    let scene = &data.loaded.spec.scenes[si].name;
    let Some(&schedule) = g.schedules.first() else { return Ok(vec![]) };
    let moving = camera.run().is_some_and(|r| !r.path.is_static());
    let pipelines: Vec<Pipeline> = g
        .pipelines
        .iter()
        .copied()
        .filter(|&p| !moving || crate::plan::pipeline_frames(p, g.frames).last() == Some(&g.frames))
        .collect();
    let mut finals: Vec<Vec<Final>> = Vec::new();
    for &row in &g.rows {
        let mut cells = Vec::new();
        for &p in &pipelines {
            let rs: Vec<&JobResult> =
                records(data, (scene, rays, row), p, schedule, (camera, first_denoiser(g))).collect();
            let Some(last) = rs.iter().map(|r| r.frame).max() else { return Ok(vec![]) };
            let at_last: Vec<&JobResult> = rs.into_iter().filter(|r| r.frame == last).collect();
            let record =
                at_last.iter().min_by_key(|r| r.replicate).copied().expect("a record at its last frame");
            let mean_rmse = crate::metrics::mean_sd(&at_last.iter().map(|r| r.rmse).collect::<Vec<_>>()).0;
            cells.push(Final { record, mean_rmse });
        }
        finals.push(cells);
    }
    let Some(first) = finals.first().and_then(|row| row.first()) else { return Ok(vec![]) };
    let Some(reference) = data.reference_at(si, camera, first.record.frame) else { return Ok(vec![]) };
    let mut full: Vec<Vec<(Image, Image)>> = Vec::new();
    for row in &finals {
        full.push(row.iter().map(|f| data.image(f.record)).collect::<Result<Vec<_>>>()?);
    }
    // Per pipeline, the two configurations with the least mean RMSE.
    let mut both = Vec::new();
    for j in 0..pipelines.len() {
        let mut order: Vec<usize> = (0..finals.len()).collect();
        order.sort_by(|&a, &b| finals[a][j].mean_rmse.total_cmp(&finals[b][j].mean_rmse));
        if let [a, b, ..] = order[..] {
            let cov = crate::report::viewer::layers::both(&full[a][j].1, &full[b][j].1);
            both.push((a, b, j, cov));
        }
    }
    let pairs: Vec<(&Image, &Image, &Image)> =
        both.iter().map(|(a, b, j, cov)| (&full[*a][*j].0, &full[*b][*j].0, cov)).collect();
    let differ = differing_window(&pairs);
    let (x, y, w, h) = differ.unwrap_or_else(|| busiest_window(&reference.mean, &reference.coverage));
    let crop = |i: &Image| i.crop(x, y, w, h);
    let images: Vec<Vec<(Image, Image, String)>> = finals
        .iter()
        .zip(&full)
        .map(|(row, imgs)| {
            row.iter()
                .zip(imgs)
                .map(|(f, (img, cov))| {
                    let r = f.record;
                    let noise = if r.noise_rmse.is_finite() {
                        format!(", noise {:.4}", r.noise_rmse)
                    } else {
                        String::new()
                    };
                    (crop(img), crop(cov), format!("frame {}: RMSE {:.4}{noise}", r.frame, r.rmse))
                })
                .collect()
        })
        .collect();
    let cells = grid_cells(&images);
    let (ref_img, ref_cov) = (crop(&reference.mean), crop(&reference.coverage));
    let ref_cell = GridCell { image: &ref_img, mask: Some(&ref_cov), caption: "reference".into() };
    let row_labels: Vec<String> = g.rows.iter().map(|r| row_label(*r)).collect();
    let col_labels: Vec<String> = pipelines.iter().map(|p| p.to_string()).collect();
    let per = if rays == 1 { "ray" } else { "rays" };
    let cam = camera.name();
    let base = if camera == CameraId::STATIC {
        format!("{stem}_final")
    } else {
        format!("{stem}_final_{}", crate::report::viewer::slug(&cam))
    };
    let title = format!(
        "{}: final frames, '{scene}', {cam} camera, {rays} {per}/frame, {}, replicate 0 (crop)",
        g.name,
        schedule.name()
    );
    let name = format!("{base}.png");
    let bytes = drawn(&name, report::image_grid(&title, &row_labels, &col_labels, &cells, Some(&ref_cell)));
    let window = match differ {
        Some(_) => {
            "where the two configurations with the least RMSE differ most (under each pipeline, the \
                    difference of their images blurred by a Gaussian of 1.5 px, so that noise averages out and \
                    structure stays; squared and summed over the pipelines)"
        }
        None => "where the reference changes most",
    };
    let what = format!(
        "'{scene}' at {rays} {per} per frame, {cam} camera — each configuration's last measured frame after each \
         pipeline (replicate 0, schedule {}), cropped to the {w}×{h} px window at ({x}, {y}) {window}",
        schedule.name()
    );
    let caption = format!(
        "{}: what a real-time user sees on {what}; captions give that image's RMSE against the reference and, \
         where it is measured, its noise RMSE against the equally filtered reference.",
        g.name
    );
    let mut figs = vec![add_figure(files, &name, caption, vec![], bytes)?];
    let name = format!("{base}_error.png");
    let title =
        format!("{}: signed error of the final frames (image − reference), {cam} camera (crop)", g.name);
    let bytes = drawn(&name, report::error_grid(&title, &row_labels, &col_labels, &cells, &ref_cell, None));
    let caption = format!(
        "{}: the signed error of the crops above against the reference of their frame (red = too open, blue = \
         too occluded, slate = no surface), one symmetric scale for the whole table, stated on its bar.",
        g.name
    );
    figs.push(add_figure(files, &name, caption, vec![], bytes)?);
    if let Some(flip) = data.flip {
        let maps: Vec<Vec<(Image, Image, String)>> = full
            .iter()
            .map(|row| {
                row.iter()
                    .map(|(img, cov)| {
                        let cov = crate::report::viewer::layers::both(cov, &reference.coverage);
                        let map = flip.of(&reference.mean, img);
                        let mean = (flip.mean)(&map, &cov);
                        (crop(&map), crop(&cov), format!("mean FLIP {mean:.4}"))
                    })
                    .collect()
            })
            .collect();
        let name = format!("{base}_flip.png");
        let title = format!("{}: FLIP maps of the final frames, {cam} camera (crop)", g.name);
        let bytes = drawn(&name, report::flip_grid(&title, &row_labels, &col_labels, &grid_cells(&maps)));
        let caption = format!(
            "{}: LDR-FLIP of the same frames against their reference at {} pixels per degree (0 = no visible \
             difference, black), computed on the whole image and cropped; captions give the mean over the \
             whole image's covered pixels.",
            g.name, flip.ppd
        );
        figs.push(add_figure(files, &name, caption, vec![], bytes)?);
    }
    Ok(figs)
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

    /// Two noisy images that differ in structure only in one blob: the window holds the blob, and
    /// the noise (larger per pixel than the blob) does not pull it away.
    #[test]
    fn the_differing_window_holds_the_structure_not_the_noise() {
        let (w, h) = (90, 60);
        let noise = |seed: u32| {
            (0..w * h)
                .map(|i| {
                    let v = crate::sampling::hash::hash(seed as u64, i as u64) >> 40;
                    0.5 + 0.4 * ((v as f32 / (1u64 << 24) as f32) - 0.5)
                })
                .collect::<Vec<f32>>()
        };
        let a = Image::from_vec(w, h, noise(1));
        let mut b = Image::from_vec(w, h, noise(2));
        for y in 40..50 {
            for x in 10..20 {
                b.data[(y * w + x) as usize] -= 0.1;
            }
        }
        let cov = Image::from_vec(w, h, vec![1.0; (w * h) as usize]);
        let (x, y, cw, ch) = differing_window(&[(&a, &b, &cov)]).unwrap();
        assert_eq!((cw, ch), (30, 20));
        assert!(x <= 10 && x + cw >= 20 && y <= 40 && y + ch >= 50, "window at ({x}, {y})");
        assert!(differing_window(&[]).is_none());
    }
}

//! Which images the run page's comparison viewer gets, and their layers (`report::viewer` draws
//! them): the files added to the report's and the page's section returned.
//!
//! The rule, which bounds the bytes: per view (scene × camera × rays per frame) and per cell in it
//! (pipeline × schedule × denoiser), the `BEST` configurations with the least mean RMSE over the
//! replicates at the cell's last frame, plus the paper's configuration; every measured frame of
//! the lowest replicate; each as image, signed error and FLIP map; the reference of every frame.
//! For experiments/realtime.toml that is 18 views of at most 12 series of 1 or 7 frames (about
//! 1,300 images, three PNGs each), whatever the replicate count: one of its views (kitchen, 1 ray,
//! 320×180) measured 7.5 MB, so about 140 MB in all beside its images' few GB of EXR.

use super::data::{ReportInput, row_label};
use crate::compare::claims::COSINE_FIB_PIXEL;
use crate::denoise::Pipeline;
use crate::error::{Error, Result};
use crate::image::Image;
use crate::outdir::File;
use crate::plan::{CameraId, DenoiserId, Measurement};
use crate::reference::store::Reference;
use crate::report::viewer::{self, Frame, Gradients, Manifest, ReferenceFrame, Series, View, layers, slug};
use crate::results::JobResult;
use crate::sampling::Schedule;
use crate::spec::Row;
use rayon::prelude::*;

/// A drawn layer (a PNG, or why it could not be drawn).
type Png = std::result::Result<Vec<u8>, String>;

/// One image's drawn layers: image, signed error, and the FLIP map with its mean.
type Layers = (Png, Png, Option<(Png, f64)>);

/// Configurations per cell besides the paper's.
pub const BEST: usize = 2;

/// One cell's configuration: what a series is.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Key {
    row: Row,
    pipeline: Pipeline,
    schedule: Schedule,
    denoiser: DenoiserId,
}

/// One view: a scene seen by a camera at a ray count, and the series chosen in it.
struct ViewPlan {
    si: usize,
    camera: CameraId,
    rays: u32,
    keys: Vec<Key>,
}

/// The records of a key in a view, each with its parsed measurement.
fn records<'a>(
    parsed: &'a [(Measurement, &'a JobResult)],
    scene: &'a str,
    v: (CameraId, u32),
    k: Key,
) -> impl Iterator<Item = &'a JobResult> + 'a {
    parsed
        .iter()
        .filter(move |(m, r)| {
            r.scene == scene
                && r.rays == v.1
                && m.camera == v.0
                && m.pipeline == k.pipeline
                && m.schedule == k.schedule
                && m.denoiser == k.denoiser
                && r.is_row(k.row)
        })
        .map(|(_, r)| *r)
}

/// Mean RMSE over the replicates at the last frame of `rs`.
fn last_frame_rmse<'a>(rs: impl Iterator<Item = &'a JobResult>) -> Option<f64> {
    let rs: Vec<&JobResult> = rs.collect();
    let last = rs.iter().map(|r| r.frame).max()?;
    let v: Vec<f64> = rs.iter().filter(|r| r.frame == last).map(|r| r.rmse).collect();
    Some(crate::metrics::mean_sd(&v).0)
}

/// The views and series the rule picks, in spec order.
fn plan(data: &ReportInput, parsed: &[(Measurement, &JobResult)]) -> Vec<ViewPlan> {
    let spec = &data.loaded.spec;
    let mut views: Vec<ViewPlan> = Vec::new();
    for g in &spec.groups {
        for &si in &g.scenes {
            let scene = &spec.scenes[si].name;
            for &camera in &g.cameras {
                for &rays in &g.rays {
                    let at = match views.iter().position(|v| (v.si, v.camera, v.rays) == (si, camera, rays)) {
                        Some(i) => i,
                        None => {
                            views.push(ViewPlan { si, camera, rays, keys: Vec::new() });
                            views.len() - 1
                        }
                    };
                    for &pipeline in &g.pipelines {
                        for &schedule in &g.schedules {
                            for &denoiser in &g.denoisers {
                                let key = |row| Key { row, pipeline, schedule, denoiser };
                                let mut ranked: Vec<(Row, f64)> = g
                                    .rows
                                    .iter()
                                    .filter_map(|&row| {
                                        let rs = records(parsed, scene, (camera, rays), key(row));
                                        Some((row, last_frame_rmse(rs)?))
                                    })
                                    .collect();
                                ranked.sort_by(|a, b| a.1.total_cmp(&b.1));
                                let paper = ranked.iter().find(|(r, _)| *r == COSINE_FIB_PIXEL).map(|p| p.0);
                                let best = ranked.iter().take(BEST).map(|p| p.0);
                                for row in paper.into_iter().chain(best) {
                                    if !views[at].keys.contains(&key(row)) {
                                        views[at].keys.push(key(row));
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    views.retain(|v| !v.keys.is_empty());
    views
}

fn key_label(k: Key, many_schedules: bool) -> String {
    let mut s = format!("{} · {}", row_label(k.row), k.pipeline);
    if many_schedules {
        s += &format!(" · {}", k.schedule.name());
    }
    if k.denoiser != DenoiserId::NONE {
        s += &format!(" · {}", k.denoiser.name());
    }
    s
}

fn key_id(k: Key) -> String {
    let r = k.row;
    let mut s = format!(
        "{}.{}-{}-{}.{}",
        k.pipeline,
        r.distribution.name(),
        r.sequence.name(),
        r.seed_mode.name(),
        k.schedule.name()
    );
    if k.denoiser != DenoiserId::NONE {
        s += &format!(".{}", k.denoiser.name());
    }
    slug(&s)
}

/// The viewer's files, added to `files`, and the page's section (`None`: no image to show).
pub fn section(data: &ReportInput, files: &mut Vec<File>) -> Result<Option<String>> {
    let flip = data.flip;
    let parsed: Vec<(Measurement, &JobResult)> =
        data.results.iter().filter_map(|r| Some((r.measurement()?, r))).collect();
    let spec = &data.loaded.spec;
    let mut manifest = Manifest {
        rule: String::new(),
        flip_note: flip.map_or(String::new(), |f| format!("LDR-FLIP at {} pixels per degree", f.ppd)),
        gradients: Gradients::of_colormaps(),
        views: Vec::new(),
    };
    let (mut count, mut bytes) = (0usize, 0usize);
    let mut add = |files: &mut Vec<File>, name: String, png: std::result::Result<Vec<u8>, String>| {
        let png = png.map_err(|e| Error::Refused(format!("{name}: cannot draw the viewer's image: {e}")))?;
        count += 1;
        bytes += png.len();
        files.push(File::new(&name, png));
        Ok::<String, Error>(name)
    };
    for vp in plan(data, &parsed) {
        let scene = &spec.scenes[vp.si].name;
        let many_schedules = vp.keys.iter().any(|k| k.schedule != vp.keys[0].schedule);
        let vid = slug(&format!("{scene}.{}.{}r", vp.camera.name(), vp.rays));
        let dir = format!("{}/{vid}", viewer::DIR);
        // Per series, the lowest replicate's record at each frame.
        let chosen: Vec<Vec<&JobResult>> = vp
            .keys
            .iter()
            .map(|&k| {
                let rs: Vec<&JobResult> = records(&parsed, scene, (vp.camera, vp.rays), k).collect();
                let mut frames: Vec<u32> = rs.iter().map(|r| r.frame).collect();
                frames.sort_unstable();
                frames.dedup();
                frames
                    .into_iter()
                    .filter_map(|f| rs.iter().filter(|r| r.frame == f).min_by_key(|r| r.replicate).copied())
                    .collect()
            })
            .collect();
        let mut frames: Vec<u32> = chosen.iter().flatten().map(|r| r.frame).collect();
        frames.sort_unstable();
        frames.dedup();
        let mut series: Vec<Series> = vp
            .keys
            .iter()
            .map(|&k| Series {
                id: key_id(k),
                label: key_label(k, many_schedules),
                paper: k.row == COSINE_FIB_PIXEL,
                frames: Vec::new(),
            })
            .collect();
        let mut reference = Vec::new();
        let (mut width, mut height) = (0, 0);
        let mut last_ref: Option<&Reference> = None;
        for &f in &frames {
            let Some(rf) = data.reference_at(vp.si, vp.camera, f) else { continue };
            (width, height) = (rf.mean.width, rf.mean.height);
            if !last_ref.is_some_and(|l| std::ptr::eq(l, rf)) {
                last_ref = Some(rf);
                let name = format!("{dir}/reference-f{f}.png");
                let image = add(files, name, layers::image_png(&rf.mean, &rf.coverage))?;
                reference.push(ReferenceFrame { frame: f, image });
            }
            // This frame's images of every series, then one error scale for them all; read and drawn
            // on the run's threads, one series a task, and added to the files in series order (the
            // same files: experiments/realtime.toml resumed, the whole run 56.1 -> 35.9 s on 2 cores).
            let picked: Vec<(usize, &JobResult)> = chosen
                .iter()
                .enumerate()
                .filter_map(|(si, rs)| Some((si, *rs.iter().find(|r| r.frame == f)?)))
                .collect();
            let shown: Vec<(usize, &JobResult, Image, Image, Image)> = picked
                .par_iter()
                .map(|&(si, r)| {
                    let (img, cov) = data.image(r)?;
                    if !img.same_size(&rf.mean) {
                        return Err(Error::Refused(format!(
                            "{}: its image is {}x{} but its reference {}x{}",
                            r.image, img.width, img.height, rf.mean.width, rf.mean.height
                        )));
                    }
                    let cov = layers::both(&cov, &rf.coverage);
                    let error = layers::signed_error(&img, &rf.mean, &cov);
                    Ok((si, r, img, cov, error))
                })
                .collect::<Result<_>>()?;
            let scale = layers::error_scale(shown.iter().map(|s| &s.4));
            let drawn: Vec<Layers> = shown
                .par_iter()
                .map(|(_, _, img, cov, error)| {
                    let flip = flip.map(|fl| {
                        let m = fl.of(&rf.mean, img);
                        ((layers::flip_png(&m, cov)), (fl.mean)(&m, cov))
                    });
                    (layers::image_png(img, cov), layers::error_png(error, cov, scale), flip)
                })
                .collect();
            for ((si, r, ..), (image_png, error_png, flip_png)) in shown.into_iter().zip(drawn) {
                let stem = format!("{dir}/{}-f{f}", series[si].id);
                let image = add(files, format!("{stem}-image.png"), image_png)?;
                let error = add(files, format!("{stem}-error.png"), error_png)?;
                let (flip, flip_mean) = match flip_png {
                    Some((png, mean)) => (Some(add(files, format!("{stem}-flip.png"), png)?), Some(mean)),
                    None => (None, None),
                };
                series[si].frames.push(Frame {
                    frame: f,
                    replicate: r.replicate,
                    image,
                    error,
                    error_scale: scale,
                    flip,
                    rmse: r.rmse,
                    flip_mean,
                });
            }
        }
        series.retain(|s| !s.frames.is_empty());
        if series.is_empty() || reference.is_empty() {
            continue;
        }
        series.sort_by_key(|s| !s.paper);
        let per = if vp.rays == 1 { "ray" } else { "rays" };
        manifest.views.push(View {
            id: vid,
            title: format!("'{scene}', {} camera, {} {per}/frame", vp.camera.name(), vp.rays),
            width,
            height,
            frames,
            reference,
            series,
        });
    }
    if manifest.views.is_empty() {
        return Ok(None);
    }
    let layers_text =
        if flip.is_some() { "image, signed error and FLIP map" } else { "image and signed error" };
    manifest.rule = format!(
        "Per scene, camera and rays per frame, and per pipeline, schedule and denoiser there: the {BEST} \
         configurations with the least mean RMSE at the last frame, and the paper's (sine-cosine × Fibonacci \
         × per-pixel seed); every measured frame of the lowest replicate, each as {layers_text} (8-bit \
         PNG, the report's grey), and the reference of every frame: {count} PNG files, {:.1} MB.",
        bytes as f64 / 1e6
    );
    let intro = format!(
        "Pick a view, then the configuration on the left and on the right (or the reference); drag the \
         yellow split; zoom with the wheel or the buttons down to single pixels and drag to pan; step the \
         frames; switch between the image, its signed error against the reference and its FLIP map. The \
         link under the controls (and the address bar) holds the view, so it can be sent. What is here: {}",
        manifest.rule
    );
    files.push(File::new(viewer::MANIFEST_JS, viewer::manifest_js(&manifest)));
    files.push(File::new(viewer::SCRIPT_JS, viewer::SCRIPT));
    Ok(Some(viewer::section_html(&intro)))
}

//! A recorded job's own work besides its render, for the calibration (`calibrate`): its metrics,
//! FLIP and image file, timed on one calibration render, and the bytes its image and its record
//! take. Apart from the renders' calibration because it times the measuring, not the rays.

use crate::error::{Error, Result};
use crate::image::{self, Channel};
use crate::io;
use crate::load::Loaded;
use crate::plan::Plan;
use crate::render::RenderOutput;
use crate::results::{self, JobResult};
use crate::timing::clock;

/// Bytes per pixel of two uncompressed 32-bit channels: a job image's size when no calibration
/// image was encoded.
pub const EXR_BYTES_PER_PIXEL_AT_MOST: f64 = 8.0;

/// What the calibration measured of a job's work after its render.
pub struct PostCost {
    /// Bytes per pixel of a job's image as written: a raw frame's …
    pub exr_bytes_per_pixel: f64,
    /// … and a filtered one's (smooth values compress least).
    pub filtered_exr_bytes_per_pixel: f64,
    /// Bytes of one record in results.json and results.csv together.
    pub record_bytes: f64,
    /// Seconds per job for its metrics, FLIP and image file (wall time where the file's fsync
    /// made it the larger), at the real image's size.
    pub measure_s: f64,
    /// CPU seconds per record of writing the results files.
    pub serialize_per_record_s: f64,
}

/// `sample`: a calibration render of several rays (and its scene); `noisiest`: a 1-ray one;
/// `ratio_of`: per scene, how many times more pixels the real image has.
pub(super) fn post_cost(
    loaded: &Loaded,
    full: &Plan,
    sample: Option<(usize, RenderOutput)>,
    noisiest: Option<RenderOutput>,
    ratio_of: &[f64],
) -> Result<PostCost> {
    let mut p = PostCost {
        exr_bytes_per_pixel: EXR_BYTES_PER_PIXEL_AT_MOST,
        filtered_exr_bytes_per_pixel: EXR_BYTES_PER_PIXEL_AT_MOST,
        record_bytes: 0.0,
        measure_s: 0.0,
        serialize_per_record_s: 0.0,
    };
    if let Some(n) = &noisiest {
        let per_pixel = |ao: &image::Image| {
            image::encode_exr(&[Channel { name: "Y", image: ao }, Channel { name: "A", image: &n.coverage }])
                .map(|b| b.len() as f64 / ao.len().max(1) as f64)
        };
        if let Ok(b) = per_pixel(&n.ao) {
            p.exr_bytes_per_pixel = b;
        }
        let smooth = crate::denoise::gaussian(&n.ao, &n.coverage, crate::denoise::GAUSS_SIGMA);
        if let Ok(b) = per_pixel(&smooth) {
            p.filtered_exr_bytes_per_pixel = b;
        }
    }
    let Some((si, out)) = sample else { return Ok(p) };
    // Against another render of the scene, as a job is against its reference: the metrics of an
    // error image of zeros cost less (the integrands spec's per-job work came out at a quarter of
    // what the run spent).
    let other = noisiest.as_ref().map(|n| &n.ao).filter(|a| a.same_size(&out.ao));
    let reference = other.unwrap_or(&out.ao);
    // Every record has its FLIP too (`jobs::measure::flip`), against a reference whose own half of
    // the map a run makes once for many jobs (`jobs::flip_refs`): made before the clock starts.
    let flip_reference = crate::metrics::flip::FlipReference::new(reference, loaded.spec.flip_ppd);
    let (c0, w0) = (clock::thread_cpu_s(), clock::wall_s());
    let stats = crate::metrics::measure(&out.ao, reference, &out.coverage)
        .map_err(|e| Error::Refused(format!("calibration: {e}")))?;
    let map = flip_reference.map(&out.ao);
    let _ = crate::metrics::flip::mean_flip(&map, &out.coverage);
    // Written as a job's image is (`io::write_atomic`: a new file, fsync, rename), in wall time: a
    // worker waits for the disk as it computes (the integrands spec's 2,544 small jobs spent 8 ms
    // each after their renders, creating files a good part of it).
    let channels = [Channel { name: "Y", image: &out.ao }, Channel { name: "A", image: &out.coverage }];
    let probe = std::env::temp_dir().join(format!("hemilab-calibration-{}.exr", std::process::id()));
    if io::write_exr(&probe, &channels).is_err() {
        let _ = image::encode_exr(&channels);
    }
    let _ = io::remove_file_if_exists(&probe);
    let measure_s = (clock::thread_cpu_s() - c0).max(clock::wall_s() - w0);
    let c1 = clock::thread_cpu_s();
    let records: Vec<JobResult> =
        full.jobs.iter().map(|j| JobResult::new(j, &stats, out.rays, crate::outdir::image_rel(j))).collect();
    let text = (results::to_json(&records), results::to_csv(&records));
    let c2 = clock::thread_cpu_s();
    p.record_bytes = (text.0.len() + text.1.len()) as f64 / records.len().max(1) as f64;
    p.measure_s = measure_s * ratio_of[si];
    p.serialize_per_record_s = (c2 - c1) / full.jobs.len().max(1) as f64;
    Ok(p)
}

//! `results.csv`: one line per record, the columns of `CSV_COLUMNS` in their order (a spreadsheet
//! reads it; `results.json` is the file every command resumes from).

use super::{CSV_COLUMNS, JobResult, csv_field, num};

/// `results.csv`: a header with `CSV_COLUMNS`, then one line per record.
pub fn to_csv(results: &[JobResult]) -> String {
    let mut s = CSV_COLUMNS.join(",");
    s.push('\n');
    for r in results {
        let fields = [
            csv_field(&r.scene),
            csv_field(&r.distribution),
            csv_field(&r.sequence),
            csv_field(&r.seed_mode),
            r.rays.to_string(),
            r.replicate.to_string(),
            r.seed.to_string(),
            num(r.rmse),
            num(r.bias),
            num(r.autocorr_x),
            num(r.autocorr_y),
            num(r.lowpass_rmse),
            num(r.time_s),
            num(r.rays_per_s),
            num(r.whiteness_z),
            r.rays_cast.to_string(),
            num(r.time_median_s),
            num(r.time_min_s),
            num(r.time_max_s),
            r.timings.to_string(),
            num(r.overhead_s),
            num(r.ao_time_s),
            num(r.ns_per_ray),
            r.efficiency.map_or(String::new(), num),
            r.timing_threads.to_string(),
            num(r.wall_s),
            r.covered_pixels.to_string(),
            csv_field(&r.key),
            csv_field(&r.image),
            num(r.lowfreq_ratio),
            csv_field(&r.pipeline),
            r.frame.to_string(),
            csv_field(&r.schedule),
            num(r.noise_rmse),
            csv_field(&r.integrand),
            csv_field(&r.camera),
            csv_field(&r.denoiser),
            num(r.flicker.unwrap_or(f64::NAN)),
            num(r.floor.unwrap_or(f64::NAN)),
            num(r.denoise_s),
            num(r.flip),
            num(r.bias_rmse),
            num(r.bias_se),
        ];
        s.push_str(&fields.join(","));
        s.push('\n');
    }
    s
}

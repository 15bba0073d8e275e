//! Unit tests of `results` (kept apart so the module itself stays readable at one sitting).

use super::*;
use crate::sampling::{Distribution, SeedMode, Sequence};

pub(super) fn job(rays: u32, replicate: u32) -> Job {
    Job {
        scene: "scenes/k.toml".into(),
        scene_id: "../scenes/k.toml".into(),
        scene_name: "k".into(),
        distribution: Distribution::SineCosine,
        sequence: Sequence::Fibonacci,
        seed_mode: SeedMode::Rotation,
        rays,
        replicate,
        seed: crate::plan::replicate_seed(1, replicate),
        resolution: Some([4, 4]),
        ao_distance: None,
        measurement: crate::plan::Measurement::PAPER,
    }
}

pub(super) fn result(rays: u32, replicate: u32, rmse: f64, time_s: f64) -> JobResult {
    let stats = ErrorStats {
        covered: 16,
        rmse,
        bias: 0.01 * replicate as f64,
        autocorr_x: 0.1,
        autocorr_y: -0.1,
        lowpass_rmse: rmse / 4.0,
        whiteness_z: 0.5,
        lowfreq_ratio: 0.75,
    };
    let mut r =
        JobResult::new(&job(rays, replicate), &stats, 16 * rays as u64, format!("img{rays}-{replicate}.exr"));
    // A measured record has its FLIP (a NaN would make the record unequal to itself).
    r.flip = 0.5;
    r.add_time(time_s, time_s * 1.5);
    r
}

/// Records with their configuration's timing columns, the overhead 0.1 s.
pub(super) fn timed(mut rs: Vec<JobResult>, overhead: f64) -> Vec<JobResult> {
    fill_timing(&mut rs, &|scene| (scene == "k").then_some(overhead));
    rs
}

#[test]
fn csv_header_columns_are_exact() {
    let csv = to_csv(&timed(vec![result(8, 0, 0.1, 0.5)], 0.1));
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "scene,distribution,sequence,seed_mode,rays,replicate,seed,rmse,bias,autocorr_x,autocorr_y,\
         lowpass_rmse,time_s,rays_per_s,whiteness_z,rays_cast,time_median_s,time_min_s,time_max_s,timings,overhead_s,\
         ao_time_s,ns_per_ray,efficiency,timing_threads,wall_s,covered_pixels,key,image,lowfreq_ratio,\
         pipeline,frame,schedule,noise_rmse,integrand,camera,denoiser,flicker,floor,denoise_s,flip,bias_rmse,bias_se"
    );
    let row: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(row.len(), CSV_COLUMNS.len());
    let col = |name: &str| row[CSV_COLUMNS.iter().position(|c| *c == name).unwrap()];
    assert_eq!(&row[..6], &["k", "sine-cosine", "fibonacci", "rotation", "8", "0"]);
    assert_eq!(col("rmse"), "0.1");
    assert_eq!((col("time_s"), col("rays_per_s"), col("rays_cast")), ("0.5", "256", "128"));
    assert_eq!(
        (col("time_median_s"), col("time_min_s"), col("time_max_s"), col("timings")),
        ("0.5", "0.5", "0.5", "1")
    );
    assert_eq!((col("overhead_s"), col("ao_time_s")), ("0.1", "0.4"));
    assert_eq!(col("ns_per_ray"), (1e9 * 0.4 / 128.0).to_string());
    assert_eq!(col("efficiency"), (1.0 / (0.1f64 * 0.1 * 0.4)).to_string());
    assert_eq!((col("timing_threads"), col("wall_s")), ("1", "0.75"));
    assert_eq!(col("key"), job(8, 0).key());
    assert_eq!(col("lowfreq_ratio"), "0.75");
    for c in TIME_COLUMNS {
        assert!(CSV_COLUMNS.contains(c), "{c}");
    }
}

#[test]
fn csv_quotes_awkward_fields_and_leaves_undefined_empty() {
    let mut r = result(8, 0, 0.0, 0.0);
    r.image = "a,b \"c\".exr".into();
    let csv = to_csv(&timed(vec![r], 0.1));
    let line = csv.lines().nth(1).unwrap();
    assert!(
        line.ends_with(",\"a,b \"\"c\"\".exr\",0.75,raw,1,independent,,ao,static,,,,0,0.5,,"),
        "quoted, then lowfreq_ratio and the real-time columns: {line}"
    );
    assert!(line.contains(",0,0,0.5,128,"), "time and rays_per_s 0, whiteness 0.5: {line}");
    assert!(line.contains(",0.1,,,,1,"), "below the overhead: AO time, ns per ray, efficiency empty: {line}");
}

#[test]
fn json_round_trips_exactly() {
    // 0.10253214158314959 reads back one ulp off without serde_json's `float_roundtrip`, which
    // made a resumed run's numbers differ from an uninterrupted one's.
    let mut rs = timed(
        vec![
            result(8, 0, 0.1, 0.5),
            result(8, 1, 0.12345678901234567, 0.0),
            result(4, 0, 0.10253214158314959, 1.0),
        ],
        0.3,
    );
    // The split of a configuration (NaN, which is never equal to itself, with one replicate).
    (rs[2].bias_rmse, rs[2].bias_se, rs[2].noise_rmse) = (0.012345678901234567, 0.001, 0.1);
    let back = from_json(&to_json(&rs)).unwrap();
    assert_eq!(back[2], rs[2]);
    assert!(back[2].flicker.is_none() && back[2].floor.is_none());
    // Undefined columns (NaN) are null in JSON and read back as NaN.
    assert!(rs[0].ao_time_s.is_nan() && back[0].ao_time_s.is_nan());
    assert!(back[0].noise_rmse.is_nan() && back[0].bias_rmse.is_nan(), "an undefined split stays undefined");
    assert_eq!(to_json(&back), to_json(&rs));
    assert_eq!(to_csv(&back), to_csv(&rs));
    let e = from_json("[{\"scene\": 1}]").unwrap_err();
    assert!(e.contains("line"), "{e}");
}

#[test]
fn flip_is_a_column_and_older_records_load_without_it() {
    let mut rs = timed(vec![result(8, 0, 0.1, 0.5), result(8, 1, 0.1, 0.5)], 0.1);
    rs[0].flip = 0.25;
    rs[1].flip = f64::NAN;
    let csv = to_csv(&rs);
    let col = CSV_COLUMNS.iter().position(|c| *c == "flip").unwrap();
    let field = |line: usize| csv.lines().nth(line).unwrap().split(',').nth(col).unwrap().to_string();
    assert_eq!((field(1), field(2)), ("0.25".to_string(), String::new()), "measured, then not measured");
    assert!(!TIME_COLUMNS.contains(&"flip"), "an estimator column: identical between runs");
    let back = from_json(&to_json(&rs)).unwrap();
    assert_eq!(back[0].flip, 0.25);
    assert!(back[1].flip.is_nan());
    // A results.json written before the column existed.
    let mut old: serde_json::Value = serde_json::from_str(&to_json(&rs)).unwrap();
    old.as_array_mut().unwrap().iter_mut().for_each(|r| {
        r.as_object_mut().unwrap().remove("flip");
    });
    let back = from_json(&old.to_string()).unwrap();
    assert!(back.iter().all(|r| r.flip.is_nan()));
    let aggs = aggregate(&rs);
    assert_eq!((aggs[0].flip.mean, aggs[0].flip.sd), (0.25, 0.0), "over the replicates that have it");
    rs.iter_mut().for_each(|r| r.flip = f64::NAN);
    assert!(aggregate(&rs)[0].flip.mean.is_nan(), "none measured");
}

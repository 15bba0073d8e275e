//! Pure: spec → the jobs it needs. A job is everything that determines one image, so its key names
//! the image file and decides whether a resumed run may skip it.

use crate::denoise::Pipeline;
use crate::sampling::{Distribution, Integrand, SeedMode, Sequence};
use crate::spec::{AoDistance, Row, Spec};
use std::fmt::Write as _;
use std::path::PathBuf;

pub mod cost;
pub mod forecast;
mod geometry;
mod measurement;
pub mod tiles;

pub use geometry::Geometry;
pub use measurement::{CameraId, CameraRun, Denoiser, DenoiserId, Measurement};

/// One image to render.
#[derive(Debug, Clone, PartialEq)]
pub struct Job {
    /// Where to load the scene from.
    pub scene: PathBuf,
    /// The scene as the spec wrote it (normalized); goes into the key instead of the machine's path.
    pub scene_id: String,
    /// Results' `scene` column.
    pub scene_name: String,
    pub distribution: Distribution,
    pub sequence: Sequence,
    pub seed_mode: SeedMode,
    pub rays: u32,
    pub replicate: u32,
    /// From the base seed and the replicate only, so adding a table never changes another job's image.
    pub seed: u64,
    /// `None`: the scene's own.
    pub resolution: Option<[u32; 2]>,
    /// `None`: the scene's own.
    pub ao_distance: Option<AoDistance>,
    /// What is measured of the images (integrand, frames, schedule, pipeline).
    pub measurement: Measurement,
}

impl Job {
    pub fn row(&self) -> Row {
        Row::new(self.distribution, self.sequence, self.seed_mode)
    }

    /// Everything that determines the image, as text; the version prefix lets a format change
    /// invalidate old keys on purpose.
    pub fn canonical(&self) -> String {
        let res = self.resolution.map_or("scene".to_string(), |[w, h]| format!("{w}x{h}"));
        let d = self.ao_distance.map_or("scene".to_string(), |d| d.canonical());
        let mut s = format!(
            concat!(
                "hemilab-job-v1;scene={};distribution={};sequence={};seed_mode={};rays={};replicate={};",
                "seed={};resolution={};ao_distance={}"
            ),
            self.scene_id,
            self.distribution,
            self.sequence,
            self.seed_mode,
            self.rays,
            self.replicate,
            self.seed,
            res,
            d
        );
        s.push_str(&self.measurement.key_suffix());
        s
    }

    /// 16 hex digits, stable across Rust releases and machines (FNV-1a 64 of `canonical`).
    pub fn key(&self) -> String {
        format!("{:016x}", fnv1a64(self.canonical().as_bytes()))
    }

    /// Readable and unique file stem for the job's image: `<scene>-<row>-<rays>r-<replicate>-<key>`.
    pub fn file_stem(&self) -> String {
        let rt = self.measurement.file_part();
        format!(
            "{}-{}-{}-{}-{}r{rt}-{}-{}",
            self.scene_name,
            self.distribution,
            file_safe(self.sequence.name()),
            file_safe(self.seed_mode.name()),
            self.rays,
            self.replicate,
            self.key()
        )
    }
}

/// A name as part of a file name: a file's texture or point set (`texture:m/x_%d.png:offset#1a2b3c4d`)
/// has '/', ':', '%' and '#' in its name; each character other than a letter, digit, '-', '_' or '.'
/// becomes '_' (the key after it keeps the stem unique). Built-in names are unchanged.
pub fn file_safe(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') { c } else { '_' })
        .collect()
}

/// FNV-1a, 64 bit: tiny and fixed forever, unlike std's `DefaultHasher`.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// SplitMix64 finalizer: decorrelates nearby inputs (replicate 0, 1, 2 …).
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seed of replicate `r` of every measured configuration.
pub fn replicate_seed(base: u64, replicate: u32) -> u64 {
    mix(mix(base) ^ replicate as u64)
}

/// Reference replicates use another stream, so a reference never shares numbers with a measured job.
pub fn reference_seed(base: u64, replicate: u32) -> u64 {
    mix(mix(base ^ 0x7265_6665_7265_6e63) ^ replicate as u64)
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Plan {
    /// Ordered: scene (spec order), then tables/sweeps in file order, then row, schedule, rays,
    /// pipeline, reported frame (`reported_frames`), replicate; a job another group already needs
    /// keeps its first place.
    pub jobs: Vec<Job>,
}

/// The union of what every table and sweep needs, duplicates merged.
pub fn plan(spec: &Spec) -> Plan {
    let mut jobs: Vec<Job> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for (si, scene) in spec.scenes.iter().enumerate() {
        for group in spec.groups.iter().filter(|g| g.scenes.contains(&si)) {
            for row in &group.rows {
                let row = row.canonical();
                for &schedule in &group.schedules {
                    for &rays in &group.rays {
                        for (&pipeline, camera, denoiser) in views(group) {
                            for frame in pipeline_frames(pipeline, group.frames) {
                                for replicate in 0..group.replicates {
                                    let job = Job {
                                        scene: scene.path.clone(),
                                        scene_id: scene.id.clone(),
                                        scene_name: scene.name.clone(),
                                        distribution: row.distribution,
                                        sequence: row.sequence,
                                        seed_mode: row.seed_mode,
                                        rays,
                                        replicate,
                                        seed: replicate_seed(spec.seed, replicate),
                                        resolution: spec.resolution,
                                        ao_distance: spec.ao_distance,
                                        measurement: Measurement {
                                            integrand: scene.integrand,
                                            frame,
                                            schedule,
                                            pipeline,
                                            camera,
                                            denoiser,
                                            tiles: spec.tiles,
                                            first_frame: 1,
                                        },
                                    };
                                    let job = if spec.steady_state {
                                        Job { measurement: job.measurement.at_steady_state(), ..job }
                                    } else {
                                        job
                                    };
                                    if seen.insert(job.canonical()) {
                                        jobs.push(job);
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    Plan { jobs }
}

/// A group's pipelines × cameras × denoisers, in that order (pipeline outermost).
fn views(group: &crate::spec::Group) -> Vec<(&Pipeline, CameraId, DenoiserId)> {
    let mut out = Vec::new();
    for p in &group.pipelines {
        for &c in &group.cameras {
            for &d in &group.denoisers {
                out.push((p, c, d));
            }
        }
    }
    out
}

/// The frames (from 1) at which a group of `frames` frames is measured: 1, 2, 4, … and `frames`.
pub fn reported_frames(frames: u32) -> Vec<u32> {
    let mut out: Vec<u32> =
        std::iter::successors(Some(1u32), |k| k.checked_mul(2)).take_while(|&k| k < frames).collect();
    out.push(frames.max(1));
    out
}

/// The frames at which `pipeline` is measured in a group of `frames` frames: `reported_frames`
/// when it accumulates; frame 1 alone when it does not (frame k of such a pipeline is one frame,
/// the same estimator as frame 1 with other numbers, so measuring it again adds only jobs).
pub fn pipeline_frames(pipeline: Pipeline, frames: u32) -> Vec<u32> {
    if pipeline.is_temporal() { reported_frames(frames) } else { vec![1] }
}

/// The reference renders of scene `scene` (index into `Spec::scenes`) at `rays` per pixel: one job
/// per reference replicate, with the spec's reference estimator and seeds from their own stream.
/// The rays are the caller's because `rays = "auto"` is settled only after a pilot render.
pub fn reference_jobs(spec: &Spec, scene: usize, rays: u32) -> Vec<Job> {
    let Some(s) = spec.scenes.get(scene) else { return Vec::new() };
    let e = reference_estimator(spec, scene).canonical();
    (0..spec.reference.replicates)
        .map(|replicate| Job {
            scene: s.path.clone(),
            scene_id: s.id.clone(),
            scene_name: s.name.clone(),
            distribution: e.distribution,
            sequence: e.sequence,
            seed_mode: e.seed_mode,
            rays,
            replicate,
            seed: reference_seed(spec.reference.seed, replicate),
            resolution: spec.resolution,
            ao_distance: spec.ao_distance,
            measurement: Measurement::of(s.integrand),
        })
        .collect()
}

/// The reference estimator of scene `scene`: the spec's, with the distribution matched to the
/// scene's integrand (`Integrand::matched_distribution`) when that is not AO (sine-cosine has
/// infinite variance on unweighted visibility). AO keeps the spec's, so its references are those
/// of every spec before integrands existed.
pub fn reference_estimator(spec: &Spec, scene: usize) -> Row {
    let e = spec.reference.estimator;
    match spec.scenes.get(scene).map(|s| s.integrand) {
        Some(i) if i != Integrand::Ao => Row { distribution: i.matched_distribution(), ..e },
        _ => e,
    }
}

/// What a plan asks for in pixels and rays, before anything is rendered.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    pub jobs: usize,
    /// Upper bound: every pixel covered (background pixels cast no AO rays).
    pub total_rays: u64,
    pub pixels: u64,
}

/// `resolution_of` supplies the scene's own resolution for jobs without an override (the planner
/// does not read scene files).
pub fn estimate(plan: &Plan, resolution_of: impl Fn(&Job) -> [u32; 2]) -> Estimate {
    estimate_with(plan, |job| {
        let [w, h] = job.resolution.unwrap_or_else(|| resolution_of(job));
        w as u64 * h as u64
    })
}

/// `estimate` with each job's rendered pixels given (`pixels_of`): under `[tiles]`, its tiles'
/// windows (`jobs::tiles::TileSet::rendered_pixels`), not the whole image.
pub fn estimate_with(plan: &Plan, pixels_of: impl Fn(&Job) -> u64) -> Estimate {
    let mut total_rays = 0u64;
    let mut pixels = 0u64;
    for job in &plan.jobs {
        let px = pixels_of(job);
        pixels += px;
        total_rays = total_rays.saturating_add(px.saturating_mul(job.rays as u64));
    }
    Estimate { jobs: plan.jobs.len(), total_rays, pixels }
}

/// The job list as `hemilab plan --jobs` prints it: run order, numbered from 1.
pub fn format_jobs(plan: &Plan) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:>4}  {:<16} {:<18} {:<10} {:<9} {:>6} {:>4}  {:<16}",
        "#", "scene", "distribution", "sequence", "seed_mode", "rays", "rep", "key"
    );
    for (i, j) in plan.jobs.iter().enumerate() {
        let _ = writeln!(
            s,
            "{:>4}  {:<16} {:<18} {:<10} {:<9} {:>6} {:>4}  {}",
            i + 1,
            j.scene_name,
            j.distribution.name(),
            j.sequence.name(),
            j.seed_mode.name(),
            j.rays,
            j.replicate,
            j.key()
        );
    }
    s
}

/// "504 MB", "18 GB", "12 kB" (powers of 1000, two significant digits at least).
pub fn format_bytes(bytes: f64) -> String {
    let units = ["bytes", "kB", "MB", "GB", "TB", "PB"];
    let mut v = bytes.max(0.0);
    let mut u = 0;
    while v >= 999.5 && u + 1 < units.len() {
        v /= 1000.0;
        u += 1;
    }
    if u == 0 || v >= 9.95 { format!("{v:.0} {}", units[u]) } else { format!("{v:.1} {}", units[u]) }
}

/// "2 h 05 min", "3 min 07 s", "12.3 s".
pub fn format_duration(seconds: f64) -> String {
    if !seconds.is_finite() {
        return "unknown time".into();
    }
    let t = seconds.round() as u64;
    if t >= 3600 {
        format!("{} h {:02} min", t / 3600, (t % 3600) / 60)
    } else if t >= 60 {
        format!("{} min {:02} s", t / 60, t % 60)
    } else {
        format!("{seconds:.1} s")
    }
}

/// What the timing protocol calls a unit: one configuration on one scene. A multi-frame
/// measurement's schedule and pipeline are part of its unit (`Measurement::series_key`), and so
/// every reported frame of one series of frames (`series`) is in one unit, so in one shard.
pub fn unit_key(job: &Job) -> (String, Row, u32) {
    (format!("{}{}", job.scene_id, job.measurement.series_key()), job.row().canonical(), job.rays)
}

/// The jobs one render produces: a job of a pipeline that accumulates frames is measured at
/// frame k of a series of frames that its jobs at the other reported frames share, so the series
/// is rendered once, to its last reported frame (the `leader`), and every member's image is read
/// from that one render on the way (each frame's image depends only on the frames before it).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Series {
    /// The member with the most frames: the job that is rendered.
    pub leader: usize,
    /// Every job of the series (plan indices), the leader among them, in plan order.
    pub members: Vec<usize>,
}

/// The pipeline a series' key names for all of its accumulating pipelines.
const SERIES_PIPELINE: crate::denoise::Pipeline =
    crate::denoise::Pipeline { temporal: Some(crate::denoise::Temporal::Mean), spatial: None };

/// The plan's jobs grouped into series (every other job a series of one), in order of their first
/// job.
pub fn series(plan: &Plan) -> Vec<Series> {
    let mut index: std::collections::HashMap<String, usize> = Default::default();
    let mut out: Vec<Series> = Vec::new();
    for (i, job) in plan.jobs.iter().enumerate() {
        let key = if job.measurement.pipeline.is_temporal() {
            // Every accumulating pipeline reads the same frames: one series renders them for all.
            let first = Job {
                measurement: Measurement { frame: 1, pipeline: SERIES_PIPELINE, ..job.measurement },
                ..job.clone()
            };
            first.canonical()
        } else {
            job.canonical()
        };
        let s = *index.entry(key).or_insert_with(|| {
            out.push(Series { leader: i, members: Vec::new() });
            out.len() - 1
        });
        let series = &mut out[s];
        series.members.push(i);
        if job.measurement.frame > plan.jobs[series.leader].measurement.frame {
            series.leader = i;
        }
    }
    out
}

/// The plan's jobs grouped into units (job indices), units in order of their first job.
pub fn units(plan: &Plan) -> Vec<Vec<usize>> {
    let mut index: std::collections::HashMap<(String, Row, u32), usize> = Default::default();
    let mut out: Vec<Vec<usize>> = Vec::new();
    for (i, job) in plan.jobs.iter().enumerate() {
        let u = *index.entry(unit_key(job)).or_insert_with(|| {
            out.push(Vec::new());
            out.len() - 1
        });
        out[u].push(i);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv_known_values() {
        // Published FNV-1a 64 test vectors.
        assert_eq!(fnv1a64(b""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
        assert_eq!(fnv1a64(b"foobar"), 0x85944171f73967e8);
    }

    #[test]
    fn replicate_seeds_differ_and_are_fixed() {
        let s: Vec<u64> = (0..4).map(|r| replicate_seed(1, r)).collect();
        for i in 0..4 {
            for j in 0..i {
                assert_ne!(s[i], s[j]);
            }
            assert_ne!(s[i], reference_seed(1, i as u32));
        }
        assert_eq!(replicate_seed(1, 0), replicate_seed(1, 0));
    }

    #[test]
    fn reported_frames_are_powers_of_two_and_the_last() {
        assert_eq!(reported_frames(1), vec![1]);
        assert_eq!(reported_frames(16), vec![1, 2, 4, 8, 16]);
        assert_eq!(reported_frames(12), vec![1, 2, 4, 8, 12]);
        let ema: Pipeline = "ema0.1+atrous".parse().unwrap();
        assert_eq!(pipeline_frames(ema, 4), vec![1, 2, 4]);
        assert_eq!(pipeline_frames("atrous".parse().unwrap(), 4), vec![1]);
    }

    #[test]
    fn durations() {
        assert_eq!(format_duration(12.34), "12.3 s");
        assert_eq!(format_duration(187.0), "3 min 07 s");
        assert_eq!(format_duration(7500.0), "2 h 05 min");
    }
}

//! Command-line definitions only; `app` does the work. Names are parsed here so that a bad value
//! fails before anything runs, with clap's exit status 2 and the list of valid choices.
// The doc comments are clap's help text, which writes placeholders as `out/<spec name>/`.
#![allow(rustdoc::invalid_html_tags)]

use crate::sampling::{Distribution, Schedule, SeedMode, Sequence};
use clap::{Args, Parser, Subcommand};

use crate::shard::{Shard, ShardArg};
use std::path::PathBuf;

#[derive(Debug, Parser)]
#[command(
    name = "hemilab",
    version,
    about = "Hemisphere sampling experiments for ray-traced ambient occlusion"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run an experiment spec: render every job, measure it against the reference, write results and report.
    Run(RunArgs),
    /// Print a spec's plan and how long its run will take here (from a short calibration), per shard with --shards.
    Plan(PlanArgs),
    /// (Re)build the reference images a spec needs.
    Reference(ReferenceArgs),
    /// Merge the output directories of `run --shard K/N` into one set of results and one report.
    Merge(MergeArgs),
    /// Render one AO image of a scene (default: sine-cosine, Fibonacci lattice, per-pixel seed, the
    /// configuration the README recommends).
    Render(RenderArgs),
    /// Measure AO rays per second on a scene (the performance figure of record).
    Bench(BenchArgs),
    /// Draw one point set on the hemisphere (a panel of the paper's Table 1 / Figures 2-4).
    Points(PointsArgs),
    /// Which sampler to ship for a scene at a time budget: every configuration at equal time, and
    /// where in the image each one wins.
    Advise(AdviseArgs),
}

#[derive(Debug, Args)]
pub struct Common {
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// No progress bars.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct RunArgs {
    /// Experiment spec (TOML).
    pub spec: PathBuf,
    /// Output directory (default: out/<spec name>/).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Redo every job, ignoring finished results.
    #[arg(long)]
    pub force: bool,
    /// Stop with an error instead of rendering a missing or mismatched reference.
    #[arg(long)]
    pub no_build_reference: bool,
    /// Where reference images and their manifests live (default: the spec's `[reference] dir`,
    /// relative to the spec file, else `reference/` beside the spec).
    #[arg(long, value_name = "DIR")]
    pub reference_dir: Option<PathBuf>,
    /// Timed renders per configuration at least (default: the spec's `[timing] repeats`, else 3);
    /// a configuration with fewer replicates is re-rendered, for its time only.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub timing_repeats: Option<u32>,
    /// Run only shard K of N (0-based, e.g. 0/3), into out/<spec name>/shard-K-of-N/; merge the
    /// shards with `hemilab merge`. `auto`: K and N from a Slurm job array (SLURM_ARRAY_TASK_ID,
    /// SLURM_ARRAY_TASK_COUNT; submit with --array=0-(N-1)) or a Kubernetes Indexed Job
    /// (JOB_COMPLETION_INDEX, with --shards N).
    #[arg(long, value_parser = parse_shard, value_name = "K/N|auto")]
    pub shard: Option<ShardArg>,
    /// N for `--shard auto` in a Kubernetes Indexed Job (its `completions`).
    #[arg(long, requires = "shard", value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub shards: Option<u32>,
    #[command(flatten)]
    pub common: Common,
}

pub fn parse_shard(s: &str) -> Result<ShardArg, String> {
    if s.trim().eq_ignore_ascii_case("auto") {
        return Ok(ShardArg::Auto);
    }
    Shard::parse(s).map(ShardArg::Fixed)
}

#[derive(Debug, Args)]
pub struct PlanArgs {
    /// Experiment spec (TOML).
    pub spec: PathBuf,
    /// Estimate shard K of N (0-based, e.g. 1/3) (its jobs with --jobs); the table shows all N shards.
    #[arg(long, value_parser = Shard::parse, value_name = "K/N", conflicts_with = "shards")]
    pub shard: Option<Shard>,
    /// Show how the plan splits into N shards (jobs and estimated time of each).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub shards: Option<u32>,
    /// Also list every job, in run order, after the summary.
    #[arg(long)]
    pub jobs: bool,
    /// Where reference images live (whether they must be built counts in the estimate; default:
    /// the spec's `[reference] dir`, else `reference/` beside the spec).
    #[arg(long, value_name = "DIR")]
    pub reference_dir: Option<PathBuf>,
    /// Threads the run will use (default: all cores), as `run --threads`.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
}

#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Experiment spec (TOML) the shards ran.
    pub spec: PathBuf,
    /// Output directories of `hemilab run SPEC --shard K/N`, one per shard.
    #[arg(required = true, value_name = "SHARD_DIR")]
    pub shard_dirs: Vec<PathBuf>,
    /// Output directory of the merged results and report (default: out/<spec name>/).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Where reference images live (the report measures against them; default: the spec's
    /// `[reference] dir`, else `reference/` beside the spec).
    #[arg(long, value_name = "DIR")]
    pub reference_dir: Option<PathBuf>,
    /// No progress bars.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct ReferenceArgs {
    /// Experiment spec (TOML).
    pub spec: PathBuf,
    /// Where reference images and their manifests live (default: the spec's `[reference] dir`,
    /// relative to the spec file, else `reference/` beside the spec).
    #[arg(long, value_name = "DIR")]
    pub reference_dir: Option<PathBuf>,
    /// Render every reference anew, even where a stored one serves the spec (one with as many rays
    /// or more, for `rays = "auto"`, which would otherwise be kept).
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub common: Common,
}

/// `render`'s estimator: by default the one the README's answer recommends, sine-cosine through
/// the Fibonacci lattice with a per-pixel seed (the paper's "random seed per pixel").
#[derive(Debug, Args)]
pub struct RenderSampling {
    /// Hemisphere distribution: uniform, sine, sine-cosine, concentric-cosine.
    #[arg(long, value_parser = parse_distribution, value_name = "D", default_value = "sine-cosine")]
    pub distribution: Distribution,
    /// Point sequence: random, fibonacci, stratified, sobol, halton, pmj02bn, zsobol, r2, or a file's
    /// point set points:PATH (.npy of N x 2 or P x N x 2, or text with one `x y` per line).
    #[arg(long, value_parser = parse_sequence, value_name = "S", default_value = "fibonacci")]
    pub sequence: SequenceArg,
    /// Randomization across pixels: static, rotation (the paper's per-pixel seed), shift (unbiased
    /// per pixel), blue-noise, stbn (spatiotemporal blue noise); the engines' rotation patterns
    /// ign (interleaved gradient noise), bayer (4x4), magic-square (5x5), r2-dither; or a noise
    /// texture texture:PATH[:offset|rotation|vector] (PNG 8/16 bit or EXR, `%d` for numbered
    /// slices; default use offset; vector needs sine-cosine).
    #[arg(long, value_parser = parse_seed_mode, value_name = "M", default_value = "rotation")]
    pub seed_mode: ModeArg,
    /// Run seed: different seeds give independent images.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub frames: FrameArgs,
}

/// Which frame of a static camera's sequence of frames, and how the randomization changes per frame.
#[derive(Debug, Args)]
pub struct FrameArgs {
    /// Frame index (0 = the single image).
    #[arg(long, default_value_t = 0, value_name = "F")]
    pub frame: u32,
    /// Per-frame randomization: independent (a fresh run seed per frame), r1 (golden-ratio steps of
    /// the offsets).
    #[arg(long, value_parser = parse_schedule, value_name = "S", default_value = "independent")]
    pub schedule: Schedule,
}

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    #[command(flatten)]
    pub sampling: RenderSampling,
    /// AO rays per pixel.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1_048_576))]
    pub rays: u32,
    /// What the rays integrate: ao (cosine-weighted visibility), visibility (unweighted, the
    /// sky-view factor), cos-lobe-N (cos^N about the normal, N >= 2); the image is 1 - the estimate.
    #[arg(long, value_parser = parse_integrand, value_name = "I", default_value = "ao")]
    pub integrand: crate::sampling::Integrand,
    /// Image size, WxH (default: the scene's).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Output EXR (Y = AO with 1 = open, A = coverage); a PNG preview is written beside it.
    #[arg(long)]
    pub output: PathBuf,
    /// Longest the render may be forecast to take, in wall minutes on this machine; a longer one
    /// is refused before it starts (the forecast says how long it would be).
    #[arg(long, default_value_t = crate::plan::forecast::DEFAULT_MAX_MINUTES, value_name = "M",
          value_parser = crate::plan::forecast::parse_max_minutes)]
    pub max_minutes: f64,
    #[command(flatten)]
    pub common: Common,
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// AO rays per pixel.
    #[arg(long, default_value_t = 32, value_parser = clap::value_parser!(u32).range(1..=65_536))]
    pub rays: u32,
    /// Image size, WxH (default: the scene's).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// AO distances d to compare at, in scene units, comma-separated; `inf` (or `infinite`) =
    /// unbounded (default: the scene's own d, 0.3 × d and inf; inf alone for a scene with d = inf).
    #[arg(long, value_parser = parse_distance, value_delimiter = ',', value_name = "LIST")]
    pub distances: Option<Vec<f32>>,
    /// Timed repeats per configuration (min / median / max are reported).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub repeats: u32,
    /// Also write the bench's exact AO ray set (the triangles, each pixel's origin and normal, its
    /// directions) to FILE in the HLRAYS1 format that peer ray tracers can read
    /// (docs/performance.md); the occluded counts the bench prints are what they must find.
    #[arg(long, value_name = "FILE")]
    pub dump_rays: Option<PathBuf>,
}

/// A positive AO distance, or `inf` / `infinite`.
pub fn parse_distance(s: &str) -> Result<f32, String> {
    let t = s.trim();
    if crate::spec::is_infinite(t) {
        return Ok(f32::INFINITY);
    }
    match t.parse::<f32>() {
        Ok(d) if d > 0.0 && d.is_finite() => Ok(d),
        _ => Err(format!("distance '{s}' must be a positive number or 'inf' (or 'infinite')")),
    }
}

#[derive(Debug, Args)]
pub struct PointsArgs {
    /// Hemisphere distribution: uniform, sine, sine-cosine, concentric-cosine.
    #[arg(long, value_parser = parse_distribution, value_name = "D")]
    pub distribution: Distribution,
    /// Point sequence: random, fibonacci, stratified, sobol, halton, pmj02bn, zsobol, r2, or a file's
    /// point set points:PATH (.npy of N x 2 or P x N x 2, or text with one `x y` per line).
    #[arg(long, value_parser = parse_sequence, value_name = "S")]
    pub sequence: SequenceArg,
    /// Randomization across pixels: static, rotation, shift, blue-noise, stbn, ign, bayer,
    /// magic-square, r2-dither, or a noise texture texture:PATH[:offset|rotation|vector].
    #[arg(long, value_parser = parse_seed_mode, value_name = "M", default_value = "static")]
    pub seed_mode: ModeArg,
    /// Run seed: the points are pixel 0's of a render with this seed.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub frames: FrameArgs,
    /// Number of points.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub count: u32,
    /// Output image (.png or .svg).
    #[arg(long)]
    pub output: PathBuf,
}

#[derive(Debug, Args)]
pub struct AdviseArgs {
    /// Scene file (TOML); not with --from (the sweep's own is used).
    #[arg(required_unless_present = "from", conflicts_with = "from")]
    pub scene: Option<PathBuf>,
    /// Re-analyse the finished sweep in DIR (an earlier advise's --out) at --budget-ms without
    /// rendering anything; writes to --out, default DIR itself. A budget whose finalists DIR has not
    /// measured is answered from the sweep's interpolation, and says so.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["rays", "only", "replicates", "resolution", "reference_dir", "pipeline", "frames", "integrand"])]
    pub from: Option<PathBuf>,
    /// Time budgets per image in ms, comma-separated: thread CPU time of a one-thread render of the
    /// whole image at the resolution (default: three spread over the paper default's measured times).
    #[arg(long, value_parser = parse_budget, value_delimiter = ',', value_name = "LIST")]
    pub budget_ms: Vec<f64>,
    /// Ray counts per pixel to measure, comma-separated, at least two different (default
    /// 1,2,4,8,16,32,64; with --pipeline 1,2,4: the rays per pixel per frame an engine spends, and
    /// the budgets its advice is given for).
    #[arg(long, value_delimiter = ',', value_name = "LIST", value_parser = clap::value_parser!(u32).range(1..=65_536))]
    pub rays: Vec<u32>,
    /// Image size, WxH (default: the largest stored reference of the scene with at most 3072
    /// pixels, else the scene's own scaled down to that).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Independent replicates (seeds) per configuration and ray count, 2..=1000 (default 4; 2 when
    /// measured on tiles, above 320x180, where each replicate holds 65,536 measured pixels)
    #[arg(long, value_parser = clap::value_parser!(u32).range(2..=1000))]
    pub replicates: Option<u32>,
    // The help names every pipeline from the list the parser's errors give (one source of truth).
    #[arg(long, default_value = "raw", value_parser = parse_pipeline, value_name = "PIPELINE",
          help = pipeline_help())]
    pub pipeline: crate::denoise::Pipeline,
    /// With a temporal --pipeline: the frame whose image is ranked (frames accumulated), 1..=1024
    /// (default 64: steady state).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub frames: Option<u32>,
    /// What the rays integrate: ao, visibility (unweighted), cos-lobe-N (N >= 2); its reference
    /// is built with the integrand's matched distribution.
    #[arg(long, value_parser = parse_integrand, value_name = "I", default_value = "ao")]
    pub integrand: crate::sampling::Integrand,
    /// Only these configurations, comma-separated distribution/sequence/seed_mode, each part a
    /// name or * (e.g. sine-cosine/fibonacci/*); the paper's default is always run.
    #[arg(long, value_parser = parse_pattern, value_delimiter = ',', value_name = "LIST")]
    pub only: Vec<crate::advice::Pattern>,
    /// Also measure a noise texture as a seed mode, PATH[:offset|rotation|vector] (PNG 8/16 bit or
    /// EXR, `%d` for numbered slices), with every sequence it is sensible with (--only narrows by
    /// distribution and sequence); repeatable.
    #[arg(long, value_name = "PATH[:USE]", conflicts_with = "from")]
    pub texture: Vec<String>,
    /// Also measure a file's point set as a sequence (.npy of N x 2 or P x N x 2, or `x y` text),
    /// with every seed mode it is sensible with; repeatable.
    #[arg(long, value_name = "PATH", conflicts_with = "from")]
    pub points: Vec<String>,
    /// With an accumulating --pipeline: another camera path to rank with, besides the scene's still
    /// camera and the default moving one (orbit:10, jittered): orbit:DEG, pan:DEG, dolly:DISTANCE
    /// (over the frames) or still (the scene's camera, jittered); repeatable.
    #[arg(long, value_name = "PATH", conflicts_with = "from")]
    pub camera_path: Vec<String>,
    /// With --pipeline: the user's own denoiser run on every ranked frame after the pipeline, as
    /// NAME=PROGRAM ARGS… (split at spaces; {input} and {output} are the EXRs hemilab writes and
    /// reads back, as a spec's [denoisers.NAME]); relative paths from the current directory.
    #[arg(long, value_name = "NAME=COMMAND", conflicts_with = "from")]
    pub denoiser: Option<String>,
    /// Output directory (default: out/advise-<scene>/, or DIR with --from). Rewritten whole: absent,
    /// empty or an earlier advise's; a rerun resumes from its records.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Where reference images and their manifests live (default: `reference/` beside the scene
    /// file, or its parent folder's `reference/` when that holds one of this scene, as in this
    /// repository's layout of scenes/ beside reference/; never the current directory).
    #[arg(long, value_name = "DIR")]
    pub reference_dir: Option<PathBuf>,
    /// Longest advise may be forecast to take, in wall minutes on this machine (its reference, the
    /// sweep and the finalists); a longer one is refused before any work, saying how long it would be.
    #[arg(long, default_value_t = crate::plan::forecast::DEFAULT_MAX_MINUTES, value_name = "M",
          value_parser = crate::plan::forecast::parse_max_minutes)]
    pub max_minutes: f64,
    #[command(flatten)]
    pub common: Common,
}

/// `advise --pipeline`'s help: what it does, then every pipeline name as the parser's error lists
/// them (`denoise::pipeline::ALLOWED`).
fn pipeline_help() -> String {
    format!(
        "Rank the image a real-time renderer shows: frames accumulated and filtered by this pipeline; \
         budgets are then per frame, and the sweep adds the engines' rotation patterns (ign, bayer, \
         magic-square, r2-dither) as engines ship them. PIPELINE: {}",
        crate::denoise::pipeline::ALLOWED
    )
}

/// A time budget in ms: positive and finite.
pub fn parse_budget(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(b) if b > 0.0 && b.is_finite() && b <= 1e7 => Ok(b),
        _ => Err(format!("budget '{s}' must be a time per image in ms, a number > 0 (e.g. 2.5)")),
    }
}

fn parse_pattern(s: &str) -> Result<crate::advice::Pattern, String> {
    crate::advice::Pattern::parse(s)
}

fn parse_distribution(s: &str) -> Result<Distribution, String> {
    s.parse()
}

fn parse_integrand(s: &str) -> Result<crate::sampling::Integrand, String> {
    crate::sampling::Integrand::parse(s)
}

/// A `--sequence` value: a name, or a point file the command reads (`load::points_arg`) before
/// any work, so that a bad file is refused with exit status 2 and nothing written.
#[derive(Debug, Clone)]
pub enum SequenceArg {
    Named(Sequence),
    Points(String),
}

/// A `--seed-mode` value: a name, or a texture the command reads (`load::texture_arg`).
#[derive(Debug, Clone)]
pub enum ModeArg {
    Named(SeedMode),
    Texture(String),
}

impl SequenceArg {
    pub fn resolve(&self) -> crate::error::Result<Sequence> {
        match self {
            SequenceArg::Named(s) => Ok(*s),
            SequenceArg::Points(text) => crate::load::points_arg(text),
        }
    }
}

impl ModeArg {
    pub fn resolve(&self) -> crate::error::Result<SeedMode> {
        match self {
            ModeArg::Named(m) => Ok(*m),
            ModeArg::Texture(text) => crate::load::texture_arg(text),
        }
    }
}

fn parse_sequence(s: &str) -> Result<SequenceArg, String> {
    match s.strip_prefix("points:") {
        Some(p) if !p.is_empty() => Ok(SequenceArg::Points(s.to_string())),
        _ => s.parse().map(SequenceArg::Named),
    }
}

fn parse_seed_mode(s: &str) -> Result<ModeArg, String> {
    match s.strip_prefix("texture:") {
        Some(p) if !p.is_empty() => Ok(ModeArg::Texture(s.to_string())),
        _ => s.parse().map(ModeArg::Named),
    }
}

fn parse_schedule(s: &str) -> Result<Schedule, String> {
    s.parse()
}

/// Parses `WxH` within `spec::RESOLUTION_RULE` (the limits of scene files and specs).
pub fn parse_pipeline(s: &str) -> Result<crate::denoise::Pipeline, String> {
    s.parse().map_err(|e: crate::denoise::PipelineError| e.to_string())
}

pub fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("resolution '{s}' must be WxH, {}; e.g. 320x240", crate::spec::RESOLUTION_RULE);
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if !crate::spec::resolution_ok(w as u64, h as u64) {
        return Err(bad());
    }
    Ok((w, h))
}

//! Experiment spec (`experiments/*.toml`): what to render and compare, validated before any work.
//!
//! ```toml
//! name = "paper"                        # optional; output dir out/<name>/; default: file stem
//! scenes = ["../scenes/kitchen.toml"]   # relative to the spec file; stems must differ
//! resolution = [160, 120]               # optional override of the scenes' own; sides 1..=16384,
//!                                       # at most 67108864 pixels (8192x8192)
//! ao_distance = 1.0                     # optional override: a number > 0 or "infinite" ("inf")
//! replicates = 4                        # independent seeds per (row, rays); 1..=1000; default 4
//! seed = 1                              # base seed, 0..=4294967295; default 1
//! point_figures = true                  # optional: also draw Table 1 and Figures 2-4; default false
//! flip_ppd = 67                         # optional: LDR-FLIP's pixels per degree, (0, 1000]; default 67
//!
//! [reference]                           # optional section; defaults shown
//! dir = "reference"                     # where reference images live, relative to this file
//! rays = "auto"                         # or 1..=4194304 rays per pixel per replicate
//! replicates = 4                        # 2..=1000 (their spread gives the standard error)
//! seed = 1                              # default: the base seed (its own stream)
//! distribution = "sine-cosine"          # the estimator: unbiased and fast-converging
//! sequence = "fibonacci"
//! seed_mode = "shift"
//! allocation = "even"                   # or "adaptive": rays per pixel ∝ its spread in a pilot pass
//!
//! [tiles]                               # optional: measure on tiles of the image (`plan::tiles`)
//! count = 4                             # 1..=64 tiles, chosen where the content is
//! size = 64                             # side in pixels, 8..=2048 (default 128), at most the image's
//!                                       # smaller side; count × size² below the image's pixels
//!
//! [timing]                              # optional section; see `timing` for the protocol
//! repeats = 3                           # timed renders per (row, rays) at least, 1..=100
//! seed = 1                              # of the interleaved order; default: the base seed
//!
//! [[table]]                             # any number, like the paper's tables 2 and 3
//! name = "table2"                       # letters, digits, '-', '_'; unique over tables and sweeps
//! rays = [8, 16, 32]                    # 1..=65536 each
//! replicates = 4                        # optional: overrides the top-level count for this group
//! scenes = ["kitchen"]                  # optional: a subset of the scenes (stem or path)
//! rows = [                              # either explicit rows (seed_mode defaults to "rotation") …
//!   { distribution = "uniform", sequence = "random" },
//!   { distribution = "sine-cosine", sequence = "fibonacci", seed_mode = "static" },
//! ]
//!
//! [[convergence]]                       # same keys as [[table]]
//! name = "convergence"
//! rays = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]
//! distributions = ["sine-cosine"]       # … or axes, expanded as a product in this order
//! sequences = ["random", "fibonacci"]
//! seed_modes = ["rotation", "shift"]    # optional; default ["rotation"]
//!
//! [[table]]                             # real-time keys (any group; defaults: one raw frame)
//! name = "realtime"
//! rays = [1, 2, 4]                      # per pixel per frame
//! distributions = ["sine-cosine"]
//! sequences = ["fibonacci"]
//! frames = 16                           # 1..=1024 frames of a static camera; measured at 1, 2, 4, …, 16
//! schedules = ["independent", "r1"]     # per-frame randomization; default ["independent"]
//! pipelines = ["raw", "ema0.1+atrous"]  # what is done to the frames (`denoise::Pipeline`); default ["raw"]
//!
//! [[table]]                             # what the rays integrate (any group)
//! name = "integrands"
//! rays = [8]
//! distributions = ["sine", "uniform"]
//! sequences = ["random"]
//! integrands = ["ao", "visibility", "cos-lobe-8"]  # default ["ao"]; each non-ao one measures
//!                                       # the group's scenes again as `<stem>-<integrand>`
//! ```
//!
//! Keys are snake_case; names are those of `sampling` (`uniform`, `sine`, `sine-cosine`,
//! `concentric-cosine`; `random`, `fibonacci`, `stratified`, `sobol`, `halton`, `pmj02bn`, `zsobol`,
//! `r2`; `static`, `rotation`, `shift`, `blue-noise`, `stbn`, `ign`, `bayer`, `magic-square`,
//! `r2-dither`). `random` + `shift` is the same estimator as `random` + `rotation` (fresh numbers per
//! pixel) and is merged into it; `random` + `static` and `random` + `blue-noise` are kept.
//!
//! Files the user brings, relative to the spec file, wherever a seed mode or a sequence
//! is named (`rows` or the axes; not `[reference]`):
//!
//! ```toml
//! seed_modes = ["shift", { texture = "masks/stbn_vec2_%d.png", use = "offset" }]  # or "rotation",
//!                                       # "vector" (sine-cosine only); `use` defaults to "offset"
//! sequences = ["fibonacci", { points = "sets/ldbn.txt" }]   # .npy (N × 2, P × N × 2) or `x y` text
//! ```
//!
//! A texture is the seed mode `texture:PATH:USE#hash8` in results, a point file the sequence
//! `points:PATH#hash8` (docs/specs.md); a bad file is one error naming its line, key and the file.
//!
//! Parsing is two-phase so that errors point at lines: serde (with `deny_unknown_fields`) checks the
//! shape and stops at the first unknown key or wrong type; then every value carries its span
//! (`toml::Spanned`) and the range/name checks run over the whole file, gathering all problems at once.
//! Every message reads `line N, key K: what is wrong; what is allowed`.

use crate::denoise::Pipeline;
use crate::sampling::{Distribution, Integrand, Schedule, SeedMode, Sequence};
use std::path::{Component, Path, PathBuf};

mod group;
mod keys;
pub(crate) mod position;
mod raw;
mod tiles;
mod validate;

pub use validate::{parse_spec, parse_spec_with};

/// Reads the files a spec's seed modes and sequences name (`{ texture = .. }`, `{ points = .. }`):
/// `load::SpecFiles` does, relative to the spec's directory. `parse_spec` itself does no IO and
/// refuses such entries (`NoFiles`); the message of an `Err` names the file and what is wrong.
pub trait Files {
    fn texture(&self, written: &str, use_: crate::sampling::texture::TextureUse) -> Result<SeedMode, String>;
    fn points(&self, written: &str) -> Result<Sequence, String>;
}

/// The `Files` of `parse_spec`: none can be read.
pub struct NoFiles;

const NO_FILES: &str =
    "files are read only when the spec is loaded (`load::load`), not by `spec::parse_spec`";

impl Files for NoFiles {
    fn texture(&self, _: &str, _: crate::sampling::texture::TextureUse) -> Result<SeedMode, String> {
        Err(NO_FILES.into())
    }

    fn points(&self, _: &str) -> Result<Sequence, String> {
        Err(NO_FILES.into())
    }
}

/// Ray counts above this are a typo, not an experiment (an image at 64k rays is a reference).
pub const MAX_RAYS: u32 = 65_536;
/// References may go higher: they are rendered once and committed.
pub const MAX_REFERENCE_RAYS: u32 = 1 << 22;
pub const MAX_REPLICATES: u32 = 1000;
/// Frames of one real-time job: a second of 1 kHz frames is more than any accumulation needs.
pub const MAX_FRAMES: u32 = 1024;

/// Replicates of a spec that names none: enough for a standard error (one replicate has no
/// spread, and a table of "± 0.0000" reads as a certainty it is not).
pub const DEFAULT_REPLICATES: u32 = 4;
/// Image sides are 1..=MAX_SIDE, and an image holds at most MAX_PIXELS pixels (8192x8192, or
/// e.g. 16384x4096): beyond that its AO and coverage channels and their EXR encoding need several
/// GB. Command line, scene files and specs all check both, with `RESOLUTION_RULE` as the text.
pub const MAX_SIDE: u32 = 16_384;
pub const MAX_PIXELS: u64 = 1 << 26;
pub const RESOLUTION_RULE: &str =
    "each side 1..=16384 and at most 67108864 pixels in all (8192x8192, or e.g. 16384x4096)";

/// Whether `w` x `h` is an image size hemilab accepts (`RESOLUTION_RULE`).
pub fn resolution_ok(w: u64, h: u64) -> bool {
    (1..=MAX_SIDE as u64).contains(&w) && (1..=MAX_SIDE as u64).contains(&h) && w * h <= MAX_PIXELS
}
/// Timed renders per configuration: beyond this a run is a benchmark, not an experiment.
pub const MAX_TIMING_REPEATS: u32 = 100;

/// AO distance d: rays hitting farther than this count as open.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AoDistance {
    Finite(f64),
    Infinite,
}

/// The words for an unbounded AO distance, in a scene file, a spec and on the command line alike.
pub fn is_infinite(s: &str) -> bool {
    let t = s.trim();
    t.eq_ignore_ascii_case("infinite") || t.eq_ignore_ascii_case("inf")
}

impl AoDistance {
    /// Stable text (shortest round-tripping float), used in job keys and manifests.
    pub fn canonical(&self) -> String {
        match self {
            AoDistance::Finite(d) => format!("{d:?}"),
            AoDistance::Infinite => "infinite".into(),
        }
    }

    pub fn as_f32(&self) -> f32 {
        match self {
            AoDistance::Finite(d) => *d as f32,
            AoDistance::Infinite => f32::INFINITY,
        }
    }
}

/// One estimator: a row of the paper's tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Row {
    pub distribution: Distribution,
    pub sequence: Sequence,
    pub seed_mode: SeedMode,
}

impl Row {
    pub fn new(distribution: Distribution, sequence: Sequence, seed_mode: SeedMode) -> Self {
        Self { distribution, sequence, seed_mode }
    }

    /// Pseudo-random numbers are fresh per pixel whether "rotated" or "shifted", so both name the
    /// same images; `rotation` is the one kept. (`static` + random is a distinct, odd choice.)
    /// A vector texture gives the directions itself, so every sequence names the same images with
    /// it; `random` is the one kept.
    pub fn canonical(self) -> Self {
        match self.seed_mode {
            SeedMode::Shift if self.sequence.info().fresh_per_pixel => {
                Self { seed_mode: SeedMode::Rotation, ..self }
            }
            m if m.texture_use() == Some(crate::sampling::texture::TextureUse::Vector) => {
                Self { sequence: Sequence::Random, ..self }
            }
            _ => self,
        }
    }

    /// Why this row cannot be rendered, if it cannot: a vector texture holds cosine-weighted
    /// directions, which only the sine-cosine warp (whose inverse hands them on) estimates with.
    pub fn invalid(&self) -> Option<String> {
        let vector = self.seed_mode.texture_use() == Some(crate::sampling::texture::TextureUse::Vector);
        (vector && self.distribution != Distribution::SineCosine).then(|| {
            format!(
                "seed mode '{}' is a vector texture (cosine-weighted directions): its distribution must be \
                 sine-cosine, not {}",
                self.seed_mode, self.distribution
            )
        })
    }

    pub fn label(&self) -> String {
        format!("{}/{}/{}", self.distribution, self.sequence, self.seed_mode)
    }

    /// The configuration as every person-facing text names it (report, figures, tables, the
    /// terminal), in the paper's words: "sine-cosine, Fibonacci, per-pixel seed". The README's
    /// "Configuration names" maps these words to the `results.csv` values (`Row::label`'s).
    pub fn name(&self) -> String {
        let seq = self.sequence.info().label;
        let mode = match self.seed_mode {
            // Fresh numbers per pixel: the paper's plain pseudo-random row needs no seed words.
            SeedMode::Rotation | SeedMode::Shift if self.sequence.info().fresh_per_pixel => None,
            SeedMode::Rotation => Some("per-pixel seed"),
            SeedMode::Static => Some("static seed"),
            SeedMode::Shift => Some("shift"),
            SeedMode::BlueNoise => Some("blue-noise"),
            SeedMode::Stbn => Some("spatiotemporal blue noise"),
            SeedMode::Ign => Some("interleaved gradient noise"),
            SeedMode::Bayer => Some("Bayer 4x4"),
            SeedMode::MagicSquare => Some("magic square 5x5"),
            SeedMode::R2Dither => Some("R2 dither"),
            SeedMode::Texture(t) => Some(t.get().label()),
        };
        match mode {
            Some(m) => format!("{}, {seq}, {m}", self.distribution),
            None => format!("{}, {seq}", self.distribution),
        }
    }
}

/// A scene as the spec names it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SceneRef {
    /// Where to load it from: the spec's directory joined with `id`.
    pub path: PathBuf,
    /// The path as written in the spec, lexically normalized; part of job keys (portable across clones).
    pub id: String,
    /// File stem: the `scene` column of the results.
    pub name: String,
    /// Line of the spec that names it, for messages.
    pub line: usize,
    /// What its rays integrate. A group's `integrands` other than `ao` add the scene
    /// again with that integrand (`name` `<stem>-<integrand>`, same file): every per-scene
    /// thing of a run (its reference, report sections, results' `scene`) then keeps integrands apart.
    pub integrand: Integrand,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroupKind {
    /// Like the paper's tables 2 and 3: images side by side.
    Table,
    /// Error against ray count and time, for slopes.
    Convergence,
}

/// A `[[table]]` or `[[convergence]]`: rows × ray counts × replicates, for some scenes.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    pub kind: GroupKind,
    pub name: String,
    /// Canonical rows (see `Row::canonical`), duplicates merged, in file order.
    pub rows: Vec<Row>,
    /// Duplicates merged, in file order.
    pub rays: Vec<u32>,
    pub replicates: u32,
    /// Indices into `Spec::scenes`.
    pub scenes: Vec<usize>,
    pub line: usize,
    /// Frames of a static camera per configuration (1: the paper's single image).
    pub frames: u32,
    /// Per-frame randomization schedules, duplicates merged, in file order.
    pub schedules: Vec<Schedule>,
    /// What is done to the frames before measuring, duplicates merged, in file order.
    pub pipelines: Vec<Pipeline>,
    /// How the camera moves over the frames (`[cameras.NAME]`; `static`: the scene's own).
    pub cameras: Vec<crate::plan::CameraId>,
    /// The user's denoisers run on each measured frame after the pipeline (`[denoisers.NAME]`;
    /// `none`: no such step).
    pub denoisers: Vec<crate::plan::DenoiserId>,
}

impl Group {
    /// Whether the plan gives this group paper-table images: a job whose measurement is one raw
    /// frame (`plan::Measurement::is_single_frame`) for every row and ray count. Each axis must
    /// hold that measurement's value: the raw pipeline, the independent schedule, the scene's own
    /// camera and no denoiser (a group with `denoisers = ["box"]` alone once rendered every job and
    /// then stopped for want of a raw image for its table figures).
    pub fn has_single_frames(&self) -> bool {
        self.pipelines.contains(&Pipeline::RAW)
            && self.schedules.contains(&Schedule::Independent)
            && self.cameras.contains(&crate::plan::CameraId::STATIC)
            && self.denoisers.contains(&crate::plan::DenoiserId::NONE)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReferenceRays {
    Fixed(u32),
    /// Enough that the noise floor is at most 1/10 of the smallest RMSE measured (decided by the app).
    Auto,
}

#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceSpec {
    /// Rays per pixel of each reference replicate.
    pub rays: ReferenceRays,
    /// Independent renders; their spread gives the per-pixel standard error (so at least 2).
    pub replicates: u32,
    pub seed: u64,
    pub estimator: Row,
    /// `allocation = "adaptive"`: a pilot pass measures each pixel's spread and the rays go where it
    /// is (`reference::allocate`); `"even"` (the default): the same rays in every pixel.
    pub adaptive: bool,
}

/// How `hemilab run` times its renders (`[timing]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimingSpec {
    /// Timed renders per configuration at least: its replicates, plus timing-only re-renders.
    pub repeats: u32,
    /// Seed of the interleaved render order.
    pub seed: u64,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Spec {
    pub path: PathBuf,
    /// Default output directory is `out/<name>/`.
    pub name: String,
    pub scenes: Vec<SceneRef>,
    pub resolution: Option<[u32; 2]>,
    pub ao_distance: Option<AoDistance>,
    /// `[tiles]`: every job measured on tiles of the image (`plan::tiles`, `jobs::tiles`); None:
    /// on the whole image.
    pub tiles: Option<crate::plan::tiles::TileSpec>,
    /// Each accumulating job's run starts where its earlier frames would weigh at most 1 % in the
    /// measured one (`plan::Measurement::at_steady_state`), not at frame 1: what advise measures,
    /// the frame at steady state for a fraction of its frames. No spec key: a run's committed
    /// series render every frame.
    pub steady_state: bool,
    pub replicates: u32,
    pub seed: u64,
    /// Draw the paper's point figures (Table 1, Figures 2-4): they depend on no rendering, so
    /// only the spec that reproduces the paper asks for them.
    pub point_figures: bool,
    /// LDR-FLIP's viewing condition in pixels per degree (`flip_ppd`, default FLIP's 67,
    /// `metrics::DEFAULT_PPD`): how large a pixel looks decides which errors the eye resolves, so
    /// the records' `flip` is at this setting (a setting other than the default is part of the
    /// run key, so a run at another never reuses them).
    pub flip_ppd: f64,
    pub reference: ReferenceSpec,
    /// Where the references live: `[reference] dir`, relative to the spec file, by default
    /// `reference/` beside it. Relative to the spec and not to the current directory, so a committed
    /// reference is found from anywhere and a user's own spec never writes into another project's
    /// folder. (Not part of `ReferenceSpec`: where a reference is stored does not change it.)
    pub reference_dir: PathBuf,
    pub timing: TimingSpec,
    /// Tables and sweeps in file order.
    pub groups: Vec<Group>,
}

impl Spec {
    pub fn group(&self, name: &str) -> Option<&Group> {
        self.groups.iter().find(|g| g.name == name)
    }
}

/// Lexical normalization ("./a/../b" → "b"), with '/' separators so keys match across platforms.
pub(crate) fn normalize(path: &str) -> String {
    let mut parts: Vec<String> = Vec::new();
    for c in Path::new(path).components() {
        match c {
            Component::CurDir | Component::RootDir => {}
            Component::ParentDir if parts.last().is_some_and(|l| l != "..") => {
                parts.pop();
            }
            other => parts.push(other.as_os_str().to_string_lossy().into_owned()),
        }
    }
    let joined = parts.join("/");
    if path.starts_with('/') { format!("/{joined}") } else { joined }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalize_paths() {
        assert_eq!(normalize("./a/../b.toml"), "b.toml");
        assert_eq!(normalize("../scenes/kitchen.toml"), "../scenes/kitchen.toml");
        assert_eq!(normalize("../../x"), "../../x");
        assert_eq!(normalize("/work/./a/../scenes/k.toml"), "/work/scenes/k.toml");
    }

    #[test]
    fn names_are_the_papers_words() {
        use {Distribution as D, SeedMode as M, Sequence as S};
        let name = |d, s, m| Row::new(d, s, m).name();
        assert_eq!(name(D::SineCosine, S::Fibonacci, M::Rotation), "sine-cosine, Fibonacci, per-pixel seed");
        assert_eq!(name(D::SineCosine, S::Fibonacci, M::Static), "sine-cosine, Fibonacci, static seed");
        assert_eq!(name(D::Uniform, S::Random, M::Rotation), "uniform, pseudo-random");
        assert_eq!(name(D::Uniform, S::Random, M::Shift), "uniform, pseudo-random");
        assert_eq!(name(D::Sine, S::Random, M::Static), "sine, pseudo-random, static seed");
        assert_eq!(name(D::ConcentricCosine, S::Sobol, M::Shift), "concentric-cosine, Sobol', shift");
        assert_eq!(name(D::Sine, S::Stratified, M::BlueNoise), "sine, stratified, blue-noise");
    }

    #[test]
    fn random_shift_is_random_rotation() {
        let r = Row::new(Distribution::Sine, Sequence::Random, SeedMode::Shift).canonical();
        assert_eq!(r.seed_mode, SeedMode::Rotation);
        let f = Row::new(Distribution::Sine, Sequence::Fibonacci, SeedMode::Shift).canonical();
        assert_eq!(f.seed_mode, SeedMode::Shift);
        let s = Row::new(Distribution::Sine, Sequence::Random, SeedMode::Static).canonical();
        assert_eq!(s.seed_mode, SeedMode::Static);
    }
}

//! hemilab: which way of generating points on the hemisphere gives the least error per unit of
//! run time for ray-traced ambient occlusion?
//!
//! Data flows one way, and the modules are declared in that order:
//!
//! ```text
//!   spec ──► plan ──► jobs ──────────► images ──► metrics ──► results ──► report
//!  (spec/,  (plan/)  (jobs/: runner,  (render/,   (metrics/) (results/,  (report/: run/,
//!   load)            executor,        scene/,                compare/,   advise/; outdir
//!                    calibrate)       sampling/,             advice/)    writes the files)
//!                                     denoise/)
//! ```
//!
//! `load` reads a spec and its scenes and refuses bad input before any work; `denoise` filters and
//! accumulates images (no IO); `reference` owns what a reference is and how it is stored; `shard`
//! splits a plan over machines and merges it back; `timing` is how a render's cost is measured
//! (thread CPU time, interleaved repeats, per-image overhead apart from per-ray cost). `compare`
//! does every statistic on records — the one paired margin, the equal-time model and its error
//! model, the structure rule, the paper's claims and the real-time and integrand verdicts — and
//! `advice` uses it to answer `hemilab advise` (pure: its inputs are loaded by the command); the
//! report only formats what they computed and returns bytes. `outdir` names, reads and writes
//! every output file once and `io` is the only module that touches the filesystem;
//! `denoise_command` runs the user's own denoiser on a frame (its files through `io`). The command
//! line (`cli`) and the commands (`app`, one thin file each) are the library's too, behind
//! [`main_with`]: the `hemilab` binary is one call to it, and so is a program that registers its
//! own sampler first (`examples/external_sampler.rs`), so that sampler runs through `hemilab run`'s
//! own code path.
//!
//! # Bringing your own sampler
//!
//! A sequence is anything implementing [`sampling::PointSequence`]; registered, it is named in
//! specs and on the command line and runs through every stage like the built-in ones (which are
//! written the same way, one file each: `sampling/r2.rs` is the shortest). Here a shifted rank-1
//! lattice written outside the crate is measured on the committed Cornell box against its
//! committed 32 × 32 reference, beside the paper's pseudo-random numbers:
//!
//! ```
//! use glam::Vec2;
//! use hemilab::render::{RenderJob, render};
//! use hemilab::sampling::seed::{fix_add, fix_from_bits, fix_to_f32, hash};
//! use hemilab::sampling::{Distribution, PixelSet, PointSequence, SamplerConfig, SeedMode, Sequence, SequenceInfo};
//!
//! /// Points ((i + ½)/n, frac(i/φ)), shifted mod 1 by offsets from the set's key.
//! struct Golden;
//!
//! impl PointSequence for Golden {
//!     fn info(&self) -> &SequenceInfo {
//!         &SequenceInfo { name: "golden", label: "golden", words: &[], fresh_per_pixel: false, shipped: None }
//!     }
//!
//!     fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
//!         // The key is fresh per pixel under `shift`; (dx, dy) are the seed mode's offsets.
//!         let (key, dx, dy) = set.keyed();
//!         let (kx, ky) = (fix_from_bits(hash(key, 1)), fix_from_bits(hash(key, 2)));
//!         for (i, p) in out.iter_mut().enumerate() {
//!             let x = (((2 * i as u64 + 1) << 23) / set.count as u64) as u32;
//!             let y = ((i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40) as u32;
//!             let (x, y) = (fix_add(fix_add(x, kx), dx), fix_add(fix_add(y, ky), dy));
//!             *p = Vec2::new(fix_to_f32(x), fix_to_f32(y));
//!         }
//!     }
//! }
//!
//! let golden = hemilab::sampling::register(Box::new(Golden))?;
//! assert_eq!("golden".parse::<Sequence>()?, golden);
//!
//! let (scene, width, height) = hemilab::load::scene_at("scenes/cornell-box.toml".as_ref(), Some((32, 32)))?;
//! let exr = std::fs::read_dir("reference")?
//!     .filter_map(|e| e.ok().map(|e| e.path()))
//!     .find(|p| p.to_string_lossy().contains("cornell-box-32x32-") && p.extension() == Some("exr".as_ref()))
//!     .expect("the committed 32x32 reference");
//! let channels = hemilab::io::read_exr(&exr)?;
//! let channel = |name: &str| channels.iter().find(|(n, _)| n == name).map(|(_, i)| i.clone());
//! let (reference, coverage) = (channel("Y").expect("AO"), channel("A").expect("coverage"));
//!
//! // RMSE at 16 cosine-weighted rays, per-pixel shift, averaged over four seeds.
//! let rmse = |sequence: Sequence| -> f64 {
//!     (1..=4u64)
//!         .map(|seed| {
//!             let sampler = SamplerConfig::new(sequence, SeedMode::Shift, 16, seed).unwrap();
//!             sampler.prepare();
//!             let job = RenderJob {
//!                 distribution: Distribution::SineCosine,
//!                 sampler,
//!                 width,
//!                 height,
//!                 ao_distance: scene.ao_distance,
//!             };
//!             let image = render(&scene, &job, &|_| {}).ao;
//!             hemilab::metrics::measure(&image, &reference, &coverage).unwrap().rmse
//!         })
//!         .sum::<f64>()
//!         / 4.0
//! };
//! let (ours, random) = (rmse(golden), rmse(Sequence::Random));
//! assert!(ours < 0.8 * random, "golden {ours:.4} against pseudo-random {random:.4}");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

// Declared in pipeline order (blank lines keep rustfmt from sorting them).
pub mod spec;

pub mod load;

pub mod plan;

pub mod sampling;

pub mod scene;

pub mod render;

pub mod denoise;

pub mod jobs;

pub mod timing;

pub mod image;

pub mod metrics;

pub mod stats;

pub mod reference;

pub mod results;

pub mod compare;

pub mod advice;

pub mod shard;

pub mod report;

// The shell around the pipeline: errors, signals, the filesystem, progress.
pub mod error;

pub mod interrupt;

pub mod io;

pub mod denoise_command;

pub mod outdir;

pub mod progress;

// The command line and its commands, behind `main_with`.
pub mod cli;

pub mod app;

/// The `hemilab` command on `args` (the program's name first, as `std::env::args_os()` gives
/// them): parse, run, print the error chain; returns the exit status (0, 2 for bad input, 130
/// after Ctrl-C). A bad command line exits here with clap's status 2 and its message, as `--help`
/// and `--version` exit with 0. Sequences registered before the call are named like the built-in
/// ones by specs and flags: that is how a sampler written outside the crate is measured.
pub fn main_with<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    use clap::Parser;
    // Before any thread starts: signals are then taken by a thread of their own (see `interrupt`).
    interrupt::install();
    let cli = cli::Cli::parse_from(args);
    match app::run(cli) {
        Ok(()) => 0,
        Err(e) => {
            match &e {
                error::Error::Interrupted(what) => eprintln!("{what}"),
                _ => eprintln!("error: {e}"),
            }
            e.exit_code()
        }
    }
}

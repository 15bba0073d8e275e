//! The sampler interface and the one list of sequences every other stage reads.
//!
//! A sequence is a type implementing [`PointSequence`]: its names and attributes ([`SequenceInfo`]),
//! the tables it needs made before any timed render (`prepare`), and the points of one pixel in one
//! frame (`fill`), given everything the seed modes and the frame schedule have derived for that
//! pixel ([`PixelSet`]). Each built-in sequence lives in its own file and is one line of
//! `BUILT_IN`; the spec and CLI names, the report's words, advise's "sensible" rule, the claims'
//! and report's list of the samplers renderers ship all read this list, so a new sequence is one
//! new file and one line here. A program using the library adds its own with [`register`] (the
//! crate's doctest in `lib.rs` does) and names it in a spec like any other.
//!
//! [`Sequence`] is a small copyable handle into the list: its order is the list's (the order of
//! tables and listings), and the built-ins keep the names the code has always used for them
//! (`Sequence::Fibonacci`, …) as constants.

use super::seed::{PixelSeed, SeedMode};
use glam::Vec2;
use std::sync::RwLock;

/// How a sequence is named and what the rest of hemilab may assume of it.
#[derive(Debug, Clone, Copy)]
pub struct SequenceInfo {
    /// The name specs, the command line and `results.csv` use (lower case, no spaces).
    pub name: &'static str,
    /// The name in person-facing text (`Row::name`: "sine-cosine, Sobol', shift").
    pub label: &'static str,
    /// Other spellings people write, each pointing at `name` in the unknown-name error.
    pub words: &'static [&'static str],
    /// Whether its numbers are fresh per pixel under every seed mode but `static` (pseudo-random
    /// numbers): then `rotation` and `shift` name the same images, and `rotation` is unbiased
    /// per pixel.
    pub fresh_per_pixel: bool,
    /// Whether renderers ship it besides the paper's own sequences, and how (see [`Shipped`]).
    pub shipped: Option<Shipped>,
}

/// A sequence renderers ship: advise runs it by default only in the seed modes it ships with, the
/// equal-time claims compare the lattice with it, and the report draws its panels.
#[derive(Debug, Clone, Copy)]
pub struct Shipped {
    /// The seed modes it ships with.
    pub modes: &'static [SeedMode],
    /// Why the other seed modes are not in advise's default sweep (advise prints it).
    pub why: &'static str,
    /// Its place in the report's and claims' list of shipped samplers.
    pub rank: u8,
}

/// What one pixel's points are made from in one frame: the set's size and pixel, the seed mode
/// with the pixel's keys (`seed`, derived from the frame's run seed), the mode's offsets with the
/// frame schedule's added (`offsets`), and the schedule's offsets alone (`frame_offsets`); all
/// offsets in 24-bit fixed point (`hash::fix_add`).
#[derive(Debug, Clone, Copy)]
pub struct PixelSet {
    /// Points in the whole set (≥ 1): strata and lattice spacing follow it, whatever `out`'s length.
    pub count: u32,
    pub x: u32,
    pub y: u32,
    /// The pixel's index (y · width + x), which keys its fresh numbers.
    pub pixel: u64,
    pub seed_mode: SeedMode,
    pub seed: PixelSeed,
    pub offsets: (u32, u32),
    pub frame_offsets: (u32, u32),
}

impl PixelSet {
    /// The common rule of a keyed set: under `shift` the set's own randomness is fresh per pixel
    /// (an Owen scramble, a jitter, a start offset) and nothing is added on top but the frame's
    /// offsets; under every other mode the set is the run's and the mode's offsets are added.
    /// Returns (key, dx, dy).
    #[inline]
    pub fn keyed(&self) -> (u64, u32, u32) {
        if self.seed_mode == SeedMode::Shift {
            (self.seed.set_key(true), self.frame_offsets.0, self.frame_offsets.1)
        } else {
            (self.seed.set_key(false), self.offsets.0, self.offsets.1)
        }
    }
}

/// A 2-D sequence hemilab can sample the hemisphere with (see the module's doc).
pub trait PointSequence: Send + Sync {
    fn info(&self) -> &SequenceInfo;

    /// Makes every process-wide table `fill` reads, so that no timed render pays for it.
    fn prepare(&self) {}

    /// The most points one pixel's set can have, if the sequence is finite (a file's point set):
    /// specs and the command line refuse larger counts.
    fn max_count(&self) -> Option<u32> {
        None
    }

    /// Writes the first `out.len()` points of pixel `set`'s `set.count`-point set into `out`, in
    /// [0, 1)². Must depend only on `set` (never on threads or other pixels) and not allocate.
    fn fill(&self, set: &PixelSet, out: &mut [Vec2]);
}

use super::{fibonacci, halton, pmj02, r2, random, sobol, stratified, zsobol};

/// The built-in sequences, in the order tables and listings use.
static BUILT_IN: [&dyn PointSequence; 8] = [
    &random::Random,
    &fibonacci::Fibonacci,
    &stratified::Stratified,
    &sobol::Sobol,
    &halton::Halton,
    &pmj02::Pmj02bn,
    &zsobol::ZSobol,
    &r2::R2,
];

/// Sequences a program registered (`register`), after the built-ins.
static REGISTERED: RwLock<Vec<&'static dyn PointSequence>> = RwLock::new(Vec::new());
/// Files' point sets (`register_file`): named and parsed like the others, but not in `all` (a file
/// is the user's, not one of the sequences every listing and default sweep covers).
static FILES: RwLock<Vec<&'static dyn PointSequence>> = RwLock::new(Vec::new());
/// The handles of `FILES` have this bit set.
const FILE_BIT: u16 = 0x8000;

/// A sequence: a handle into the list (built-ins first, then registered ones, in that order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Sequence(u16);

#[allow(non_upper_case_globals)]
impl Sequence {
    /// The paper's pseudo-random numbers ([`random`]).
    pub const Random: Sequence = Sequence(0);
    /// The paper's Fibonacci lattice ([`fibonacci`]).
    pub const Fibonacci: Sequence = Sequence(1);
    /// Jittered strata ([`stratified`]).
    pub const Stratified: Sequence = Sequence(2);
    /// Sobol' (0,2), Owen-scrambled ([`sobol`]).
    pub const Sobol: Sequence = Sequence(3);
    /// Halton bases 2 and 3, Owen-scrambled ([`halton`]).
    pub const Halton: Sequence = Sequence(4);
    /// Progressive multi-jittered (0,2) with blue-noise selection ([`pmj02`]).
    pub const Pmj02bn: Sequence = Sequence(5);
    /// Sobol' through the pixel's Morton code ([`zsobol`]).
    pub const ZSobol: Sequence = Sequence(6);
    /// The plastic-number Kronecker sequence ([`r2`]).
    pub const R2: Sequence = Sequence(7);

    /// The implementation behind the handle.
    #[inline]
    pub fn imp(self) -> &'static dyn PointSequence {
        if self.0 & FILE_BIT != 0 {
            return FILES.read().unwrap_or_else(|e| e.into_inner())[(self.0 & !FILE_BIT) as usize];
        }
        let i = self.0 as usize;
        match BUILT_IN.get(i) {
            Some(s) => *s,
            None => REGISTERED.read().unwrap_or_else(|e| e.into_inner())[i - BUILT_IN.len()],
        }
    }

    pub fn info(self) -> &'static SequenceInfo {
        self.imp().info()
    }

    pub fn name(self) -> &'static str {
        self.info().name
    }

    /// Every sequence, built-in then registered, in the order tables and listings use.
    pub fn all() -> Vec<Sequence> {
        let n = BUILT_IN.len() + REGISTERED.read().unwrap_or_else(|e| e.into_inner()).len();
        (0..n as u16).map(Sequence).collect()
    }

    /// The files' point sets read in this process (`register_file`), in the order they were read.
    pub fn files() -> Vec<Sequence> {
        let n = FILES.read().unwrap_or_else(|e| e.into_inner()).len();
        (0..n as u16).map(|i| Sequence(i | FILE_BIT)).collect()
    }

    /// Every accepted name, in the order of `all`.
    pub fn names() -> Vec<&'static str> {
        Self::all().into_iter().map(Sequence::name).collect()
    }

    /// The sequences renderers ship besides the paper's, in their `Shipped::rank` order.
    pub fn shipped() -> Vec<Sequence> {
        let mut v: Vec<(u8, Sequence)> =
            Self::all().into_iter().filter_map(|s| s.info().shipped.map(|sh| (sh.rank, s))).collect();
        v.sort();
        v.into_iter().map(|(_, s)| s).collect()
    }
}

/// Why a sequence could not be registered.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RegisterError(pub String);

impl std::fmt::Display for RegisterError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for RegisterError {}

/// Adds a sequence to the list for the rest of the process (it is leaked: the list lives as long
/// as the program) and returns its handle. Refused if its name is taken or is not a plain name
/// (lower-case letters, digits and '-'), since specs and results name it.
pub fn register(sequence: Box<dyn PointSequence>) -> Result<Sequence, RegisterError> {
    let name = sequence.info().name;
    let plain =
        !name.is_empty() && name.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-');
    if !plain {
        return Err(RegisterError(format!(
            "sequence name '{}' must be lower-case letters, digits and '-'",
            name.escape_debug()
        )));
    }
    let mut list = REGISTERED.write().unwrap_or_else(|e| e.into_inner());
    let taken =
        BUILT_IN.iter().chain(list.iter()).any(|s| s.info().name == name || s.info().words.contains(&name));
    if taken {
        return Err(RegisterError(format!("a sequence named '{name}' exists already")));
    }
    let index = BUILT_IN.len() + list.len();
    let index = u16::try_from(index).map_err(|_| RegisterError("too many sequences".into()))?;
    list.push(Box::leak(sequence));
    Ok(Sequence(index))
}

/// Adds a file's point set (`point_file::PointFile`) to the list: as `register`, but its name is
/// `points:PATH#hash8` (the file as the spec or command line wrote it, and its content), and a
/// sequence of that name already registered (the same file, read again) is returned instead.
pub fn register_file(sequence: Box<dyn PointSequence>) -> Result<Sequence, RegisterError> {
    let name = sequence.info().name;
    let ok = name.starts_with("points:") && !name.chars().any(|c| c.is_control());
    if !ok {
        return Err(RegisterError(format!(
            "a point file's name '{}' must start with 'points:'",
            name.escape_debug()
        )));
    }
    let mut list = FILES.write().unwrap_or_else(|e| e.into_inner());
    if let Some(i) = list.iter().position(|s| s.info().name == name) {
        return Ok(Sequence(i as u16 | FILE_BIT));
    }
    let index = u16::try_from(list.len()).ok().filter(|&i| i < FILE_BIT);
    let index = index.ok_or_else(|| RegisterError("too many point files".into()))?;
    list.push(Box::leak(sequence));
    Ok(Sequence(index | FILE_BIT))
}

impl std::str::FromStr for Sequence {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let all = Sequence::all();
        if let Some(q) = all.iter().chain(&Sequence::files()).find(|q| q.name() == s) {
            return Ok(*q);
        }
        // The report's words are not values, but say which is meant.
        let said = s.trim().to_lowercase();
        let meant = all.iter().find(|q| q.info().words.contains(&said.as_str()));
        let s = s.escape_debug();
        let hint = meant.map_or(String::new(), |m| format!(" ('{s}' is written `{}`)", m.name()));
        let file = if said.starts_with("points") {
            " (a point file is named `points:PATH` on the command line and `{ points = \"PATH\" }` in a spec)"
        } else {
            ""
        };
        let builtin: Vec<&str> =
            Sequence::names().into_iter().filter(|n| !n.starts_with("points:")).collect();
        Err(format!("unknown sequence '{s}'; valid: {}{hint}{file}", builtin.join(", ")))
    }
}

impl std::fmt::Display for Sequence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Why the shipped samplers other than ZSobol run in advise's default sweep with `shift` only.
pub const SHIPS_SHIFTED: &str =
    "the samplers renderers ship besides the paper's run as they ship them: `shift`";

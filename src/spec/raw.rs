//! Phase 1 of reading a spec: its raw shape as serde reads it (unknown keys refused, types checked,
//! every value with its place in the text), which phase 2 (`validate`) checks and turns into a
//! `Spec`.

use serde::Deserialize;
use toml::Spanned;

pub(super) type S<T> = Spanned<T>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSpec {
    pub(super) name: Option<S<String>>,
    pub(super) scenes: S<Vec<S<String>>>,
    pub(super) resolution: Option<S<Vec<S<i64>>>>,
    pub(super) ao_distance: Option<S<toml::Value>>,
    pub(super) replicates: Option<S<i64>>,
    pub(super) seed: Option<S<i64>>,
    pub(super) point_figures: Option<S<bool>>,
    pub(super) flip_ppd: Option<S<toml::Value>>,
    pub(super) reference: Option<RawReference>,
    pub(super) timing: Option<RawTiming>,
    /// Measure on tiles of the image (`[tiles]`, `plan::tiles`).
    pub(super) tiles: Option<S<RawTiles>>,
    /// Named camera paths for the real-time groups' `cameras` (`[cameras.NAME]`).
    #[serde(default)]
    pub(super) cameras: std::collections::BTreeMap<String, S<RawCamera>>,
    /// Named denoiser commands for the groups' `denoisers` (`[denoisers.NAME]`).
    #[serde(default)]
    pub(super) denoisers: std::collections::BTreeMap<String, S<crate::denoise_command::DenoiseCommand>>,
    #[serde(default)]
    pub(super) table: Vec<S<RawGroup>>,
    #[serde(default)]
    pub(super) convergence: Vec<S<RawGroup>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawReference {
    pub(super) dir: Option<S<String>>,
    pub(super) rays: Option<S<toml::Value>>,
    pub(super) replicates: Option<S<i64>>,
    pub(super) seed: Option<S<i64>>,
    pub(super) distribution: Option<S<String>>,
    pub(super) sequence: Option<S<String>>,
    pub(super) seed_mode: Option<S<String>>,
    pub(super) allocation: Option<S<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTiming {
    pub(super) repeats: Option<S<i64>>,
    pub(super) seed: Option<S<i64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTiles {
    pub(super) count: Option<S<i64>>,
    pub(super) size: Option<S<i64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawGroup {
    pub(super) name: S<String>,
    pub(super) rays: S<Vec<S<i64>>>,
    pub(super) replicates: Option<S<i64>>,
    pub(super) scenes: Option<S<Vec<S<String>>>>,
    pub(super) rows: Option<S<Vec<S<RawRow>>>>,
    pub(super) distributions: Option<S<Vec<S<String>>>>,
    pub(super) sequences: Option<S<Vec<S<toml::Value>>>>,
    pub(super) seed_modes: Option<S<Vec<S<toml::Value>>>>,
    pub(super) frames: Option<S<i64>>,
    pub(super) pipelines: Option<S<Vec<S<String>>>>,
    pub(super) schedules: Option<S<Vec<S<String>>>>,
    pub(super) integrands: Option<S<Vec<S<String>>>>,
    pub(super) cameras: Option<S<Vec<S<String>>>>,
    pub(super) denoisers: Option<S<Vec<S<String>>>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCamera {
    /// `"static"`, or a table with one of `orbit`, `dolly`, `pan`, `keyframes` (`scene::camera_path`).
    pub(super) path: crate::scene::camera_path::CameraPath,
    /// Halton (2,3) sub-pixel jitter per frame, as TAA engines do; default false.
    #[serde(default)]
    pub(super) jitter: bool,
}

/// A spec's camera as `[cameras.NAME]` writes it.
pub(super) struct CameraChoice {
    pub(super) path: crate::scene::camera_path::CameraPath,
    pub(super) jitter: bool,
}

/// The named things a group's axes may name: cameras and denoisers.
pub(super) struct Named<'a> {
    pub(super) cameras: &'a [(String, CameraChoice)],
    pub(super) denoisers: &'a [crate::plan::Denoiser],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRow {
    pub(super) distribution: S<String>,
    pub(super) sequence: S<toml::Value>,
    pub(super) seed_mode: Option<S<toml::Value>>,
}

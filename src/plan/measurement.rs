//! What is measured of a job's images besides the configuration that renders them: what the rays
//! integrate, how the frames are randomized over time, what is done to them before the error is
//! taken, and at which frame. One typed value, carried by every `Job` and `JobResult`, so that a
//! new axis of measurement (a camera path, say) is one more field here and not one more special
//! case in each stage.
//!
//! The paper's measurement — one raw AO frame — is `Measurement::PAPER`; it adds nothing to a job's
//! key, so every key of a spec without the newer axes is what it was before they existed.
//!
//! A camera path and a user's denoiser are values a spec defines by name; a measurement carries
//! them as small handles (`CameraId`, `DenoiserId`) into a process-wide list they are interned in
//! when the spec is read, so that a measurement stays a plain copyable value.

use crate::denoise::Pipeline;
use crate::denoise_command::DenoiseCommand;
use crate::sampling::{Integrand, Schedule};
use crate::scene::camera_path::CameraPath;
use std::fmt::Write as _;
use std::sync::RwLock;

/// How the camera moves over a multi-frame measurement's frames: a named path of the spec, with
/// or without the per-frame sub-pixel jitter of TAA engines (`scene::camera_path::halton_jitter`).
#[derive(Debug, Clone, PartialEq)]
pub struct CameraRun {
    /// The spec's name for it (the results' `camera` column).
    pub name: String,
    pub path: CameraPath,
    pub jitter: bool,
    /// Frames the path spans: frame f's camera is the path at f / (frames − 1) (the group's
    /// `frames`), so that frame f has one camera whichever frame a job reports.
    pub frames: u32,
}

impl CameraRun {
    /// Everything that determines each frame's view, as explicit text (part of job keys).
    pub fn canonical(&self) -> String {
        let v = |a: [f64; 3]| format!("{:?},{:?},{:?}", a[0], a[1], a[2]);
        let path = match &self.path {
            CameraPath::Static => "static".to_string(),
            CameraPath::Orbit { degrees } => format!("orbit:{degrees:?}"),
            CameraPath::Dolly { distance } => format!("dolly:{distance:?}"),
            CameraPath::Pan { degrees } => format!("pan:{degrees:?}"),
            CameraPath::Keyframes(keys) => {
                let k: Vec<String> =
                    keys.iter().map(|k| format!("{}@{}>{}", k.frame, v(k.eye), v(k.target))).collect();
                format!("keyframes:{}", k.join("|"))
            }
        };
        format!("{}={path}/{}{}", self.name, self.frames, if self.jitter { "/jitter" } else { "" })
    }
}

/// A user's denoiser, named by the spec, run on every measured frame after the pipeline.
#[derive(Debug, Clone, PartialEq)]
pub struct Denoiser {
    pub name: String,
    pub command: DenoiseCommand,
}

static CAMERAS: RwLock<Vec<&'static CameraRun>> = RwLock::new(Vec::new());
static DENOISERS: RwLock<Vec<&'static Denoiser>> = RwLock::new(Vec::new());

/// Interns `value` in `list` (equal values share one entry) and returns its index from 1.
fn intern<T: PartialEq>(list: &RwLock<Vec<&'static T>>, value: T) -> u16 {
    let mut l = list.write().unwrap_or_else(|e| e.into_inner());
    if let Some(i) = l.iter().position(|x| **x == value) {
        return i as u16 + 1;
    }
    l.push(Box::leak(Box::new(value)));
    u16::try_from(l.len()).expect("fewer than 65536 cameras and denoisers in a process")
}

fn get<T>(list: &RwLock<Vec<&'static T>>, id: u16) -> Option<&'static T> {
    let i = id.checked_sub(1)? as usize;
    list.read().unwrap_or_else(|e| e.into_inner()).get(i).copied()
}

/// A measurement's camera: the scene's own, unjittered (`STATIC`, the default), or an interned
/// `CameraRun`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct CameraId(u16);

impl CameraId {
    /// The scene's camera for every frame, no jitter.
    pub const STATIC: CameraId = CameraId(0);
    /// What a results file names the static camera.
    pub const STATIC_NAME: &'static str = "static";

    /// The handle of `run` (a static path without jitter is `STATIC`).
    pub fn intern(run: CameraRun) -> CameraId {
        if run.path.is_static() && !run.jitter {
            return CameraId::STATIC;
        }
        CameraId(intern(&CAMERAS, run))
    }

    /// The run behind the handle (`None`: the static camera).
    pub fn run(self) -> Option<&'static CameraRun> {
        get(&CAMERAS, self.0)
    }

    pub fn name(self) -> String {
        self.run().map_or(Self::STATIC_NAME.to_string(), |r| r.name.clone())
    }

    /// The handle a results file's `camera` column names, among those interned in this process.
    pub fn named(name: &str) -> Option<CameraId> {
        if name == Self::STATIC_NAME {
            return Some(CameraId::STATIC);
        }
        let l = CAMERAS.read().unwrap_or_else(|e| e.into_inner());
        l.iter().position(|r| r.name == name).map(|i| CameraId(i as u16 + 1))
    }
}

/// A measurement's denoiser step: none (`NONE`, the default) or an interned `Denoiser`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct DenoiserId(u16);

impl DenoiserId {
    pub const NONE: DenoiserId = DenoiserId(0);

    pub fn intern(d: Denoiser) -> DenoiserId {
        DenoiserId(intern(&DENOISERS, d))
    }

    pub fn get(self) -> Option<&'static Denoiser> {
        get(&DENOISERS, self.0)
    }

    /// The results' `denoiser` column: its name, empty for none.
    pub fn name(self) -> String {
        self.get().map_or(String::new(), |d| d.name.clone())
    }

    pub fn named(name: &str) -> Option<DenoiserId> {
        if name.is_empty() {
            return Some(DenoiserId::NONE);
        }
        let l = DENOISERS.read().unwrap_or_else(|e| e.into_inner());
        l.iter().position(|d| d.name == name).map(|i| DenoiserId(i as u16 + 1))
    }
}

/// What one job's image measures (see the module's doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measurement {
    /// What the rays integrate (`sampling::Integrand`).
    pub integrand: Integrand,
    /// The frame whose image is measured, counted from 1: frames 0..frame-1 of a static camera
    /// are rendered (with `SamplerConfig::with_frame`) when the pipeline accumulates, only the
    /// last one when it does not.
    pub frame: u32,
    /// How the per-pixel randomization changes from frame to frame.
    pub schedule: Schedule,
    /// What is done to the frames before the image is measured (`denoise::Pipeline`).
    pub pipeline: Pipeline,
    /// How the camera moves over the frames.
    pub camera: CameraId,
    /// The user's denoiser, run on each measured frame after the pipeline.
    pub denoiser: DenoiserId,
    /// Measured on tiles of the image (the spec's `[tiles]`, `jobs::tiles`); None: the whole image.
    pub tiles: Option<super::tiles::TileSpec>,
    /// The first frame rendered, from 1 (1: every frame up to `frame`): a steady-state
    /// measurement (`first_frame`) starts its run where the frames before would weigh at most
    /// `denoise::accumulate::FORGOTTEN` in the measured one.
    pub first_frame: u32,
}

impl Default for Measurement {
    fn default() -> Self {
        Self::PAPER
    }
}

impl Measurement {
    /// One raw AO frame: the paper's tables.
    pub const PAPER: Measurement = Measurement {
        integrand: Integrand::Ao,
        frame: 1,
        schedule: Schedule::Independent,
        pipeline: Pipeline::RAW,
        camera: CameraId::STATIC,
        denoiser: DenoiserId::NONE,
        tiles: None,
        first_frame: 1,
    };

    /// The same measurement of another integrand.
    pub fn of(integrand: Integrand) -> Self {
        Self { integrand, ..Self::PAPER }
    }

    /// Whether one raw frame of the scene's camera is measured (frame 1, independent schedule,
    /// raw, no denoiser), of any integrand: the images the paper's tables, aggregates and
    /// equal-time comparisons read.
    pub fn is_single_frame(&self) -> bool {
        self.frame == 1
            && self.schedule == Schedule::Independent
            && self.pipeline == Pipeline::RAW
            && self.camera == CameraId::STATIC
            && self.denoiser == DenoiserId::NONE
    }

    /// The frame indices (from 0) a job renders: all `frame` frames when the pipeline
    /// accumulates, the one last frame when it does not.
    pub fn frames_rendered(&self) -> Vec<u32> {
        if self.pipeline.is_temporal() {
            (self.first_frame.clamp(1, self.frame) - 1..self.frame).collect()
        } else {
            vec![self.frame - 1]
        }
    }

    /// The same measurement at steady state: its run started `pipeline.memory_frames()` frames
    /// before `frame` when that is later than frame 1 (a pipeline that forgets nothing, or one
    /// whose memory reaches frame 1, renders every frame).
    pub fn at_steady_state(self) -> Self {
        let first_frame = match self.pipeline.memory_frames() {
            Some(w) if w < self.frame => self.frame - w + 1,
            _ => 1,
        };
        Self { first_frame, ..self }
    }

    /// `;from=F` when the run starts at frame F > 1, else empty (so every other key is what it was).
    pub fn start_key(&self) -> String {
        if self.first_frame > 1 && self.pipeline.is_temporal() {
            format!(";from={}", self.first_frame)
        } else {
            String::new()
        }
    }

    /// Whether the timing protocol's second round (more renders for cheap configurations) applies:
    /// a multi-frame measurement is run for its errors, its many cheap units would each be
    /// re-rendered up to `max_repeats` times, and its times are those of the first round.
    pub fn tops_up(&self) -> bool {
        self.is_single_frame()
    }

    /// `;frame=..;schedule=..;pipeline=..` for a multi-frame measurement, empty for a single frame;
    /// part of the job's key and of its timing unit.
    pub fn frames_key(&self) -> String {
        if self.is_single_frame() {
            String::new()
        } else {
            format!(
                ";frame={};schedule={};pipeline={}{}{}",
                self.frame,
                self.schedule,
                self.pipeline,
                self.view_key(),
                self.start_key()
            )
        }
    }

    /// `;camera=..` for a moving or jittered camera, `;denoiser=..` for a denoiser step (its
    /// command spelt out): empty for the static camera without one, so older keys stay.
    pub fn view_key(&self) -> String {
        let mut s = String::new();
        if let Some(c) = self.camera.run() {
            let _ = write!(s, ";camera={}", c.canonical());
        }
        if let Some(d) = self.denoiser.get() {
            let c = &d.command;
            let _ = write!(s, ";denoiser={}:{}:{}", d.name, c.program, c.args.join(" "));
        }
        s
    }

    /// What the jobs of one series of frames share (`plan::series`): for a pipeline that
    /// accumulates, the frames part without the frame or the pipeline, so that every reported
    /// frame of one sequence, through every accumulating pipeline, is read from one render of it;
    /// otherwise `frames_key`. Part of the timing unit.
    pub fn series_key(&self) -> String {
        let part = if self.pipeline.is_temporal() {
            format!(";schedule={};pipeline=temporal{}{}", self.schedule, self.view_key(), self.start_key())
        } else {
            self.frames_key()
        };
        part + &self.tiles_key()
    }

    /// `;tiles=4x128` when measured on tiles, else empty (so every other key is what it was).
    pub fn tiles_key(&self) -> String {
        self.tiles.map_or(String::new(), |t| format!(";tiles={}", t.canonical()))
    }

    /// Everything this measurement adds to a job's canonical text: the frames part, then
    /// `;integrand=..` unless it is AO.
    pub fn key_suffix(&self) -> String {
        let mut s = self.frames_key();
        if self.integrand != Integrand::Ao {
            let _ = write!(s, ";integrand={}", self.integrand);
        }
        s.push_str(&self.tiles_key());
        s
    }

    /// `-<schedule>-<pipeline>[-<camera>][-<denoiser>]-f<frame>` for a multi-frame measurement's
    /// file names, empty for one frame.
    pub fn file_part(&self) -> String {
        if self.is_single_frame() {
            return String::new();
        }
        let mut s = format!("-{}-{}", self.schedule, self.pipeline);
        for extra in [self.camera.run().map(|c| c.name.clone()), self.denoiser.get().map(|d| d.name.clone())]
            .into_iter()
            .flatten()
        {
            let _ = write!(s, "-{extra}");
        }
        let _ = write!(s, "-f{}", self.frame);
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_measurement_adds_nothing_to_a_key() {
        assert_eq!(Measurement::PAPER.key_suffix(), "");
        assert_eq!(Measurement::PAPER.file_part(), "");
        assert!(Measurement::PAPER.is_single_frame() && Measurement::PAPER.tops_up());
        assert_eq!(Measurement::PAPER.frames_rendered(), vec![0]);
        let v = Measurement::of(Integrand::Visibility);
        assert!(v.is_single_frame());
        assert_eq!(v.key_suffix(), ";integrand=visibility");
    }

    #[test]
    fn a_temporal_pipeline_renders_every_frame_a_spatial_one_the_last() {
        let m = |p: &str, frame| Measurement { frame, pipeline: p.parse().unwrap(), ..Measurement::PAPER };
        assert_eq!(m("ema0.1+atrous", 4).frames_rendered(), vec![0, 1, 2, 3]);
        assert_eq!(m("atrous", 4).frames_rendered(), vec![3]);
        assert_eq!(m("atrous", 1).frames_key(), ";frame=1;schedule=independent;pipeline=atrous");
        assert!(!m("atrous", 1).tops_up());
    }
}

//! What the user asked `hemilab advise` for (its flags, less the budgets), as one value stored
//! with the advice (`advice.json`'s sibling `request.json`) so that `--from` sets the same sweep
//! up again, and the real-time flags read from text: `--camera-path` and `--denoiser`. Nothing is
//! read or written here.

use crate::advice;
use crate::denoise_command::DenoiseCommand;
use crate::error::{Error, Result};
use crate::plan::{CameraId, CameraRun, Denoiser};
use crate::sampling::Integrand;
use crate::scene::camera_path::CameraPath;
use std::path::{Path, PathBuf};

/// What the user asked advise for (`hemilab advise`'s flags), less the budgets: the sweep. Stored
/// in the output directory (`to_json`, outdir's `ADVISE_REQUEST`) so that `advise --from` can set
/// the same sweep up again without the flags.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    pub scene: PathBuf,
    pub rays: Vec<u32>,
    pub only: Vec<advice::Pattern>,
    pub replicates: u32,
    pub resolution: Option<(u32, u32)>,
    pub reference_dir: Option<PathBuf>,
    /// What is done to the frames before the image is ranked (`advice::pipeline`; raw: the paper's).
    pub pipeline: crate::denoise::Pipeline,
    /// The frame whose image is ranked (frames accumulated by a temporal pipeline), 1 for raw.
    pub frames: u32,
    /// What the rays integrate; `ao` in a request written before integrands existed.
    pub integrand: Integrand,
    /// Textures and point files to measure besides the built-ins (`--texture`, `--points`), as
    /// `texture:PATH[:use]` / `points:PATH`, PATH as given (it names the seed mode or sequence).
    pub files: Vec<String>,
    /// Where their relative paths start (the directory advise ran in), so that `--from` elsewhere
    /// reads the same files under the same names.
    pub files_dir: Option<PathBuf>,
    /// Camera paths besides the scene's still camera and the default moving one (`--camera-path`,
    /// as given: `orbit:DEG`, `pan:DEG`, `dolly:DISTANCE`); each jittered, as a TAA engine's.
    pub cameras: Vec<String>,
    /// The user's denoiser run on every ranked frame after the pipeline (`--denoiser
    /// NAME=PROGRAM ARGS…`, as given; its paths against `files_dir`).
    pub denoiser: Option<String>,
}

impl Request {
    /// As JSON, the paths made absolute (a later `--from` may run from another directory).
    pub fn to_json(&self) -> String {
        let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf()).display().to_string();
        let v = serde_json::json!({
            "scene": abs(&self.scene),
            "rays": self.rays,
            "only": self.only.iter().map(advice::Pattern::to_text).collect::<Vec<_>>(),
            "replicates": self.replicates,
            "resolution": self.resolution.map(|(w, h)| [w, h]),
            "reference_dir": self.reference_dir.as_deref().map(abs),
            "pipeline": self.pipeline.to_string(),
            "frames": self.frames,
            "integrand": self.integrand.to_string(),
            "files": self.files,
            "files_dir": self.files_dir.as_deref().map(abs),
            "cameras": self.cameras,
            "denoiser": self.denoiser,
        });
        let mut text = serde_json::to_string_pretty(&v).unwrap_or_default();
        text.push('\n');
        text
    }

    /// What makes `earlier` another question than this one, if anything: its scene (as an
    /// absolute path), its pipeline, frame or integrand. Other rays, replicates or budgets are the
    /// same question asked again (a rerun resumes from the records it shares).
    pub fn differs_from(&self, earlier: &Request) -> Option<String> {
        let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
        if abs(&self.scene) != abs(&earlier.scene) {
            return Some(format!("the scene {}", earlier.scene.display()));
        }
        if (self.pipeline, self.frames) != (earlier.pipeline, earlier.frames) {
            return Some(format!("pipeline {} at frame {}", earlier.pipeline, earlier.frames));
        }
        if self.integrand != earlier.integrand {
            return Some(format!("integrand {}", earlier.integrand));
        }
        if self.denoiser != earlier.denoiser {
            return Some(match &earlier.denoiser {
                Some(d) => format!("the denoiser {d}"),
                None => "no denoiser".into(),
            });
        }
        None
    }

    /// Reads `to_json`'s text back; the message says what is missing or wrong.
    pub fn from_json(text: &str) -> std::result::Result<Self, String> {
        let v: serde_json::Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
        let field = |k: &str| v.get(k).ok_or_else(|| format!("no '{k}'"));
        let de = |k: &str| -> std::result::Result<serde_json::Value, String> { field(k).cloned() };
        let scene: String = serde_json::from_value(de("scene")?).map_err(|e| format!("scene: {e}"))?;
        let rays: Vec<u32> = serde_json::from_value(de("rays")?).map_err(|e| format!("rays: {e}"))?;
        let only: Vec<String> = serde_json::from_value(de("only")?).map_err(|e| format!("only: {e}"))?;
        let replicates: u32 =
            serde_json::from_value(de("replicates")?).map_err(|e| format!("replicates: {e}"))?;
        let resolution: Option<[u32; 2]> =
            serde_json::from_value(de("resolution")?).map_err(|e| format!("resolution: {e}"))?;
        let reference_dir: Option<String> =
            serde_json::from_value(de("reference_dir")?).map_err(|e| format!("reference_dir: {e}"))?;
        // An earlier advise's request, from before pipelines, ranked raw single frames.
        let pipeline = match v.get("pipeline").and_then(|p| p.as_str()) {
            Some(p) => p.parse().map_err(|e| format!("pipeline: {e}"))?,
            None => crate::denoise::Pipeline::RAW,
        };
        let frames = v.get("frames").and_then(|f| f.as_u64()).map_or(1, |f| f as u32);
        Ok(Self {
            scene: scene.into(),
            rays,
            only: only.iter().map(|p| advice::Pattern::parse(p)).collect::<std::result::Result<_, _>>()?,
            replicates,
            resolution: resolution.map(|[w, h]| (w, h)),
            reference_dir: reference_dir.map(PathBuf::from),
            pipeline,
            frames,
            integrand: match v.get("integrand").and_then(|i| i.as_str()) {
                Some(i) => Integrand::parse(i).map_err(|e| format!("integrand: {e}"))?,
                None => Integrand::Ao,
            },
            // A request from before files could be named has none.
            files: match v.get("files") {
                Some(f) => serde_json::from_value(f.clone()).map_err(|e| format!("files: {e}"))?,
                None => Vec::new(),
            },
            files_dir: v.get("files_dir").and_then(|d| d.as_str()).map(PathBuf::from),
            // A request from before cameras and denoisers could be named has none.
            cameras: match v.get("cameras") {
                Some(c) => serde_json::from_value(c.clone()).map_err(|e| format!("cameras: {e}"))?,
                None => Vec::new(),
            },
            denoiser: v.get("denoiser").and_then(|d| d.as_str()).map(String::from),
        })
    }
}

/// The name advise gives the moving camera it always adds (results' `camera` column).
pub const DEFAULT_PATH_NAME: &str = "orbit";

/// The moving camera advise adds after an accumulating pipeline when none is asked for… a
/// circle of 10° about the scene camera's target over the frames, jittered as TAA engines jitter
/// (`experiments/realtime.toml`'s `orbit`): small enough to stay in the scene's own view, large
/// enough that history must be reprojected and disoccluded pixels start anew.
pub fn default_path() -> CameraPath {
    CameraPath::Orbit { degrees: 10.0 }
}

/// The cameras a request is measured with: the scene's still camera; after a pipeline that
/// accumulates frames, also the default moving path and each `--camera-path` (jittered), over
/// the request's frames. `--camera-path` without such a pipeline is refused.
pub(super) fn cameras(args: &Request) -> Result<Vec<CameraId>> {
    let mut out = vec![CameraId::STATIC];
    if !args.pipeline.is_temporal() || args.frames < 2 {
        if let Some(c) = args.cameras.first() {
            return Err(Error::Usage(format!(
                "--camera-path {c}: a camera moves over frames, and pipeline '{}' at frame {} accumulates none; \
                 give a pipeline with a temporal part (e.g. ema0.1+atrous, svgf) and --frames of 2 or more",
                args.pipeline, args.frames
            )));
        }
        return Ok(out);
    }
    let run = |name: &str, path: CameraPath| CameraRun {
        name: name.into(),
        path,
        jitter: true,
        frames: args.frames,
    };
    let mut paths = vec![run(DEFAULT_PATH_NAME, default_path())];
    for text in &args.cameras {
        let path = parse_camera_path(text).map_err(|e| Error::Usage(format!("--camera-path {text}: {e}")))?;
        if paths.iter().any(|p| p.path == path) {
            continue;
        }
        // Its name in results' `camera` column and in file names: `pan:15` is `pan-15`.
        let name: String = text
            .trim()
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() || c == '.' { c } else { '-' })
            .collect();
        paths.push(run(&name, path));
    }
    out.extend(paths.into_iter().map(CameraId::intern));
    Ok(out)
}

/// The scene file's own camera paths (`[cameras.NAME]`, `Scene::paths`) as advise ranks them after
/// a pipeline that accumulates frames, over the request's frames, each unless `already` has the
/// same path (none without such a pipeline: the scene's paths are there for its real-time advice,
/// not a request to refuse).
pub(super) fn scene_cameras(
    args: &Request,
    scene: &crate::scene::Scene,
    already: &[CameraId],
) -> Vec<CameraId> {
    if !args.pipeline.is_temporal() || args.frames < 2 {
        return Vec::new();
    }
    let mut out: Vec<CameraId> = Vec::new();
    for (name, path, jitter) in &scene.paths {
        let same = |c: &CameraId| c.run().is_some_and(|r| r.path == *path && r.jitter == *jitter);
        if already.iter().chain(&out).any(same) {
            continue;
        }
        out.push(CameraId::intern(CameraRun {
            name: name.clone(),
            path: path.clone(),
            jitter: *jitter,
            frames: args.frames,
        }));
    }
    out
}

/// `--camera-path`'s text: `orbit:DEG`, `pan:DEG`, `dolly:DISTANCE` (a number, degrees or scene
/// units over the frames; see `scene::camera_path`), or `still` (the scene's camera, jittered).
pub fn parse_camera_path(text: &str) -> std::result::Result<CameraPath, String> {
    let allowed = "allowed: orbit:DEG, pan:DEG, dolly:DISTANCE (over the frames) or still (the scene's camera, jittered)";
    if text.trim() == "still" {
        return Ok(CameraPath::Static);
    }
    let Some((kind, value)) = text.split_once(':') else { return Err(allowed.into()) };
    let v: f64 = value
        .trim()
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| format!("'{value}' is not a finite number; {allowed}"))?;
    match kind.trim() {
        "orbit" => Ok(CameraPath::Orbit { degrees: v }),
        "pan" => Ok(CameraPath::Pan { degrees: v }),
        "dolly" => Ok(CameraPath::Dolly { distance: v }),
        k => Err(format!("unknown path '{k}'; {allowed}")),
    }
}

/// `--denoiser`'s text, `NAME=PROGRAM ARG…` (split at white space; `{input}` and `{output}` among
/// the arguments), checked as a spec's `[denoisers.NAME]` and its paths resolved against `base`
/// (where advise runs) as a spec's are against the spec's folder.
pub fn parse_denoiser(text: &str, base: &Path) -> std::result::Result<Denoiser, String> {
    let Some((name, command)) = text.split_once('=') else {
        return Err(
            "must be NAME=PROGRAM ARGS…, e.g. oidn=python3 examples/oidn_denoise.py {input} {output}".into(),
        );
    };
    let name = name.trim();
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
        return Err(format!("the name '{name}' must be letters, digits, '-' and '_'"));
    }
    let mut words = command.split_whitespace().map(String::from);
    let program = words.next().ok_or("no program after '='")?;
    let command = DenoiseCommand { program, args: words.collect(), timeout_s: 60.0 };
    command.validate()?;
    Ok(Denoiser { name: name.into(), command: command.resolve(base) })
}

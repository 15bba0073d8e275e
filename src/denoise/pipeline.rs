//! What is done to the rendered frames before the image is measured, by name: an optional temporal
//! part (`mean`, `emaA`, `taaA`) then an optional spatial one (`gauss`, `atrous`), joined by `+`;
//! `svgf` is a whole pipeline on its own (its temporal part and à-trous filter are one: its
//! history is its first à-trous pass); `raw` is nothing. `atrous` and `svgf` take an optional
//! iteration count, `atrous:3`, `svgf:5` (default: `edges::default_iterations`, a share of the
//! image). `svgf` then takes the options of `SVGF_OPTIONS` (`svgf:5:fallback:id:releps`: the
//! paper's and Falcor's SVGF, `SvgfOptions`), in that order, each at most once; without them it
//! is the filter every committed run measured, bit for bit. Names round-trip:
//! `"ema0.1+atrous".parse::<Pipeline>()?.to_string() == "ema0.1+atrous"`.
//!
//! `Pipeline::start` gives the stateful per-run filter (`FrameFilter`) that runs any pipeline
//! frame by frame; `accumulator` and `apply_spatial` are the older two-step path (accumulate all
//! frames, then filter the result), for the pipelines it can express (no `taa`, no `svgf`).

use super::accumulate::Temporal;
use super::atrous::{AtrousParams, atrous};
use super::filter::{FrameFilter, Run};
use super::gaussian::{GAUSS_SIGMA, gaussian};
use super::svgf::SvgfOptions;
use crate::image::Image;
use crate::render::GBuffer;
use std::fmt;
use std::str::FromStr;

/// The spatial filter applied to one (accumulated) frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Spatial {
    /// The normalized Gaussian of σ = `GAUSS_SIGMA` pixels over covered pixels (`gaussian`).
    Gauss,
    /// The edge-avoiding à-trous filter with `AtrousParams::default()` (`atrous`) and this many
    /// passes (None: the share-of-image default).
    Atrous(Option<u32>),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pipeline {
    pub temporal: Option<Temporal>,
    pub spatial: Option<Spatial>,
}

/// The most à-trous passes a name may ask for (a 16381 px footprint).
pub const MAX_ITERATIONS: u32 = 12;

/// SVGF's options after `svgf` or `svgf:K`, in the order a name gives them: (name, what it turns on).
/// The default of each is off. `ALLOWED` names every one (a unit test checks).
pub const SVGF_OPTIONS: [(&str, &str); 3] = [
    ("fallback", "Falcor's 3x3 cross-bilateral reprojection fallback"),
    ("id", "the paper's primitive-ID test in reprojection"),
    ("releps", "the luminance weight's epsilon relative to the frame's level"),
];

/// What a pipeline name may be, for errors and `--help`.
pub const ALLOWED: &str = "raw, gauss, atrous, mean, emaA, taaA (0 < A <= 1, e.g. ema0.1, taa0.1), svgf, \
                           or a temporal part (mean, emaA, taaA) then a spatial one (gauss, atrous) joined \
                           by '+', e.g. ema0.1+atrous, taa0.1+atrous, mean+gauss; atrous and svgf take an \
                           iteration count 1..=12 after ':', e.g. atrous:3, svgf:5; svgf then takes, in \
                           this order and each at most once, ':fallback' (Falcor's 3x3 cross-bilateral \
                           reprojection fallback), ':id' (the paper's primitive-ID test in reprojection), \
                           ':releps' (the luminance weight's epsilon relative to the frame's level), all \
                           off by default, e.g. svgf:5:fallback:id:releps, svgf:id";

impl Pipeline {
    pub const RAW: Pipeline = Pipeline { temporal: None, spatial: None };

    /// SVGF's options (its iteration count among them) if this is `svgf`, else None: what lets a
    /// verdict pair `svgf` with `svgf:5` by type (`compare::realtime::iterations_pairs`).
    pub fn svgf_options(&self) -> Option<SvgfOptions> {
        match self.temporal {
            Some(Temporal::Svgf(o)) => Some(o),
            _ => None,
        }
    }

    /// The frames its history remembers (`Temporal::memory_frames`); None when it forgets nothing
    /// (the mean) or combines no frames.
    pub fn memory_frames(&self) -> Option<u32> {
        self.temporal.and_then(Temporal::memory_frames)
    }

    /// True if more than one frame is combined.
    pub fn is_temporal(&self) -> bool {
        self.temporal.is_some()
    }

    /// The stateful filter of one run of `width` × `height` frames: each `push` takes the next
    /// frame and returns the image after the whole pipeline (`FrameFilter`). Default iteration
    /// counts are settled here, from the size.
    pub fn start(&self, width: u32, height: u32) -> Box<dyn FrameFilter> {
        Box::new(Run::new(*self, width, height))
    }

    /// The same pipeline with its default iteration counts (`atrous`, `svgf` without `:K`) settled
    /// for a `width` × `height` image: what a window of that image (`render::Window`) is filtered
    /// with, so that a tile's kernels are the full frame's, not those of the tile's own size.
    pub fn at_size(&self, width: u32, height: u32) -> Pipeline {
        let k = super::edges::default_iterations(width, height);
        let temporal = match self.temporal {
            Some(Temporal::Svgf(o)) => {
                Some(Temporal::Svgf(SvgfOptions { iterations: Some(o.iterations.unwrap_or(k)), ..o }))
            }
            t => t,
        };
        let spatial = match self.spatial {
            Some(Spatial::Atrous(None)) => Some(Spatial::Atrous(Some(k))),
            s => s,
        };
        Pipeline { temporal, spatial }
    }

    /// How far from a pixel, in pixels, one frame through the pipeline reads at a `width` ×
    /// `height` image: half the à-trous footprint (`edges::footprint`; SVGF's 5 passes at 1080
    /// lines: 62 px) plus SVGF's 7 × 7 spatial variance window (3), the Gaussian's 3σ, TAA's 3 × 3
    /// neighbourhood (1). What a tile's apron must hold for its interior to be filtered as in the
    /// full frame (`plan::tiles::apron`).
    pub fn reach(&self, width: u32, height: u32) -> u32 {
        let p = self.at_size(width, height);
        let half = |k: Option<u32>| k.map_or(0, |k| (super::edges::footprint(k) / 2) as u32);
        let temporal = match p.temporal {
            Some(Temporal::Svgf(o)) => half(o.iterations) + 3,
            Some(Temporal::Taa(_)) => 1,
            _ => 0,
        };
        let spatial = match p.spatial {
            Some(Spatial::Atrous(k)) => half(k),
            Some(Spatial::Gauss) => (3.0 * GAUSS_SIGMA).ceil() as u32,
            None => 0,
        };
        temporal + spatial
    }

    /// The spatial part applied to `img` (a frame, or the accumulated frames), guided by `gbuf`
    /// (only `atrous` reads depth and normals; every filter reads its coverage). No spatial part:
    /// `img` as it is.
    pub fn apply_spatial(&self, img: &Image, gbuf: &GBuffer) -> Image {
        match self.spatial {
            None => img.clone(),
            Some(Spatial::Gauss) => gaussian(img, &gbuf.coverage, GAUSS_SIGMA),
            Some(Spatial::Atrous(k)) => {
                atrous(img, gbuf, &AtrousParams { iterations: k, ..AtrousParams::default() })
            }
        }
    }
}

/// Why a pipeline name was refused: the name and what is allowed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PipelineError(pub String);

impl fmt::Display for PipelineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for PipelineError {}

/// `name` or `name:K`: (name, K).
fn iterations(part: &str) -> Result<(&str, Option<u32>), String> {
    match part.split_once(':') {
        None => Ok((part, None)),
        Some((name, k)) => match k.parse::<u32>() {
            Ok(k) if (1..=MAX_ITERATIONS).contains(&k) && (name == "atrous" || name == "svgf") => {
                Ok((name, Some(k)))
            }
            Ok(_) | Err(_) if name == "atrous" || name == "svgf" => {
                Err(format!("the iteration count in '{part}' must be a whole number in 1..={MAX_ITERATIONS}"))
            }
            _ => Err(format!("'{part}': only atrous and svgf take an iteration count")),
        },
    }
}

fn weight(part: &str, prefix: &str) -> Option<Result<f32, String>> {
    let a = part.strip_prefix(prefix)?;
    Some(match a.parse::<f32>() {
        Ok(alpha) if alpha > 0.0 && alpha <= 1.0 => Ok(alpha),
        _ => Err(format!("the weight in '{part}' must be a number in (0, 1], e.g. {prefix}0.1")),
    })
}

/// `svgf[:K][:fallback][:id][:releps]`: its options (`SVGF_OPTIONS`).
fn svgf(part: &str) -> Result<SvgfOptions, String> {
    let mut o = SvgfOptions::default();
    // The position in (K, fallback, id, releps) the next word may take at the earliest.
    let mut next = 0;
    for word in part.split(':').skip(1) {
        let at = match SVGF_OPTIONS.iter().position(|&(name, _)| name == word) {
            Some(i) => i + 1,
            None if !word.is_empty() && word.bytes().all(|b| b.is_ascii_digit()) => 0,
            None => {
                let names: Vec<&str> = SVGF_OPTIONS.iter().map(|&(name, _)| name).collect();
                return Err(format!(
                    "'{word}' in '{part}' is no svgf option (an iteration count 1..={MAX_ITERATIONS}, {})",
                    names.join(", ")
                ));
            }
        };
        if at < next {
            return Err(format!(
                "'{part}': svgf's options come at most once each, in the order K, fallback, id, releps"
            ));
        }
        next = at + 1;
        match at {
            0 => match word.parse::<u32>() {
                Ok(k) if (1..=MAX_ITERATIONS).contains(&k) => o.iterations = Some(k),
                _ => {
                    return Err(format!(
                        "the iteration count in '{part}' must be a whole number in 1..={MAX_ITERATIONS}"
                    ));
                }
            },
            1 => o.fallback = true,
            2 => o.id_test = true,
            _ => o.relative_eps = true,
        }
    }
    Ok(o)
}

fn temporal(part: &str) -> Option<Result<Temporal, String>> {
    if part == "svgf" || part.starts_with("svgf:") {
        return Some(svgf(part).map(Temporal::Svgf));
    }
    let (name, k) = match iterations(part) {
        Ok(v) => v,
        Err(_) => return None,
    };
    match (name, k) {
        (_, Some(_)) => None,
        ("mean", None) => Some(Ok(Temporal::Mean)),
        _ => weight(name, "ema")
            .map(|r| r.map(Temporal::Ema))
            .or_else(|| weight(name, "taa").map(|r| r.map(Temporal::Taa))),
    }
}

fn spatial(part: &str) -> Option<Result<Spatial, String>> {
    match iterations(part) {
        Ok(("gauss", None)) => Some(Ok(Spatial::Gauss)),
        Ok(("atrous", k)) => Some(Ok(Spatial::Atrous(k))),
        Err(e) if part.starts_with("atrous") || part.starts_with("gauss") => Some(Err(e)),
        _ => None,
    }
}

impl FromStr for Pipeline {
    type Err = PipelineError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let refuse = |why: String| PipelineError(format!("unknown pipeline '{s}': {why}; write {ALLOWED}"));
        if s == "raw" {
            return Ok(Pipeline::RAW);
        }
        let parts: Vec<&str> = s.split('+').collect();
        match parts.as_slice() {
            [one] => {
                if let Some(sp) = spatial(one) {
                    return Ok(Pipeline { temporal: None, spatial: Some(sp.map_err(refuse)?) });
                }
                match temporal(one) {
                    Some(Ok(t)) => Ok(Pipeline { temporal: Some(t), spatial: None }),
                    Some(Err(e)) => Err(refuse(e)),
                    None => Err(refuse(format!("'{one}' is no filter"))),
                }
            }
            [t, sp] => {
                let t = match temporal(t) {
                    Some(Ok(Temporal::Svgf(_))) => {
                        return Err(refuse(format!(
                            "'{t}' has its own spatial part and takes none after it"
                        )));
                    }
                    Some(Ok(t)) => t,
                    Some(Err(e)) => return Err(refuse(e)),
                    None => {
                        return Err(refuse(format!(
                            "'{t}' is no temporal part (mean, emaA, taaA); it comes first"
                        )));
                    }
                };
                let sp = match spatial(sp) {
                    Some(r) => r.map_err(refuse)?,
                    None => return Err(refuse(format!("'{sp}' is no spatial filter (gauss, atrous)"))),
                };
                Ok(Pipeline { temporal: Some(t), spatial: Some(sp) })
            }
            _ => Err(refuse("at most one temporal and one spatial part".into())),
        }
    }
}

fn with_iterations(name: &str, k: Option<u32>) -> String {
    match k {
        None => name.to_string(),
        Some(k) => format!("{name}:{k}"),
    }
}

impl fmt::Display for Pipeline {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let t = self.temporal.map(|t| match t {
            Temporal::Mean => "mean".to_string(),
            Temporal::Ema(a) => format!("ema{a}"),
            Temporal::Taa(a) => format!("taa{a}"),
            Temporal::Svgf(o) => {
                let mut name = with_iterations("svgf", o.iterations);
                for (on, (word, _)) in [o.fallback, o.id_test, o.relative_eps].into_iter().zip(SVGF_OPTIONS) {
                    if on {
                        name = name + ":" + word;
                    }
                }
                name
            }
        });
        let s = self.spatial.map(|s| match s {
            Spatial::Gauss => "gauss".to_string(),
            Spatial::Atrous(k) => with_iterations("atrous", k),
        });
        match (t, s) {
            (None, None) => f.write_str("raw"),
            (Some(t), None) => f.write_str(&t),
            (None, Some(s)) => f.write_str(&s),
            (Some(t), Some(s)) => write!(f, "{t}+{s}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reach_is_half_the_footprint_at_the_full_size() {
        let svgf: Pipeline = "svgf".parse().unwrap();
        assert_eq!(svgf.reach(1920, 1080), 62 + 3, "5 passes at 1080 lines");
        assert_eq!(svgf.at_size(1920, 1080).reach(128, 128), 65, "settled counts stay");
        assert_eq!("ema0.1+atrous:2".parse::<Pipeline>().unwrap().reach(1920, 1080), 6);
        assert_eq!(Pipeline::RAW.reach(1920, 1080), 0);
        assert_eq!("taa0.1".parse::<Pipeline>().unwrap().reach(64, 64), 1);
    }

    #[test]
    fn names_round_trip_and_bad_ones_say_what_is_allowed() {
        for name in [
            "raw",
            "gauss",
            "atrous",
            "atrous:3",
            "mean",
            "ema0.1",
            "ema0.1+atrous",
            "ema0.1+atrous:5",
            "mean+atrous",
            "ema1+gauss",
            "taa0.1",
            "taa0.1+atrous",
            "taa0.25+gauss",
            "svgf",
            "svgf:4",
            "svgf:12",
            "svgf:fallback",
            "svgf:id",
            "svgf:releps",
            "svgf:5:fallback:id:releps",
            "svgf:4:fallback:releps",
        ] {
            let p: Pipeline = name.parse().unwrap();
            assert_eq!(p.to_string(), name);
        }
        assert_eq!("ema0.1+atrous".parse::<Pipeline>().unwrap().temporal, Some(Temporal::Ema(0.1)));
        assert_eq!(
            "taa0.1+atrous:2".parse::<Pipeline>().unwrap(),
            Pipeline { temporal: Some(Temporal::Taa(0.1)), spatial: Some(Spatial::Atrous(Some(2))) }
        );
        assert_eq!(
            "svgf:4".parse::<Pipeline>().unwrap(),
            Pipeline {
                temporal: Some(Temporal::Svgf(SvgfOptions { iterations: Some(4), ..SvgfOptions::default() })),
                spatial: None
            }
        );
        assert!("svgf".parse::<Pipeline>().unwrap().is_temporal());
        for bad in [
            "",
            "blur",
            "ema0",
            "ema1.5",
            "emax",
            "taa0",
            "taa2",
            "atrous+mean",
            "mean+ema0.1",
            "raw+atrous",
            "mean+atrous+gauss",
            "svgf+atrous",
            "svgf+gauss",
            "atrous+svgf",
            "atrous:0",
            "atrous:13",
            "atrous:x",
            "atrous:",
            "svgf:0",
            "gauss:2",
            "ema0.1:3",
            "mean+atrous:0",
            "svgf:",
            "svgf:id:5",
            "svgf:releps:id",
            "svgf:id:id",
            "svgf:5:5",
            "svgf:13:id",
            "svgf:fast",
            "svgf:5:fallback+atrous",
            "atrous:fallback",
        ] {
            let e = bad.parse::<Pipeline>().unwrap_err().to_string();
            assert!(e.contains(&format!("'{bad}'")) && e.contains(ALLOWED), "{bad}: {e}");
        }
        assert_eq!(
            "svgf:5:id".parse::<Pipeline>().unwrap().temporal,
            Some(Temporal::Svgf(SvgfOptions {
                iterations: Some(5),
                id_test: true,
                ..SvgfOptions::default()
            }))
        );
        assert_eq!(
            "svgf".parse::<Pipeline>().unwrap().temporal,
            Some(Temporal::Svgf(SvgfOptions::default()))
        );
        for (name, what) in SVGF_OPTIONS {
            assert!(ALLOWED.contains(&format!("':{name}' ({what})")), "{name}");
        }
    }
}

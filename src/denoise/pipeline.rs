//! What is done to the rendered frames before the image is measured, by name: an optional temporal
//! part (`mean`, `emaA`) then an optional spatial one (`gauss`, `atrous`), joined by `+`; `raw` is
//! neither. Names round-trip: `"ema0.1+atrous".parse::<Pipeline>()?.to_string() == "ema0.1+atrous"`.

use super::accumulate::{Accumulator, Temporal};
use super::atrous::{AtrousParams, atrous};
use super::gaussian::{GAUSS_SIGMA, gaussian};
use crate::image::Image;
use crate::render::GBuffer;
use std::fmt;
use std::str::FromStr;

/// The spatial filter applied to one (accumulated) frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Spatial {
    /// The normalized Gaussian of σ = `GAUSS_SIGMA` pixels over covered pixels (`gaussian`).
    Gauss,
    /// The edge-avoiding à-trous filter with `AtrousParams::default()` (`atrous`).
    Atrous,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pipeline {
    pub temporal: Option<Temporal>,
    pub spatial: Option<Spatial>,
}

/// What a pipeline name may be, for errors.
pub const ALLOWED: &str = "raw, gauss, atrous, mean, emaA (0 < A <= 1, e.g. ema0.1), or a temporal part \
                           (mean, emaA) then a spatial one (gauss, atrous) joined by '+', e.g. \
                           ema0.1+atrous, mean+gauss";

impl Pipeline {
    pub const RAW: Pipeline = Pipeline { temporal: None, spatial: None };

    /// True if more than one frame is combined.
    pub fn is_temporal(&self) -> bool {
        self.temporal.is_some()
    }

    /// A fresh accumulator for the temporal part, if there is one.
    pub fn accumulator(&self) -> Option<Accumulator> {
        self.temporal.map(Accumulator::new)
    }

    /// The spatial part applied to `img` (a frame, or the accumulated frames), guided by `gbuf`
    /// (only `atrous` reads depth and normals; every filter reads its coverage). No spatial part:
    /// `img` as it is.
    pub fn apply_spatial(&self, img: &Image, gbuf: &GBuffer) -> Image {
        match self.spatial {
            None => img.clone(),
            Some(Spatial::Gauss) => gaussian(img, &gbuf.coverage, GAUSS_SIGMA),
            Some(Spatial::Atrous) => atrous(img, gbuf, &AtrousParams::default()),
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

fn temporal(part: &str) -> Option<Result<Temporal, String>> {
    if part == "mean" {
        return Some(Ok(Temporal::Mean));
    }
    let a = part.strip_prefix("ema")?;
    Some(match a.parse::<f32>() {
        Ok(alpha) if alpha > 0.0 && alpha <= 1.0 => Ok(Temporal::Ema(alpha)),
        _ => Err(format!("the EMA weight in '{part}' must be a number in (0, 1], e.g. ema0.1")),
    })
}

fn spatial(part: &str) -> Option<Spatial> {
    match part {
        "gauss" => Some(Spatial::Gauss),
        "atrous" => Some(Spatial::Atrous),
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
                    return Ok(Pipeline { temporal: None, spatial: Some(sp) });
                }
                match temporal(one) {
                    Some(Ok(t)) => Ok(Pipeline { temporal: Some(t), spatial: None }),
                    Some(Err(e)) => Err(refuse(e)),
                    None => Err(refuse(format!("'{one}' is no filter"))),
                }
            }
            [t, sp] => {
                let t = match temporal(t) {
                    Some(Ok(t)) => t,
                    Some(Err(e)) => return Err(refuse(e)),
                    None => {
                        return Err(refuse(format!(
                            "'{t}' is no temporal part (mean, emaA); it comes first"
                        )));
                    }
                };
                let sp = spatial(sp)
                    .ok_or_else(|| refuse(format!("'{sp}' is no spatial filter (gauss, atrous)")))?;
                Ok(Pipeline { temporal: Some(t), spatial: Some(sp) })
            }
            _ => Err(refuse("at most one temporal and one spatial part".into())),
        }
    }
}

impl fmt::Display for Pipeline {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let t = self.temporal.map(|t| match t {
            Temporal::Mean => "mean".to_string(),
            Temporal::Ema(a) => format!("ema{a}"),
        });
        let s = self.spatial.map(|s| match s {
            Spatial::Gauss => "gauss".to_string(),
            Spatial::Atrous => "atrous".to_string(),
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
    fn names_round_trip_and_bad_ones_say_what_is_allowed() {
        for name in ["raw", "gauss", "atrous", "mean", "ema0.1", "ema0.1+atrous", "mean+atrous", "ema1+gauss"]
        {
            let p: Pipeline = name.parse().unwrap();
            assert_eq!(p.to_string(), name);
        }
        assert_eq!("ema0.1+atrous".parse::<Pipeline>().unwrap().temporal, Some(Temporal::Ema(0.1)));
        for bad in [
            "",
            "blur",
            "ema0",
            "ema1.5",
            "emax",
            "atrous+mean",
            "mean+ema0.1",
            "raw+atrous",
            "mean+atrous+gauss",
        ] {
            let e = bad.parse::<Pipeline>().unwrap_err().to_string();
            assert!(e.contains(&format!("'{bad}'")) && e.contains(ALLOWED), "{bad}: {e}");
        }
    }
}

//! The scene TOML format. Values are checked while deserializing, so toml's error names the line,
//! column and key of the bad value; unknown keys are refused for the same reason.
//!
//! ```toml
//! mesh = "cornell-box.obj"          # .obj or .obj.zst, relative to this file
//! resolution = [320, 240]           # default image size
//! ao_distance = 1.0                 # or "infinite"
//! [camera.perspective]              # or [camera.orthographic] with view_width instead of fov_y_deg
//! eye = [278.0, 273.0, -800.0]
//! target = [278.0, 273.0, 0.0]
//! up = [0.0, 1.0, 0.0]
//! fov_y_deg = 39.3
//! ```

use super::camera::{Camera, WorldCamera};
use crate::cli::MAX_SIDE;
use glam::DVec3;
use serde::{Deserialize, Deserializer, de};

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Defaults to the file stem.
    pub name: Option<String>,
    pub mesh: String,
    pub camera: CameraFile,
    pub resolution: Resolution,
    pub ao_distance: AoDistance,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum CameraFile {
    Perspective(PerspectiveFile),
    Orthographic(OrthographicFile),
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerspectiveFile {
    pub eye: [f64; 3],
    pub target: [f64; 3],
    pub up: [f64; 3],
    pub fov_y_deg: FovDeg,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrthographicFile {
    pub eye: [f64; 3],
    pub target: [f64; 3],
    pub up: [f64; 3],
    pub view_width: Positive,
}

impl CameraFile {
    /// The camera in world coordinates, in f64 as written (a scene far from the origin keeps its
    /// precision until `Scene::new` re-centres it on the eye).
    pub fn camera(&self) -> WorldCamera {
        match self {
            CameraFile::Perspective(p) => Camera::Perspective {
                eye: DVec3::from(p.eye),
                target: DVec3::from(p.target),
                up: DVec3::from(p.up),
                fov_y_deg: p.fov_y_deg.0,
            },
            CameraFile::Orthographic(o) => Camera::Orthographic {
                eye: DVec3::from(o.eye),
                target: DVec3::from(o.target),
                up: DVec3::from(o.up),
                view_width: o.view_width.0,
            },
        }
    }
}

/// Vertical field of view in degrees, strictly between 0 and 180.
#[derive(Debug, Clone, Copy)]
pub struct FovDeg(pub f32);

impl<'de> Deserialize<'de> for FovDeg {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = f64::deserialize(d)?;
        if v > 0.0 && v < 180.0 {
            Ok(FovDeg(v as f32))
        } else {
            Err(de::Error::custom(format!("fov_y_deg must be in (0, 180) degrees, got {v}")))
        }
    }
}

/// A positive finite length.
#[derive(Debug, Clone, Copy)]
pub struct Positive(pub f32);

impl<'de> Deserialize<'de> for Positive {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = f64::deserialize(d)?;
        if v > 0.0 && (v as f32).is_finite() {
            Ok(Positive(v as f32))
        } else {
            Err(de::Error::custom(format!("must be a positive finite number, got {v}")))
        }
    }
}

/// `[width, height]`, each in 1..=MAX_SIDE.
#[derive(Debug, Clone, Copy)]
pub struct Resolution(pub u32, pub u32);

impl<'de> Deserialize<'de> for Resolution {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let [w, h] = <[i64; 2]>::deserialize(d)?;
        let ok = |s: i64| (1..=MAX_SIDE as i64).contains(&s);
        if ok(w) && ok(h) {
            Ok(Resolution(w as u32, h as u32))
        } else {
            Err(de::Error::custom(format!(
                "resolution must be [width, height] with each side in 1..={MAX_SIDE}, got [{w}, {h}]"
            )))
        }
    }
}

/// The paper's AO distance d: a positive number, or the string "infinite".
#[derive(Debug, Clone, Copy)]
pub struct AoDistance(pub f32);

impl<'de> Deserialize<'de> for AoDistance {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl de::Visitor<'_> for V {
            type Value = AoDistance;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("ao_distance: a positive number or the string \"infinite\"")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<AoDistance, E> {
                if v > 0.0 && !v.is_nan() {
                    Ok(AoDistance(v as f32))
                } else {
                    Err(E::custom(format!("ao_distance must be a positive number or \"infinite\", got {v}")))
                }
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<AoDistance, E> {
                self.visit_f64(v as f64)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<AoDistance, E> {
                self.visit_f64(v as f64)
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<AoDistance, E> {
                if v == "infinite" {
                    Ok(AoDistance(f32::INFINITY))
                } else {
                    Err(E::custom(format!(
                        "ao_distance must be a positive number or \"infinite\", got \"{v}\""
                    )))
                }
            }
        }
        d.deserialize_any(V)
    }
}

/// Parses the scene TOML; the error is toml's (line, column, caret, key), without the file name.
pub fn parse(text: &str) -> Result<SceneFile, String> {
    toml::from_str(text).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "mesh = \"a.obj\"\nresolution = [4, 3]\nao_distance = \"infinite\"\n\
        [camera.orthographic]\neye = [0, 0, 1]\ntarget = [0, 0, 0]\nup = [0, 1, 0]\nview_width = 2\n";

    #[test]
    fn good_file_parses() {
        let f = parse(GOOD).unwrap();
        assert_eq!(f.ao_distance.0, f32::INFINITY);
        assert!(matches!(f.camera.camera(), Camera::Orthographic { view_width: 2.0, .. }));
    }

    #[test]
    fn errors_name_line_and_key() {
        let e = parse(&GOOD.replace("view_width", "view_wdth")).unwrap_err();
        assert!(e.contains("line 8") && e.contains("view_wdth"), "{e}");
        let e = parse(&GOOD.replace("\"infinite\"", "-1")).unwrap_err();
        assert!(e.contains("line 3") && e.contains("ao_distance"), "{e}");
        let e = parse(&GOOD.replace("[4, 3]", "[0, 3]")).unwrap_err();
        assert!(e.contains("line 2") && e.contains("resolution"), "{e}");
    }
}

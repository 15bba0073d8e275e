//! How a reference manifest records its camera: as JSON now, as a debug string before (whose text
//! `WorldCamera::canonical` now writes out explicitly).

use crate::scene::{Camera, WorldCamera};
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// A manifest's camera. New manifests hold it as JSON (`{"projection": "perspective", "eye": [..],
/// ..}`); those written before hold a Rust debug string (`Perspective { eye: DVec3(..), .. }`), and
/// stay readable. Both forms compare, name files and enter run keys through that debug string
/// (`legacy`), which the JSON reproduces exactly (its numbers round-trip), so the committed
/// references keep their file names and are reused, and a reference rebuilt in the new form
/// invalidates no finished job.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum CameraRecord {
    Json(CameraJson),
    Legacy(String),
}

/// A camera in world coordinates, as the scene file writes it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "projection", rename_all = "kebab-case", deny_unknown_fields)]
pub enum CameraJson {
    Perspective { eye: [f64; 3], target: [f64; 3], up: [f64; 3], fov_y_deg: f32 },
    Orthographic { eye: [f64; 3], target: [f64; 3], up: [f64; 3], view_width: f32 },
}

impl CameraRecord {
    pub fn of(camera: &WorldCamera) -> Self {
        let a = |v: DVec3| v.to_array();
        CameraRecord::Json(match *camera {
            Camera::Perspective { eye, target, up, fov_y_deg } => {
                CameraJson::Perspective { eye: a(eye), target: a(target), up: a(up), fov_y_deg }
            }
            Camera::Orthographic { eye, target, up, view_width } => {
                CameraJson::Orthographic { eye: a(eye), target: a(target), up: a(up), view_width }
            }
        })
    }

    /// The camera as manifests wrote it before it was JSON: the world camera's debug string.
    pub fn legacy(&self) -> String {
        let v = DVec3::from_array;
        match self {
            CameraRecord::Legacy(s) => s.clone(),
            CameraRecord::Json(CameraJson::Perspective { eye, target, up, fov_y_deg }) => {
                let c: WorldCamera = Camera::Perspective {
                    eye: v(*eye),
                    target: v(*target),
                    up: v(*up),
                    fov_y_deg: *fov_y_deg,
                };
                c.canonical()
            }
            CameraRecord::Json(CameraJson::Orthographic { eye, target, up, view_width }) => {
                let c: WorldCamera = Camera::Orthographic {
                    eye: v(*eye),
                    target: v(*target),
                    up: v(*up),
                    view_width: *view_width,
                };
                c.canonical()
            }
        }
    }
}

/// A camera and a scene's description of one (`Scene::camera_description`) are the same camera
/// when their debug strings are.
impl PartialEq<String> for CameraRecord {
    fn eq(&self, other: &String) -> bool {
        self.legacy() == *other
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_json_form_reproduces_the_debug_string_exactly() {
        let cams: [WorldCamera; 2] = [
            Camera::Perspective {
                eye: DVec3::new(278.0, 273.0, -800.0),
                target: DVec3::new(0.1, 1e-7, -3.9),
                up: DVec3::new(0.0, 1.0, 0.0),
                fov_y_deg: 39.3077,
            },
            Camera::Orthographic {
                eye: DVec3::new(1.0 / 3.0, 2e300, -0.0),
                target: DVec3::ZERO,
                up: DVec3::Z,
                view_width: 0.1,
            },
        ];
        for cam in cams {
            let r = CameraRecord::of(&cam);
            assert_eq!(r.legacy(), format!("{cam:?}"));
            let text = serde_json::to_string(&r).unwrap();
            assert!(text.starts_with("{\"projection\":"), "{text}");
            let back: CameraRecord = serde_json::from_str(&text).unwrap();
            assert_eq!((back.legacy(), &back), (format!("{cam:?}"), &r));
            let old: CameraRecord = serde_json::from_value(serde_json::json!(format!("{cam:?}"))).unwrap();
            assert_eq!(old, CameraRecord::Legacy(format!("{cam:?}")), "the older form still reads");
            assert!(old == format!("{cam:?}") && r == format!("{cam:?}"));
        }
    }
}

//! The scene TOML format. Values are checked while deserializing, so toml's error names the line,
//! column and key of the bad value; unknown keys are refused for the same reason.
//!
//! ```toml
//! mesh = "cornell-box.obj"          # .obj, .obj.zst, .gltf or .glb, relative to this file
//! resolution = [320, 240]           # default image size
//! ao_distance = 1.0                 # or "infinite" ("inf")
//! [camera.perspective]              # or [camera.orthographic] with view_width instead of fov_y_deg
//! eye = [278.0, 273.0, -800.0]
//! target = [278.0, 273.0, 0.0]
//! up = [0.0, 1.0, 0.0]
//! fov_y_deg = 39.3
//! ```
//!
//! A glTF mesh may leave out the camera: the file's first camera is used (`load` checks it has one).

use super::camera::{Camera, WorldCamera, up_problem};
use crate::spec::position::{describe, line_of};
use crate::spec::{RESOLUTION_RULE, resolution_ok};
use glam::DVec3;
use serde::{Deserialize, Deserializer, de};
use toml::Spanned;

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Defaults to the file stem.
    pub name: Option<String>,
    pub mesh: String,
    /// Optional only for a glTF mesh, whose first camera stands in.
    #[serde(default)]
    pub camera: CameraEntry,
    pub resolution: Resolution,
    pub ao_distance: AoDistance,
    /// Camera paths of the scene's own, `[cameras.NAME]` with `path` and `jitter` as a spec's
    /// (`scene::camera_path`; jitter default false): what `advise --pipeline` ranks besides the
    /// still camera and its default orbit, as the user's game moves through the scene.
    #[serde(default)]
    pub cameras: std::collections::BTreeMap<String, ScenePath>,
}

/// One of a scene file's `[cameras.NAME]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenePath {
    pub path: super::camera_path::CameraPath,
    #[serde(default)]
    pub jitter: bool,
}

/// Names a scene's camera may not take: the still camera's and advise's default orbit's.
const RESERVED_CAMERAS: [&str; 2] = ["static", "orbit"];

/// The `[camera.*]` table if the file has one (`parse` refuses a file without one unless its mesh
/// is glTF).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(transparent)]
pub struct CameraEntry(pub Option<CameraFile>);

impl CameraEntry {
    /// The file's camera; only for a file that gives one (any file whose mesh is not glTF).
    pub fn camera(&self) -> WorldCamera {
        self.0.as_ref().expect("the scene file gives a camera").camera()
    }
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
    pub eye: Spanned<Point>,
    pub target: Spanned<Point>,
    pub up: Spanned<Point>,
    pub fov_y_deg: FovDeg,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrthographicFile {
    pub eye: Spanned<Point>,
    pub target: Spanned<Point>,
    pub up: Spanned<Point>,
    pub view_width: Positive,
}

impl CameraFile {
    /// The camera in world coordinates, in f64 as written (a scene far from the origin keeps its
    /// precision until `Scene::new` re-centres it on the eye).
    pub fn camera(&self) -> WorldCamera {
        let [eye, target, up] = self.pose().map(|p| p.get_ref().0);
        match self {
            CameraFile::Perspective(p) => Camera::Perspective { eye, target, up, fov_y_deg: p.fov_y_deg.0 },
            CameraFile::Orthographic(o) => {
                Camera::Orthographic { eye, target, up, view_width: o.view_width.0 }
            }
        }
    }

    /// Eye, target and up, with where each is written.
    fn pose(&self) -> [&Spanned<Point>; 3] {
        match self {
            CameraFile::Perspective(p) => [&p.eye, &p.target, &p.up],
            CameraFile::Orthographic(o) => [&o.eye, &o.target, &o.up],
        }
    }

    /// The table's dotted key, for messages.
    fn key(&self) -> &'static str {
        match self {
            CameraFile::Perspective(_) => "camera.perspective",
            CameraFile::Orthographic(_) => "camera.orthographic",
        }
    }
}

/// What no single value's check can see: a camera whose target is its eye, or whose `up` is zero
/// or (nearly) parallel to its view (`camera::up_problem`, a relative tolerance), which would
/// render rolled by rounding error. Blamed on the line and key of `target` or `up`.
fn check_camera(text: &str, camera: &CameraFile) -> Result<(), String> {
    let [eye, target, up] = camera.pose();
    let at = |v: &Spanned<Point>, name: &str, what: String| {
        format!("line {}, key `{}.{name}`: {what}", line_of(text, v.span().start), camera.key())
    };
    let dir = target.get_ref().0 - eye.get_ref().0;
    if dir.length() == 0.0 {
        return Err(at(
            target,
            "target",
            "target is the eye; the camera looks from eye toward target".into(),
        ));
    }
    if let Some(p) = up_problem(dir, up.get_ref().0) {
        let [x, y, z] = up.get_ref().0.to_array();
        return Err(at(up, "up", format!("[{x}, {y}, {z}]: {p}")));
    }
    Ok(())
}

/// `[x, y, z]`: exactly three finite numbers within ±`MAX_COORDINATE` (as a mesh's vertices), in
/// f64 as written (toml would drop a fourth silently into an array).
#[derive(Debug, Clone, Copy)]
pub struct Point(pub DVec3);

impl<'de> Deserialize<'de> for Point {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<f64>::deserialize(d)?;
        match v[..] {
            [x, y, z] if v.iter().all(|c| c.abs() <= super::MAX_COORDINATE) => Ok(Point(DVec3::new(x, y, z))),
            _ => Err(de::Error::custom(format!(
                "must be [x, y, z], three finite numbers within ±{:e}, got {v:?}",
                super::MAX_COORDINATE
            ))),
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

/// `[width, height]`, within `spec::RESOLUTION_RULE`.
#[derive(Debug, Clone, Copy)]
pub struct Resolution(pub u32, pub u32);

impl<'de> Deserialize<'de> for Resolution {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec::<i64>::deserialize(d)?;
        let [w, h] = v[..] else {
            return Err(de::Error::custom(format!(
                "resolution must be [width, height], got {} numbers",
                v.len()
            )));
        };
        if w > 0 && h > 0 && resolution_ok(w as u64, h as u64) {
            Ok(Resolution(w as u32, h as u32))
        } else {
            Err(de::Error::custom(format!(
                "resolution must be [width, height], {RESOLUTION_RULE}; got [{w}, {h}]"
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
                f.write_str("ao_distance: a positive number or the string \"infinite\" (or \"inf\")")
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
                if crate::spec::is_infinite(v) {
                    Ok(AoDistance(f32::INFINITY))
                } else {
                    Err(E::custom(format!(
                        "ao_distance must be a positive number or \"infinite\" (or \"inf\"), got \"{v}\""
                    )))
                }
            }
        }
        d.deserialize_any(V)
    }
}

/// Parses the scene TOML; the error is one line, `line N, key K: what` (without the file name), as
/// a spec's are.
pub fn parse(text: &str) -> Result<SceneFile, String> {
    let file: SceneFile = toml::from_str(text).map_err(|e| describe(text, &e, &hint))?;
    match &file.camera.0 {
        Some(c) => check_camera(text, c)?,
        None if !is_gltf(&file.mesh) => return Err(format!("key `camera`: missing; {}", MISSING_CAMERA)),
        None => {}
    }
    for name in file.cameras.keys() {
        let ok = !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
        if !ok || RESERVED_CAMERAS.contains(&name.as_str()) {
            return Err(format!(
                "key `cameras.{name}`: a camera's name is letters, digits, '-' and '_' (it names files), \
                 and not {}",
                RESERVED_CAMERAS.join(" or ")
            ));
        }
    }
    Ok(file)
}

/// Whether a mesh path names a glTF 2.0 file (JSON `.gltf` or binary `.glb`), by its extension.
pub fn is_gltf(mesh: &str) -> bool {
    let lower = mesh.to_ascii_lowercase();
    lower.ends_with(".gltf") || lower.ends_with(".glb")
}

/// What a scene without a camera is told: write one (or, for glTF, give the file one).
pub const MISSING_CAMERA: &str = "add a camera: write `[camera.perspective]` (eye, target, up, fov_y_deg) or \
                                  `[camera.orthographic]` (eye, target, up, view_width); a glTF mesh's own \
                                  first camera is used when the scene file gives none";

/// The two ways to write the camera, said whenever the camera is missing or malformed.
const CAMERA: &str = "write `[camera.perspective]` (eye, target, up, fov_y_deg) or `[camera.orthographic]` \
                      (eye, target, up, view_width)";

/// What to write instead, for the mistakes serde describes in its own terms.
fn hint(key: &str, message: &str) -> Option<String> {
    if key == "camera" && message.starts_with("wanted exactly 1 element") {
        // An externally tagged enum: `[camera]` with the keys directly under it, or both kinds.
        return Some(format!("`[camera]` needs its projection in the header: {CAMERA}"));
    }
    let spec_keys = ["`scenes`", "`table`", "`convergence`", "`replicates`", "`reference`"];
    if spec_keys.iter().any(|k| message.starts_with(&format!("unknown field {k}"))) {
        return Some(
            "this is an experiment spec, not a scene file: `render`, `bench` and `advise` take a scene file \
             (like scenes/cornell-box.toml); run a spec with `hemilab run`"
                .into(),
        );
    }
    if !message.starts_with("missing field") {
        return None;
    }
    let field = key.rsplit('.').next().unwrap_or(key);
    Some(match field {
        "camera" => format!("add a camera: {CAMERA}"),
        "mesh" => "add `mesh = \"file.obj\"` (.obj, .obj.zst, .gltf or .glb, relative to this file)".into(),
        "resolution" => format!("add `resolution = [width, height]`, {RESOLUTION_RULE}"),
        "ao_distance" => "add `ao_distance = d`, a positive number or \"infinite\"".into(),
        "eye" | "target" | "up" => format!("add `{field} = [x, y, z]`"),
        "fov_y_deg" => "add `fov_y_deg = ..`, the vertical field of view in (0, 180) degrees".into(),
        "view_width" => "add `view_width = ..`, the width of the view in scene units".into(),
        _ => return None,
    })
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
    fn only_a_gltf_mesh_may_leave_out_the_camera() {
        let bare = GOOD.split("[camera").next().unwrap();
        let e = parse(bare).unwrap_err();
        assert!(e.starts_with("key `camera`: missing; add a camera: write `[camera.perspective]`"), "{e}");
        for mesh in ["a.glb", "a.GLTF"] {
            assert!(parse(&bare.replace("a.obj", mesh)).unwrap().camera.0.is_none(), "{mesh}");
        }
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

    #[test]
    fn camera_coordinates_are_bounded_as_a_mesh_is() {
        let e = parse(&GOOD.replace("eye = [0, 0, 1]", "eye = [0, 0, 1e30]")).unwrap_err();
        assert!(e.contains("line 5") && e.contains("within ±1e18"), "{e}");
    }

    #[test]
    fn up_along_the_view_is_refused_at_its_line() {
        let e = parse(&GOOD.replace("up = [0, 1, 0]", "up = [0, 0, -3]")).unwrap_err();
        assert!(e.starts_with("line 7, key `camera.orthographic.up`: [0, 0, -3]: up is parallel"), "{e}");
        let e = parse(&GOOD.replace("up = [0, 1, 0]", "up = [0, 1e-4, 1]")).unwrap_err();
        assert!(e.contains("line 7") && e.contains("from parallel"), "{e}");
        assert!(parse(&GOOD.replace("up = [0, 1, 0]", "up = [0, 1, 1]")).is_ok(), "45° is fine");
        let e = parse(&GOOD.replace("eye = [0, 0, 1]", "eye = [0, 0, 0]")).unwrap_err();
        assert!(e.starts_with("line 6, key `camera.orthographic.target`: target is the eye"), "{e}");
    }
}

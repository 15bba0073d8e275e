//! How the camera moves over a real-time job's frames, and each frame's sub-pixel jitter.
//!
//! A path starts at the scene's camera (frame 0 is it, exactly) and gives the `WorldCamera` of frame
//! f of F. The motions are named as in film: `orbit` circles the camera's target, `dolly` moves the
//! camera along its view, `pan` turns the view with the eye fixed (pure rotation: no parallax), and
//! `keyframes` interpolates written eyes and targets. In TOML, like a scene file's camera (the table
//! the path sits in is the spec's; `camera_path` here):
//!
//! ```toml
//! camera_path = "static"            # the scene's camera for every frame (the default)
//!
//! [camera_path.orbit]               # about the axis through the target along `up`
//! degrees = 30                      # total angle from the first frame to the last; + is
//!                                   # counter-clockwise seen from the side `up` points to
//! [camera_path.dolly]
//! distance = 0.5                    # eye and target move this far along the view, over the path
//!
//! [camera_path.pan]                 # the view direction turns about `up`, the eye stays
//! degrees = 10                      # + turns left (counter-clockwise seen from above)
//!
//! [[camera_path.keyframes]]         # one table per key, frames increasing; `up` and the field
//! frame = 0                         # of view (or view width) are the scene camera's; between
//! eye = [0.0, -3.0, 1.0]            # keys, eye and target move linearly; before the first key
//! target = [0.0, 0.0, 0.5]          # and after the last, the camera stays at that key
//! ```
//!
//! Over F frames the path's parameter is f / (F − 1) (0 for a single frame): frame F − 1 is the
//! path's end. A job measured at several frame counts should pass the group's longest F for every
//! job, so that frame f has one camera whatever the job.
//!
//! The jitter (`halton_jitter`) is the Halton (2, 3) sequence TAA engines use (Karis 2014, "High
//! Quality Temporal Supersampling"), in a cycle of `JITTER_CYCLE` = 16 frames; see there for why 16.

use super::{Camera, WorldCamera};
use crate::sampling::halton::{POW3, radical_inverse_3};
use glam::{DQuat, DVec3, Vec2};
use serde::Deserialize;

/// A camera's motion over a job's frames (module doc).
#[derive(Debug, Clone, PartialEq, Default, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum CameraPath {
    /// The scene's camera for every frame.
    #[default]
    Static,
    /// The eye circles the target about the axis through the target along `up`, by `degrees`
    /// over the path (counter-clockwise seen from where `up` points); target and up are kept.
    Orbit { degrees: f64 },
    /// Eye and target move by `distance` (scene units, negative: backwards) along the view
    /// direction over the path.
    Dolly { distance: f64 },
    /// The view direction (target − eye) turns about `up` by `degrees` over the path, the eye
    /// fixed (counter-clockwise seen from where `up` points, i.e. to the left).
    Pan { degrees: f64 },
    /// Eyes and targets at given frames, linearly interpolated between them.
    Keyframes(Vec<Keyframe>),
}

/// One key of a `keyframes` path: where the camera is at `frame` (from 0).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Keyframe {
    pub frame: u32,
    pub eye: [f64; 3],
    pub target: [f64; 3],
}

impl CameraPath {
    /// True if every frame is the scene's camera (then `Motion::identity` is the exact motion
    /// without jitter, and nothing needs reprojecting).
    pub fn is_static(&self) -> bool {
        *self == CameraPath::Static
    }

    /// The path's key in TOML (`orbit`, `keyframes`, …), for messages.
    pub fn key(&self) -> &'static str {
        match self {
            CameraPath::Static => "static",
            CameraPath::Orbit { .. } => "orbit",
            CameraPath::Dolly { .. } => "dolly",
            CameraPath::Pan { .. } => "pan",
            CameraPath::Keyframes(_) => "keyframes",
        }
    }

    /// The camera of frame `frame` (from 0) of `frames`, starting from the scene's camera `start`.
    /// Frame 0 of every path but `keyframes` is `start` bit for bit. Call `validate` first: on a
    /// path it refuses, the camera may be unusable.
    pub fn camera(&self, start: &WorldCamera, frame: u32, frames: u32) -> WorldCamera {
        let s = if frames <= 1 { 0.0 } else { frame as f64 / (frames - 1) as f64 };
        let (eye, target, up) = pose(start);
        let (eye, target) = match self {
            CameraPath::Static => return *start,
            _ if s == 0.0 && !matches!(self, CameraPath::Keyframes(_)) => return *start,
            CameraPath::Orbit { degrees } => (target + turn(up, degrees * s) * (eye - target), target),
            CameraPath::Dolly { distance } => {
                let step = (target - eye).normalize() * (distance * s);
                (eye + step, target + step)
            }
            CameraPath::Pan { degrees } => (eye, eye + turn(up, degrees * s) * (target - eye)),
            CameraPath::Keyframes(keys) => keyframe_pose(keys, frame),
        };
        with_pose(start, eye, target)
    }

    /// Checks the path's values (each message names its key, e.g. `orbit.degrees`,
    /// `keyframes[2].frame`) and then every frame's camera from `start` over `frames` frames
    /// (`Camera::problem`: eye and target apart, `up` not along the view, coordinates within
    /// `MAX_COORDINATE`), so that rendering any frame cannot fail.
    pub fn validate(&self, start: &WorldCamera, frames: u32) -> Result<(), String> {
        if frames == 0 {
            return Err("a camera path needs at least one frame".into());
        }
        let finite = |key: &str, v: f64| -> Result<(), String> {
            if v.is_finite() { Ok(()) } else { Err(format!("{key} must be a finite number, got {v}")) }
        };
        match self {
            CameraPath::Static => return Ok(()),
            CameraPath::Orbit { degrees } => finite("orbit.degrees", *degrees)?,
            CameraPath::Dolly { distance } => finite("dolly.distance", *distance)?,
            CameraPath::Pan { degrees } => finite("pan.degrees", *degrees)?,
            CameraPath::Keyframes(keys) => check_keys(keys, start, frames)?,
        }
        for f in 0..frames {
            let camera = self.camera(start, f, frames);
            if let Some(p) = problem(&camera) {
                return Err(format!("{}: the camera of frame {f} of {frames}: {p}", self.key()));
            }
        }
        Ok(())
    }
}

/// The keys' own checks: at least one, frames increasing and within the job, finite points, and
/// each key's camera usable with the scene camera's `up`.
fn check_keys(keys: &[Keyframe], start: &WorldCamera, frames: u32) -> Result<(), String> {
    if keys.is_empty() {
        return Err(
            "keyframes must list at least one key ([[camera_path.keyframes]] with frame, eye, target)".into(),
        );
    }
    for (i, k) in keys.iter().enumerate() {
        if i > 0 && k.frame <= keys[i - 1].frame {
            return Err(format!(
                "keyframes[{i}].frame must be greater than keyframes[{}].frame ({}), got {}: keys are in \
                 increasing frame order",
                i - 1,
                keys[i - 1].frame,
                k.frame
            ));
        }
        if k.frame >= frames {
            return Err(format!(
                "keyframes[{i}].frame is {} but the job's last frame is {} (frames 0..={}; a key past the \
                 end would only bend the path before it)",
                k.frame,
                frames - 1,
                frames - 1
            ));
        }
        for (name, p) in [("eye", k.eye), ("target", k.target)] {
            if !p.iter().all(|c| c.is_finite() && c.abs() <= super::MAX_COORDINATE) {
                return Err(format!(
                    "keyframes[{i}].{name} must be three finite numbers of magnitude at most {:e}, got {p:?}",
                    super::MAX_COORDINATE
                ));
            }
        }
        let camera = with_pose(start, DVec3::from_array(k.eye), DVec3::from_array(k.target));
        if let Some(p) = problem(&camera) {
            return Err(format!("keyframes[{i}]: {p}"));
        }
    }
    Ok(())
}

/// Why a world camera cannot make an image (`Camera::problem` of it relative to its own eye, and
/// the coordinate limit), if it cannot.
fn problem(camera: &WorldCamera) -> Option<String> {
    let (eye, target, _) = pose(camera);
    if !(eye.is_finite() && target.is_finite())
        || eye.abs().max_element() > super::MAX_COORDINATE
        || target.abs().max_element() > super::MAX_COORDINATE
    {
        return Some(format!(
            "eye and target must be finite and of magnitude at most {:e} (eye {eye}, target {target})",
            super::MAX_COORDINATE
        ));
    }
    camera.relative_to(eye).problem()
}

/// Eye and target of `frame` between the keys (held before the first and after the last; a key's
/// own frame gives its points exactly).
fn keyframe_pose(keys: &[Keyframe], frame: u32) -> (DVec3, DVec3) {
    let v = DVec3::from_array;
    let after = keys.partition_point(|k| k.frame <= frame);
    if after == 0 {
        return (v(keys[0].eye), v(keys[0].target));
    }
    let a = &keys[after - 1];
    if a.frame == frame || after == keys.len() {
        return (v(a.eye), v(a.target));
    }
    let b = &keys[after];
    let s = (frame - a.frame) as f64 / (b.frame - a.frame) as f64;
    (v(a.eye).lerp(v(b.eye), s), v(a.target).lerp(v(b.target), s))
}

/// The rotation by `degrees` about `up` (right-handed: counter-clockwise seen from where up points).
fn turn(up: DVec3, degrees: f64) -> DQuat {
    DQuat::from_axis_angle(up.normalize(), degrees.to_radians())
}

fn pose(c: &WorldCamera) -> (DVec3, DVec3, DVec3) {
    match *c {
        Camera::Perspective { eye, target, up, .. } | Camera::Orthographic { eye, target, up, .. } => {
            (eye, target, up)
        }
    }
}

/// `c` moved to `eye` and `target`, keeping its up and lens.
fn with_pose(c: &WorldCamera, eye: DVec3, target: DVec3) -> WorldCamera {
    match *c {
        Camera::Perspective { up, fov_y_deg, .. } => Camera::Perspective { eye, target, up, fov_y_deg },
        Camera::Orthographic { up, view_width, .. } => Camera::Orthographic { eye, target, up, view_width },
    }
}

/// Frames after which `halton_jitter` repeats: 16. Karis (2014) used 8 Halton (2, 3) points; 16 is
/// chosen here because the frames a temporal filter averages are about that many (the running
/// mean is measured at up to 16 frames and beyond, and an EMA with α = 0.1 still gives frames 16
/// back 19% of its weight), and because 16 points stratify the pixel evenly in x (base 2: one
/// point in each sixteenth) where 8 would repeat inside the window — a cycle shorter than the
/// history averages fewer distinct positions than the history holds.
pub const JITTER_CYCLE: u32 = 16;

/// Frame `frame`'s sub-pixel offset, in pixels, in [-0.5, 0.5)² (+x right, +y down): Halton point
/// (frame mod `JITTER_CYCLE`) + 1 in bases 2 and 3 (the radical inverses of `sampling::halton`,
/// unscrambled) minus 0.5. Index 0, the point (0, 0), is skipped, as engines do, so no frame
/// samples a pixel's corner and the cycle's mean is near the centre.
pub fn halton_jitter(frame: u32) -> Vec2 {
    let i = frame % JITTER_CYCLE + 1;
    let x = i.reverse_bits() as f64 / 4_294_967_296.0;
    let y = radical_inverse_3(i) as f64 / POW3 as f64;
    Vec2::new((x - 0.5) as f32, (y - 0.5) as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halton_jitter_is_the_known_sequence() {
        assert_eq!(halton_jitter(0), Vec2::new(0.0, (1.0f64 / 3.0 - 0.5) as f32));
        assert_eq!(halton_jitter(1), Vec2::new(-0.25, (2.0f64 / 3.0 - 0.5) as f32));
        assert_eq!(halton_jitter(2), Vec2::new(0.25, (1.0f64 / 9.0 - 0.5) as f32));
        assert_eq!(halton_jitter(JITTER_CYCLE), halton_jitter(0));
        let xs: std::collections::BTreeSet<u32> =
            (0..JITTER_CYCLE).map(|f| ((halton_jitter(f).x + 0.5) * 16.0) as u32).collect();
        assert_eq!(xs.len(), 16, "one point in each sixteenth of the pixel in x");
        assert!((0..64).all(|f| halton_jitter(f).abs().max_element() <= 0.5 && halton_jitter(f).x < 0.5));
    }
}

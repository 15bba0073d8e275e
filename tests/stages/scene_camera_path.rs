//! Camera paths: what each gives every frame, as closed forms (a static path is the
//! scene camera, an orbit keeps its distance to the target, keys are hit exactly), and the errors
//! for input a path refuses, each naming its key.

use glam::DVec3;
use hemilab::scene::camera_path::{CameraPath, Keyframe};
use hemilab::scene::{Camera, WorldCamera};
use serde::Deserialize;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Holder {
    camera_path: CameraPath,
}

fn parse(text: &str) -> Result<CameraPath, String> {
    toml::from_str::<Holder>(text).map(|h| h.camera_path).map_err(|e| e.to_string())
}

fn start() -> WorldCamera {
    Camera::Perspective {
        eye: DVec3::new(1000.3, -2.0, 1.2),
        target: DVec3::new(1000.0, 0.0, 0.25),
        up: DVec3::Z,
        fov_y_deg: 50.0,
    }
}

fn pose(c: &WorldCamera) -> (DVec3, DVec3) {
    match *c {
        Camera::Perspective { eye, target, .. } | Camera::Orthographic { eye, target, .. } => (eye, target),
    }
}

#[test]
fn every_path_parses_from_toml() {
    assert_eq!(parse("camera_path = \"static\"").unwrap(), CameraPath::Static);
    assert_eq!(parse("[camera_path.orbit]\ndegrees = 30").unwrap(), CameraPath::Orbit { degrees: 30.0 });
    assert_eq!(parse("[camera_path.dolly]\ndistance = -0.5").unwrap(), CameraPath::Dolly { distance: -0.5 });
    assert_eq!(parse("[camera_path.pan]\ndegrees = 10.5").unwrap(), CameraPath::Pan { degrees: 10.5 });
    let keys = "[[camera_path.keyframes]]\nframe = 0\neye = [0, -3, 1]\ntarget = [0, 0, 0.5]\n\
                [[camera_path.keyframes]]\nframe = 7\neye = [1, -3, 1]\ntarget = [1, 0, 0.5]\n";
    assert_eq!(
        parse(keys).unwrap(),
        CameraPath::Keyframes(vec![
            Keyframe { frame: 0, eye: [0.0, -3.0, 1.0], target: [0.0, 0.0, 0.5] },
            Keyframe { frame: 7, eye: [1.0, -3.0, 1.0], target: [1.0, 0.0, 0.5] },
        ])
    );
}

#[test]
fn unknown_keys_and_kinds_are_refused_by_name() {
    let e = parse("[camera_path.orbit]\ndegrees = 30\nspeed = 2").unwrap_err();
    assert!(e.contains("line 3") && e.contains("speed") && e.contains("degrees"), "{e}");
    let e = parse("[camera_path.spiral]\ndegrees = 30").unwrap_err();
    assert!(e.contains("spiral") && e.contains("orbit") && e.contains("keyframes"), "{e}");
    let e = parse("[camera_path.dolly]").unwrap_err();
    assert!(e.contains("missing field `distance`"), "{e}");
    let e =
        parse("[[camera_path.keyframes]]\nframe = 0\neye = [0, 0, 1]\ntarget = [0, 1, 1]\nup = [0, 0, 1]")
            .unwrap_err();
    assert!(e.contains("unknown field `up`") && e.contains("`target`"), "{e}");
    let e = parse("[camera_path.pan]\ndegrees = \"ten\"").unwrap_err();
    assert!(e.contains("degrees") || e.contains("invalid type"), "{e}");
}

#[test]
fn static_path_is_the_scene_camera_for_every_frame() {
    let path = CameraPath::default();
    assert!(path.is_static());
    path.validate(&start(), 16).unwrap();
    for f in 0..16 {
        assert_eq!(path.camera(&start(), f, 16), start());
    }
}

#[test]
fn frame_zero_of_a_moving_path_is_the_scene_camera() {
    for path in [
        CameraPath::Orbit { degrees: 40.0 },
        CameraPath::Dolly { distance: 0.3 },
        CameraPath::Pan { degrees: -12.0 },
    ] {
        path.validate(&start(), 9).unwrap();
        assert_eq!(path.camera(&start(), 0, 9), start(), "{path:?}");
        assert_eq!(path.camera(&start(), 0, 1), start(), "{path:?}: one frame");
        assert_ne!(path.camera(&start(), 8, 9), start(), "{path:?}");
    }
}

#[test]
fn orbit_keeps_distance_to_target_and_height_and_turns_the_stated_angle() {
    let (eye, target) = pose(&start());
    let path = CameraPath::Orbit { degrees: 90.0 };
    let frames = 7;
    for f in 0..frames {
        let (e, t) = pose(&path.camera(&start(), f, frames));
        assert_eq!(t, target);
        assert!(((e - t).length() - (eye - target).length()).abs() < 1e-9);
        assert!((e.z - eye.z).abs() < 1e-9, "about the up axis: the height stays");
        // The angle about up between the start's and this frame's horizontal offsets.
        let (a, b) = ((eye - target).truncate(), (e - t).truncate());
        let angle = a.perp_dot(b).atan2(a.dot(b)).to_degrees();
        assert!((angle - 90.0 * f as f64 / (frames - 1) as f64).abs() < 1e-9, "frame {f}: {angle}");
    }
}

#[test]
fn dolly_moves_eye_and_target_along_the_view() {
    let (eye, target) = pose(&start());
    let dir = (target - eye).normalize();
    let (e, t) = pose(&CameraPath::Dolly { distance: 2.0 }.camera(&start(), 4, 5));
    assert!((e - (eye + 2.0 * dir)).length() < 1e-9 && (t - (target + 2.0 * dir)).length() < 1e-9);
    let (e, t) = pose(&CameraPath::Dolly { distance: 2.0 }.camera(&start(), 2, 5));
    assert!((e - (eye + dir)).length() < 1e-9 && (t - e - (target - eye)).length() < 1e-9);
}

#[test]
fn pan_keeps_the_eye_and_turns_the_view_left() {
    let (eye, target) = pose(&start());
    let (e, t) = pose(&CameraPath::Pan { degrees: 30.0 }.camera(&start(), 1, 2));
    assert_eq!(e, eye);
    assert!(((t - e).length() - (target - eye).length()).abs() < 1e-9);
    assert!(((t - e).z - (target - eye).z).abs() < 1e-9);
    let (a, b) = ((target - eye).truncate(), (t - e).truncate());
    assert!((a.perp_dot(b).atan2(a.dot(b)).to_degrees() - 30.0).abs() < 1e-9, "counter-clockwise about +z");
}

#[test]
fn keyframes_hit_their_keys_exactly_and_interpolate_linearly() {
    let keys = vec![
        Keyframe { frame: 2, eye: [1000.1, -3.0, 1.0], target: [1000.0, 0.0, 0.5] },
        Keyframe { frame: 5, eye: [1001.3, -2.7, 1.3], target: [1000.2, 0.1, 0.4] },
        Keyframe { frame: 11, eye: [1000.7, -2.0, 2.0], target: [999.9, 0.0, 0.0] },
    ];
    let path = CameraPath::Keyframes(keys.clone());
    path.validate(&start(), 12).unwrap();
    for k in &keys {
        let c = path.camera(&start(), k.frame, 12);
        assert_eq!(pose(&c), (DVec3::from_array(k.eye), DVec3::from_array(k.target)));
        let Camera::Perspective { up, fov_y_deg, .. } = c else { panic!() };
        assert_eq!((up, fov_y_deg), (DVec3::Z, 50.0), "up and fov are the scene camera's");
    }
    assert_eq!(pose(&path.camera(&start(), 0, 12)), pose(&path.camera(&start(), 2, 12)), "held before");
    let (e, t) = pose(&path.camera(&start(), 7, 12));
    let (a, b) = (DVec3::from_array(keys[1].eye), DVec3::from_array(keys[2].eye));
    assert!((e - (a + (b - a) / 3.0)).length() < 1e-9, "a third of the way from frame 5 to 11");
    let (a, b) = (DVec3::from_array(keys[1].target), DVec3::from_array(keys[2].target));
    assert!((t - (a + (b - a) / 3.0)).length() < 1e-9);
}

#[test]
fn invalid_paths_are_refused_naming_the_key() {
    let s = start();
    let err = |p: CameraPath, frames: u32| p.validate(&s, frames).unwrap_err();
    assert!(err(CameraPath::Orbit { degrees: f64::NAN }, 4).contains("orbit.degrees must be a finite"));
    assert!(err(CameraPath::Dolly { distance: f64::INFINITY }, 4).contains("dolly.distance"));
    assert!(err(CameraPath::Pan { degrees: f64::NEG_INFINITY }, 4).contains("pan.degrees"));
    assert!(err(CameraPath::Keyframes(vec![]), 4).contains("at least one key"));
    let k = |frame, eye: [f64; 3], target: [f64; 3]| Keyframe { frame, eye, target };
    let e = err(
        CameraPath::Keyframes(vec![k(0, [0., -3., 1.], [0., 0., 0.]), k(0, [1., -3., 1.], [0., 0., 0.])]),
        4,
    );
    assert!(e.contains("keyframes[1].frame must be greater than keyframes[0].frame"), "{e}");
    let e = err(CameraPath::Keyframes(vec![k(4, [0., -3., 1.], [0., 0., 0.])]), 4);
    assert!(e.contains("keyframes[0].frame is 4 but the job's last frame is 3"), "{e}");
    let e = err(CameraPath::Keyframes(vec![k(0, [0., -3., f64::NAN], [0., 0., 0.])]), 4);
    assert!(e.contains("keyframes[0].eye must be three finite numbers"), "{e}");
    let e = err(CameraPath::Keyframes(vec![k(0, [0., 0., 1.], [0., 0., 1.])]), 4);
    assert!(e.contains("keyframes[0]: eye and target must differ"), "{e}");
    let e = err(CameraPath::Keyframes(vec![k(0, [0., 0., 3.], [0., 0., 0.])]), 4);
    assert!(e.contains("keyframes[0]: up is parallel"), "{e}: looking straight down an up of +z");
    // Keys each fine, but a frame between them looks along up (eye passes over the target).
    let e = err(
        CameraPath::Keyframes(vec![k(0, [-1., 0., 3.], [0., 0., 0.]), k(2, [1., 0., 3.], [0., 0., 0.])]),
        3,
    );
    assert!(e.contains("keyframes: the camera of frame 1 of 3: up is parallel"), "{e}");
    // A dolly through the target is fine (both move); an orbit can't break a valid camera.
    CameraPath::Dolly { distance: 100.0 }.validate(&s, 4).unwrap();
    CameraPath::Orbit { degrees: 720.0 }.validate(&s, 4).unwrap();
    assert!(CameraPath::Static.validate(&s, 0).unwrap_err().contains("at least one frame"));
}

//! Validation scenes whose AO is known exactly: an open floor (nothing occludes: AO is 1 everywhere),
//! a closed box (every ray is blocked), and a floor under a floating rectangle (Lambert's form factor).
//! Each takes a uniform `scale` and an `offset` so the tests can move them far from unit size and origin.

use super::{Camera, Scene, WorldCamera};
use glam::DVec3;

/// Where to put a validation scene: p → p * scale + offset, in f64 (world coordinates; `Scene::new`
/// re-centres on the camera).
#[derive(Debug, Clone, Copy)]
pub struct Placement {
    pub scale: f64,
    pub offset: DVec3,
}

impl Placement {
    pub const UNIT: Placement = Placement { scale: 1.0, offset: DVec3::ZERO };

    pub fn p(&self, v: DVec3) -> DVec3 {
        v * self.scale + self.offset
    }

    pub fn quad(&self, a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> [[DVec3; 3]; 2] {
        let (a, b, c, d) = (self.p(a), self.p(b), self.p(c), self.p(d));
        [[a, b, c], [a, c, d]]
    }

    fn perspective(&self, eye: DVec3, target: DVec3, up: DVec3, fov_y_deg: f32) -> WorldCamera {
        Camera::Perspective { eye: self.p(eye), target: self.p(target), up, fov_y_deg }
    }
}

/// A 2 x 2 floor at z = 0 seen obliquely from above (some pixels are background).
pub fn open_floor(at: Placement, resolution: (u32, u32)) -> Scene {
    let tris = at
        .quad(
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
        )
        .to_vec();
    let cam = at.perspective(DVec3::new(0.3, -2.0, 1.2), DVec3::new(0.0, 0.0, 0.0), DVec3::Z, 60.0);
    Scene::from_triangles("open-floor", cam, resolution, f32::INFINITY, tris).expect("valid scene")
}

/// The unit cube seen from inside (eye at its centre): every pixel covered, every AO ray blocked.
pub fn closed_box(at: Placement, resolution: (u32, u32)) -> Scene {
    let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    let faces = [
        [v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.)],
        [v(0., 0., 1.), v(0., 1., 1.), v(1., 1., 1.), v(1., 0., 1.)],
        [v(0., 0., 0.), v(0., 0., 1.), v(1., 0., 1.), v(1., 0., 0.)],
        [v(0., 1., 0.), v(1., 1., 0.), v(1., 1., 1.), v(0., 1., 1.)],
        [v(0., 0., 0.), v(0., 1., 0.), v(0., 1., 1.), v(0., 0., 1.)],
        [v(1., 0., 0.), v(1., 0., 1.), v(1., 1., 1.), v(1., 1., 0.)],
    ];
    let tris = faces.iter().flat_map(|f| at.quad(f[0], f[1], f[2], f[3])).collect();
    let cam = at.perspective(v(0.5, 0.5, 0.5), v(0.2, 0.9, 0.1), DVec3::Z, 120.0);
    Scene::from_triangles("closed-box", cam, resolution, f32::INFINITY, tris).expect("valid scene")
}

/// The occluder of `floating_rectangle`: corners of an axis-aligned rectangle at height `RECT_Z`.
pub const RECT_MIN: [f64; 2] = [-0.4, -0.3];
pub const RECT_MAX: [f64; 2] = [0.6, 0.5];
pub const RECT_Z: f64 = 0.8;
/// Half-size of the floor and of the orthographic view of `floating_rectangle`.
pub const FLOOR_HALF: f64 = 4.0;
pub const VIEW_HALF: f64 = 2.0;

/// A large floor at z = 0 under a floating rectangle, seen top-down by an orthographic camera
/// covering [-VIEW_HALF, VIEW_HALF]^2; d infinite, so the whole rectangle counts from every floor point.
pub fn floating_rectangle(resolution: (u32, u32)) -> Scene {
    let at = Placement::UNIT;
    let f = FLOOR_HALF;
    let (lo, hi, z) = (RECT_MIN, RECT_MAX, RECT_Z);
    let mut tris = at
        .quad(DVec3::new(-f, -f, 0.0), DVec3::new(f, -f, 0.0), DVec3::new(f, f, 0.0), DVec3::new(-f, f, 0.0))
        .to_vec();
    tris.extend(at.quad(
        DVec3::new(lo[0], lo[1], z),
        DVec3::new(hi[0], lo[1], z),
        DVec3::new(hi[0], hi[1], z),
        DVec3::new(lo[0], hi[1], z),
    ));
    let cam = Camera::Orthographic {
        eye: DVec3::new(0.0, 0.0, 10.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
        view_width: 2.0 * VIEW_HALF as f32,
    };
    Scene::from_triangles("floating-rectangle", cam, resolution, f32::INFINITY, tris).expect("valid scene")
}

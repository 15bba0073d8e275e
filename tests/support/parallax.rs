//! A scene whose visibility and AO are known in closed form, for the reprojection tests:
//! a large floor (z = 0) under a floating rectangle (z = `RECT_Z`), seen obliquely from above, so
//! that a moving camera uncovers floor the rectangle hid. `Caster` traces its primary rays
//! analytically in f64 (a plane test each, not the BVH) and projects points into a camera with the
//! renderer's conventions written out again here, so the tests check the library against an
//! independent computation.

use super::lambert::form_factor;
use glam::{DVec3, Vec2};
use hemilab::scene::{Camera, Scene, WorldCamera};

pub const RECT_MIN: [f64; 2] = [-0.4, -0.3];
pub const RECT_MAX: [f64; 2] = [0.6, 0.5];
pub const RECT_Z: f64 = 0.8;
/// Half-size of the floor: every ray of the tests' cameras that points down meets it.
pub const FLOOR_HALF: f64 = 60.0;
/// Where the scene sits in the world (far from the origin, as a real scene may).
pub const OFFSET: DVec3 = DVec3::new(300.0, -200.0, 0.0);

/// The scene's camera: 20° above the floor's horizon at the top of the image, the rectangle in view.
pub fn camera() -> WorldCamera {
    Camera::Perspective {
        eye: OFFSET + DVec3::new(0.3, -2.5, 2.0),
        target: OFFSET + DVec3::new(0.1, 0.1, 0.3),
        up: DVec3::Z,
        fov_y_deg: 50.0,
    }
}

pub fn rectangle() -> [DVec3; 4] {
    let (lo, hi, z) = (RECT_MIN, RECT_MAX, RECT_Z);
    [
        OFFSET + DVec3::new(lo[0], lo[1], z),
        OFFSET + DVec3::new(hi[0], lo[1], z),
        OFFSET + DVec3::new(hi[0], hi[1], z),
        OFFSET + DVec3::new(lo[0], hi[1], z),
    ]
}

pub fn scene(resolution: (u32, u32)) -> Scene {
    let f = FLOOR_HALF;
    let quad = |q: [DVec3; 4]| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]];
    let floor =
        [DVec3::new(-f, -f, 0.0), DVec3::new(f, -f, 0.0), DVec3::new(f, f, 0.0), DVec3::new(-f, f, 0.0)]
            .map(|p| OFFSET + p);
    let mut tris = quad(floor).to_vec();
    tris.extend(quad(rectangle()));
    Scene::from_triangles("parallax", camera(), resolution, f32::INFINITY, tris).expect("valid scene")
}

/// What a primary ray hit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Surface {
    Floor,
    Rect,
    Background,
}

/// One pixel's sample: the surface, the world point, and whether it lies within `EDGE` of the
/// rectangle's outline (where f32 rounding may decide the surface either way).
#[derive(Debug, Clone, Copy)]
pub struct Sample {
    pub surface: Surface,
    pub point: DVec3,
    pub near_edge: bool,
}

/// World distance from the rectangle's outline below which a hit is ambiguous.
pub const EDGE: f64 = 1e-4;

/// Signed distance-like margin of (x, y) inside the rectangle: > 0 inside, < 0 outside.
fn inside(x: f64, y: f64) -> f64 {
    let (lo, hi) = (RECT_MIN, RECT_MAX);
    let (x, y) = (x - OFFSET.x, y - OFFSET.y);
    (x - lo[0]).min(hi[0] - x).min(y - lo[1]).min(hi[1] - y)
}

/// A camera's rays at one image size and jitter, in f64.
pub struct Caster {
    eye: DVec3,
    forward: DVec3,
    right: DVec3,
    true_up: DVec3,
    tan_half: f64,
    width: u32,
    height: u32,
    jitter: Vec2,
}

impl Caster {
    pub fn new(camera: &WorldCamera, (width, height): (u32, u32), jitter: Vec2) -> Self {
        let Camera::Perspective { eye, target, up, fov_y_deg } = *camera else { panic!("perspective only") };
        let forward = (target - eye).normalize();
        let right = forward.cross(up).normalize();
        let true_up = right.cross(forward);
        let tan_half = (0.5 * (fov_y_deg as f64).to_radians()).tan();
        Caster { eye, forward, right, true_up, tan_half, width, height, jitter }
    }

    pub fn eye(&self) -> DVec3 {
        self.eye
    }

    fn aspect(&self) -> f64 {
        self.width as f64 / self.height as f64
    }

    /// The unit direction of pixel (x, y)'s ray: through its centre plus the jitter.
    pub fn dir(&self, x: u32, y: u32) -> DVec3 {
        let sx = 2.0 * (x as f64 + 0.5 + self.jitter.x as f64) / self.width as f64 - 1.0;
        let sy = 1.0 - 2.0 * (y as f64 + 0.5 + self.jitter.y as f64) / self.height as f64;
        (self.forward
            + self.right * (sx * self.tan_half * self.aspect())
            + self.true_up * (sy * self.tan_half))
            .normalize()
    }

    /// What pixel (x, y)'s ray hits first.
    pub fn sample(&self, x: u32, y: u32) -> Sample {
        let d = self.dir(x, y);
        let t_rect = (OFFSET.z + RECT_Z - self.eye.z) / d.z;
        if t_rect > 0.0 {
            let p = self.eye + d * t_rect;
            let m = inside(p.x, p.y);
            if m > -EDGE {
                return Sample { surface: Surface::Rect, point: p, near_edge: m < EDGE };
            }
        }
        let t_floor = (OFFSET.z - self.eye.z) / d.z;
        if t_floor > 0.0 {
            let p = self.eye + d * t_floor;
            if (p.x - OFFSET.x).abs() < FLOOR_HALF && (p.y - OFFSET.y).abs() < FLOOR_HALF {
                let m = if t_rect > 0.0 {
                    inside((self.eye + d * t_rect).x, (self.eye + d * t_rect).y)
                } else {
                    -1.0
                };
                return Sample { surface: Surface::Floor, point: p, near_edge: m.abs() < EDGE };
            }
        }
        Sample { surface: Surface::Background, point: DVec3::ZERO, near_edge: false }
    }

    /// The fractional pixel whose ray passes through `p` (the inverse of `dir`), or None behind
    /// the eye.
    pub fn pixel_of(&self, p: DVec3) -> Option<(f64, f64)> {
        let d = p - self.eye;
        let z = d.dot(self.forward);
        if z <= 0.0 {
            return None;
        }
        let sx = d.dot(self.right) / (z * self.tan_half * self.aspect());
        let sy = d.dot(self.true_up) / (z * self.tan_half);
        let px = 0.5 * (sx + 1.0) * self.width as f64 - 0.5 - self.jitter.x as f64;
        let py = 0.5 * (1.0 - sy) * self.height as f64 - 0.5 - self.jitter.y as f64;
        Some((px, py))
    }

    /// Whether the rectangle hides floor point `p` from the eye, and whether the sight line passes
    /// within `EDGE` of its outline.
    pub fn hidden(&self, p: DVec3) -> (bool, bool) {
        let s = (OFFSET.z + RECT_Z - self.eye.z) / (p.z - self.eye.z);
        if !(0.0..1.0).contains(&s) {
            return (false, false);
        }
        let q = self.eye + (p - self.eye) * s;
        let m = inside(q.x, q.y);
        (m > 0.0, m.abs() < EDGE)
    }
}

/// The exact AO (d infinite) of a sample: 1 on the rectangle's top (nothing above it), 1 − the
/// rectangle's form factor on the floor (Lambert).
pub fn exact_ao(s: &Sample) -> f64 {
    match s.surface {
        Surface::Rect => 1.0,
        Surface::Floor => 1.0 - form_factor(s.point, DVec3::Z, &rectangle()),
        Surface::Background => 1.0,
    }
}

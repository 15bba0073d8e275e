//! Pinhole and orthographic cameras: one primary ray per pixel, through the pixel centre (moved by
//! a per-frame sub-pixel jitter for temporal anti-aliasing, `Camera::raster_jittered`).
//!
//! A scene file places its camera in world coordinates (`WorldCamera`, f64, as written); the renderer
//! works relative to the eye (`Camera`, f32, eye at the origin), so the scene's distance from the
//! world origin costs no precision (see `Scene::new`).

use glam::{DVec3, Vec2, Vec3};

/// The least sine of the angle between `up` and the view direction (target − eye) a camera may have:
/// 1e-3, about 0.057°. Closer to parallel, the image's roll is decided by rounding error rather
/// than by the scene file (in f32, the renderer's precision, the cross product that fixes "right" is
/// then mostly rounding), so such a camera is refused rather than rendered rolled.
pub const MIN_UP_SINE: f64 = 1e-3;

/// Why `up` cannot orient a camera looking along `dir`, if it cannot: zero, or within
/// `MIN_UP_SINE` of parallel to `dir` (a relative test: |dir × up| against |dir| |up|).
pub fn up_problem(dir: DVec3, up: DVec3) -> Option<String> {
    let (d, u) = (dir.length(), up.length());
    if u == 0.0 || !u.is_finite() {
        return Some("up must not be zero".into());
    }
    let sine = dir.cross(up).length() / (d * u);
    if sine.is_finite() && sine >= MIN_UP_SINE {
        return None;
    }
    let degrees = sine.clamp(0.0, 1.0).asin().to_degrees();
    Some(format!(
        "up is {} to the view direction (target - eye); up must be at least {:.3}° from it (|up × \
         (target - eye)| ≥ {MIN_UP_SINE:e} |up| |target - eye|), so that it decides which way is up in \
         the image",
        if sine == 0.0 { "parallel".to_string() } else { format!("{degrees:.2e}° from parallel") },
        MIN_UP_SINE.asin().to_degrees()
    ))
}

/// `V`: `Vec3` for the renderer's camera-relative camera, `DVec3` for the world placement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Camera<V = Vec3> {
    Perspective { eye: V, target: V, up: V, fov_y_deg: f32 },
    Orthographic { eye: V, target: V, up: V, view_width: f32 },
}

/// A camera as a scene file places it (world coordinates, f64).
pub type WorldCamera = Camera<DVec3>;

impl<V: Copy> Camera<V> {
    pub fn eye(&self) -> V {
        match *self {
            Camera::Perspective { eye, .. } | Camera::Orthographic { eye, .. } => eye,
        }
    }
}

impl WorldCamera {
    /// The camera as text, for the stored identities that name it (reference manifests and file
    /// names, scene hashes, run keys): written out here, number by number (Rust's shortest
    /// round-trip form of each), so that the text cannot change under a dependency upgrade. It is
    /// the text glam's and the derived `Debug` gave when it was first stored (a test checks), so
    /// every committed reference keeps its name.
    pub fn canonical(&self) -> String {
        let v = |p: DVec3| format!("DVec3({:?}, {:?}, {:?})", p.x, p.y, p.z);
        match *self {
            Camera::Perspective { eye, target, up, fov_y_deg } => format!(
                "Perspective {{ eye: {}, target: {}, up: {}, fov_y_deg: {fov_y_deg:?} }}",
                v(eye),
                v(target),
                v(up)
            ),
            Camera::Orthographic { eye, target, up, view_width } => format!(
                "Orthographic {{ eye: {}, target: {}, up: {}, view_width: {view_width:?} }}",
                v(eye),
                v(target),
                v(up)
            ),
        }
    }

    /// The same camera relative to `origin` (its positions minus `origin`, subtracted in f64 and then
    /// rounded once to f32).
    pub fn relative_to(&self, origin: DVec3) -> Camera {
        let rel = |p: DVec3| (p - origin).as_vec3();
        match *self {
            Camera::Perspective { eye, target, up, fov_y_deg } => {
                Camera::Perspective { eye: rel(eye), target: rel(target), up: up.as_vec3(), fov_y_deg }
            }
            Camera::Orthographic { eye, target, up, view_width } => {
                Camera::Orthographic { eye: rel(eye), target: rel(target), up: up.as_vec3(), view_width }
            }
        }
    }
}

/// A primary ray; `dir` is a unit vector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrimaryRay {
    pub origin: Vec3,
    pub dir: Vec3,
}

impl Camera {
    fn pose(&self) -> (Vec3, Vec3, Vec3) {
        match *self {
            Camera::Perspective { eye, target, up, .. } | Camera::Orthographic { eye, target, up, .. } => {
                (eye, target, up)
            }
        }
    }

    /// Why the camera cannot make an image, if it cannot (checked once at load, so rays never are NaN).
    pub fn problem(&self) -> Option<String> {
        let (eye, target, up) = self.pose();
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return Some("eye, target and up must be finite".into());
        }
        let forward = (target - eye).normalize_or_zero();
        if forward == Vec3::ZERO {
            return Some("eye and target must differ".into());
        }
        if let Some(p) = up_problem(forward.as_dvec3(), up.as_dvec3()) {
            return Some(p);
        }
        match *self {
            Camera::Perspective { fov_y_deg, .. } if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) => {
                Some(format!("fov_y_deg must be in (0, 180) degrees, got {fov_y_deg}"))
            }
            Camera::Orthographic { view_width, .. } if !(view_width > 0.0 && view_width.is_finite()) => {
                Some(format!("view_width must be a positive finite number, got {view_width}"))
            }
            _ => None,
        }
    }

    /// The ray through the centre of pixel (x, y) of a `width` x `height` image; y = 0 is the top row.
    pub fn ray(&self, x: u32, y: u32, width: u32, height: u32) -> PrimaryRay {
        self.raster(width, height).ray(x, y)
    }

    /// What every pixel's ray of a `width` x `height` image shares (the basis, tan(fov/2)), worked
    /// out once: `Raster::ray` then gives `ray`'s bits without redoing it per pixel.
    pub fn raster(&self, width: u32, height: u32) -> Raster {
        self.raster_jittered(width, height, Vec2::ZERO)
    }

    /// `raster` with every pixel's ray through (x + 0.5 + jitter.x, y + 0.5 + jitter.y) instead of
    /// its centre, in pixels (+x right, +y down, as rows go): a TAA engine's per-frame sub-pixel
    /// offset (Karis 2014), so that frames accumulated over time sample the whole pixel. A zero
    /// jitter gives `raster`'s rays bit for bit (x + 0.5 + 0.0 is x + 0.5 exactly).
    pub fn raster_jittered(&self, width: u32, height: u32, jitter: Vec2) -> Raster {
        let (eye, target, up) = self.pose();
        let forward = (target - eye).normalize();
        let right = forward.cross(up).normalize();
        let true_up = right.cross(forward);
        let aspect = width as f32 / height as f32;
        let lens = match *self {
            Camera::Perspective { fov_y_deg, .. } => {
                Lens::Perspective { tan_half: (0.5 * fov_y_deg.to_radians()).tan() }
            }
            Camera::Orthographic { view_width, .. } => {
                let half_w = 0.5 * view_width;
                Lens::Orthographic { half_w, half_h: half_w / aspect }
            }
        };
        Raster { eye, forward, right, true_up, aspect, width, height, jitter, lens }
    }
}

/// A camera's rays for one image size (see `Camera::raster`).
#[derive(Debug, Clone, Copy)]
pub struct Raster {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    true_up: Vec3,
    aspect: f32,
    width: u32,
    height: u32,
    /// Where in its pixel each ray passes, from the centre, in pixels (`Camera::raster_jittered`).
    jitter: Vec2,
    lens: Lens,
}

#[derive(Debug, Clone, Copy)]
enum Lens {
    Perspective { tan_half: f32 },
    Orthographic { half_w: f32, half_h: f32 },
}

impl Raster {
    /// Screen coordinates in [-1, 1] (x right, y up) of pixel (x, y)'s sample point: its centre
    /// plus the jitter.
    #[inline(always)]
    fn screen(&self, x: u32, y: u32) -> (f32, f32) {
        let sx = 2.0 * (x as f32 + 0.5 + self.jitter.x) / self.width as f32 - 1.0;
        let sy = 1.0 - 2.0 * (y as f32 + 0.5 + self.jitter.y) / self.height as f32;
        (sx, sy)
    }

    /// The ray through the centre of pixel (x, y) (plus the jitter, if any); y = 0 is the top row.
    #[inline]
    pub fn ray(&self, x: u32, y: u32) -> PrimaryRay {
        let (sx, sy) = self.screen(x, y);
        let (forward, right, true_up) = (self.forward, self.right, self.true_up);
        match self.lens {
            Lens::Perspective { tan_half } => {
                let dir = forward + right * (sx * tan_half * self.aspect) + true_up * (sy * tan_half);
                PrimaryRay { origin: self.eye, dir: dir.normalize() }
            }
            Lens::Orthographic { half_w, half_h } => PrimaryRay {
                origin: self.eye + right * (sx * half_w) + true_up * (sy * half_h),
                dir: forward,
            },
        }
    }

    /// Where the ray through the centre of pixel (x, y) starts: `ray(x, y).origin`, without the
    /// direction.
    #[inline]
    pub fn origin(&self, x: u32, y: u32) -> Vec3 {
        match self.lens {
            Lens::Perspective { .. } => self.eye,
            Lens::Orthographic { half_w, half_h } => {
                let (sx, sy) = self.screen(x, y);
                self.eye + self.right * (sx * half_w) + self.true_up * (sy * half_h)
            }
        }
    }

    /// True if every ray starts at the same point (a pinhole camera's eye).
    pub fn shared_origin(&self) -> bool {
        matches!(self.lens, Lens::Perspective { .. })
    }

    /// The image size (width, height) the rays are for.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The per-frame sub-pixel offset of every ray (`Camera::raster_jittered`).
    pub fn jitter(&self) -> Vec2 {
        self.jitter
    }

    /// The inverse of `ray`: the fractional pixel (px, py) whose ray passes through the point `p`
    /// (same coordinates as the camera's), i.e. `ray(x, y)` for integer (x, y) = (px, py) passes
    /// through p; between pixels, the position in the grid of this raster's (jittered) sample
    /// points, which is what bilinear reprojection taps need. None if p is not in front of the
    /// camera (pinhole: at or behind the eye's plane) or the result is not finite. Not limited to
    /// the image: the caller decides what to do with points outside it.
    pub fn pixel_of(&self, p: Vec3) -> Option<Vec2> {
        let d = p - self.eye;
        let (sx, sy) = match self.lens {
            Lens::Perspective { tan_half } => {
                let z = d.dot(self.forward);
                if z.is_nan() || z <= 0.0 {
                    return None;
                }
                (d.dot(self.right) / (z * tan_half * self.aspect), d.dot(self.true_up) / (z * tan_half))
            }
            Lens::Orthographic { half_w, half_h } => {
                (d.dot(self.right) / half_w, d.dot(self.true_up) / half_h)
            }
        };
        let px = 0.5 * (sx + 1.0) * self.width as f32 - 0.5 - self.jitter.x;
        let py = 0.5 * (1.0 - sy) * self.height as f32 - 0.5 - self.jitter.y;
        let out = Vec2::new(px, py);
        out.is_finite().then_some(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orthographic_top_down_maps_pixel_centres() {
        let cam = Camera::Orthographic {
            eye: Vec3::new(0.0, 0.0, 10.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            view_width: 4.0,
        };
        let r = cam.ray(0, 0, 4, 4);
        assert!((r.origin - Vec3::new(-1.5, 1.5, 10.0)).length() < 1e-6, "{r:?}");
        assert_eq!(r.dir, Vec3::new(0.0, 0.0, -1.0));
        assert!(cam.problem().is_none());
        let bad = Camera::Perspective { eye: Vec3::ZERO, target: Vec3::Z, up: Vec3::Y, fov_y_deg: 180.0 };
        assert!(bad.problem().unwrap().contains("fov_y_deg"));
    }

    #[test]
    fn pixel_of_inverts_the_jittered_ray() {
        let cams = [
            Camera::Perspective {
                eye: Vec3::new(0.3, -2.0, 1.2),
                target: Vec3::ZERO,
                up: Vec3::Z,
                fov_y_deg: 60.0,
            },
            Camera::Orthographic {
                eye: Vec3::new(0.0, 0.0, 10.0),
                target: Vec3::ZERO,
                up: Vec3::Y,
                view_width: 4.0,
            },
        ];
        for cam in cams {
            let jitter = Vec2::new(0.3125, -0.2);
            let r = cam.raster_jittered(40, 30, jitter);
            for (x, y) in [(0, 0), (39, 29), (17, 4)] {
                let ray = r.ray(x, y);
                let p = ray.origin + ray.dir * 3.0;
                let back = r.pixel_of(p).unwrap();
                assert!((back - Vec2::new(x as f32, y as f32)).abs().max_element() < 1e-3, "{back}");
            }
            let plain = cam.raster(40, 30);
            assert_eq!(plain.ray(5, 6), cam.ray(5, 6, 40, 30), "a zero jitter is the pixel centre");
        }
    }

    #[test]
    fn up_nearly_parallel_to_the_view_is_refused() {
        let look = |up: Vec3| Camera::Perspective { eye: Vec3::ZERO, target: Vec3::Z, up, fov_y_deg: 45.0 };
        assert!(look(Vec3::Z).problem().unwrap().contains("parallel"));
        assert!(look(Vec3::new(0.0, 1e-4, 1.0)).problem().unwrap().contains("from parallel"));
        assert!(look(Vec3::ZERO).problem().unwrap().contains("zero"));
        assert!(look(Vec3::new(0.0, 2e-3, 1.0)).problem().is_none(), "0.11° away is enough");
        assert!(look(-Vec3::Y).problem().is_none());
    }
}

//! Orthonormal basis around a surface normal.

use glam::Vec3;

/// Local frame with `z` = the normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub x: Vec3,
    pub y: Vec3,
    pub z: Vec3,
}

impl Frame {
    /// Duff et al. 2017, "Building an Orthonormal Basis, Revisited" (JCGT 6(1)), branchless.
    /// `n` must be unit. copysign keeps n.z = -0.0 on the safe side (sign = -1, a finite).
    #[inline]
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let x = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let y = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Self { x, y, z: n }
    }

    /// Local (z = normal) to world, canonicalized (no -0.0 component).
    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        canonical(self.x * v.x + self.y * v.y + self.z * v.z)
    }

    /// World to local (the transpose: the frame is orthonormal).
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        canonical(Vec3::new(self.x.dot(v), self.y.dot(v), self.z.dot(v)))
    }
}

/// Turns every -0.0 component into +0.0 (obvhs 0.4.0's 8-wide traversal misses all geometry on -0.0).
#[inline]
pub fn canonical(v: Vec3) -> Vec3 {
    v + Vec3::ZERO
}

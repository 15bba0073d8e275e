//! Where an AO ray starts so that it never hits the surface it leaves.

use glam::Vec3;

/// Wächter & Binder 2019, "A Fast and Robust Method for Avoiding Self-Intersection" (Ray Tracing
/// Gems, ch. 6): move each coordinate a fixed number of ulps along the normal, or by a small fixed
/// amount near zero where ulps vanish. Their constants (1/32, 1/65536) assume unit-sized scenes; here
/// they are multiplied by `scale`, a power of two >= the triangle's largest |coordinate|, so scaling a
/// scene by 2^k scales every offset by exactly 2^k and a 1e-3-sized scene is treated like a unit one.
pub fn offset_origin(p: Vec3, n: Vec3, scale: f32) -> Vec3 {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let one = |p: f32, n: f32| {
        if p.abs() < ORIGIN * scale {
            p + FLOAT_SCALE * scale * n
        } else {
            let of = (INT_SCALE * n) as i32;
            let of = if p < 0.0 { -of } else { of };
            f32::from_bits((p.to_bits() as i32).wrapping_add(of) as u32)
        }
    };
    Vec3::new(one(p.x, n.x), one(p.y, n.y), one(p.z, n.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moves_along_the_normal_at_every_scale() {
        for (p, n, s) in [
            (Vec3::new(0.3, 0.0, 0.0), Vec3::Z, 1.0),
            (Vec3::new(1e4, 1e4, 1e4), Vec3::Z, 16384.0),
            (Vec3::new(-1e4, 2.0, -1e4), -Vec3::Z, 16384.0),
            (Vec3::new(1e-3, 5e-4, 0.0), Vec3::Z, 1.0 / 512.0),
        ] {
            let o = offset_origin(p, n, s);
            assert!((o - p).dot(n) > 0.0, "{p} {n} {o}");
            assert_eq!((o.x, o.y), (p.x, p.y), "only the normal's components move");
        }
    }
}

//! Proof of the orthonormal basis (Duff et al. 2017) and of direction canonicalization.

use glam::Vec3;
use hemilab::sampling::seed::hash;
use hemilab::sampling::{Distribution, Frame, canonical};

fn assert_orthonormal(n: Vec3) {
    let f = Frame::from_normal(n);
    let ctx = format!("n = {n:?}: {f:?}");
    for v in [f.x, f.y, f.z] {
        assert!(v.is_finite(), "{ctx}");
        assert!((v.length() - 1.0).abs() < 1e-6, "{ctx}");
    }
    assert!(f.x.dot(f.y).abs() < 1e-6 && f.x.dot(f.z).abs() < 1e-6 && f.y.dot(f.z).abs() < 1e-6, "{ctx}");
    assert!((f.x.cross(f.y) - f.z).length() < 2e-6, "not right-handed: {ctx}");
}

#[test]
fn basis_orthonormal_for_plus_minus_x_y_z() {
    for n in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
        assert_orthonormal(n);
    }
    // -0.0 components (e.g. -Vec3::X has z = -0.0) are covered above; spell one out.
    assert_orthonormal(Vec3::new(0.0, 1.0, -0.0));
}

#[test]
fn basis_orthonormal_for_almost_minus_z_renormalized() {
    assert_orthonormal(Vec3::new(0.0, 0.0, -1.0 + 1e-7).normalize());
    assert_orthonormal(Vec3::new(1e-7, -1e-7, -1.0).normalize());
    assert_orthonormal(Vec3::new(1e-4, 0.0, -1.0).normalize());
}

#[test]
fn basis_orthonormal_for_a_million_random_normals() {
    for i in 0..1_000_000u64 {
        let h = hash(0xBA515, i);
        // Uniform on the sphere: z uniform in [-1,1], phi uniform.
        let z = ((h >> 40) as f32 / 8_388_608.0) - 1.0;
        let phi = ((h >> 16) & 0xFF_FFFF) as f32 / 16_777_216.0 * std::f32::consts::TAU;
        let r = (1.0 - z * z).max(0.0).sqrt();
        assert_orthonormal(Vec3::new(r * phi.cos(), r * phi.sin(), z).normalize());
    }
}

#[test]
fn to_world_keeps_samples_above_the_surface_and_canonical() {
    for i in 0..20_000u64 {
        let h = hash(0xF00D, i);
        let n =
            Vec3::new((h & 0xFFFF) as f32 - 32768.0, ((h >> 16) & 0xFFFF) as f32 - 32768.0, 1.0).normalize();
        let n = if i % 2 == 0 { -n } else { n };
        let f = Frame::from_normal(n);
        for &d in Distribution::ALL {
            let u = glam::Vec2::new((h >> 40) as f32 / 16_777_216.0, 0.999);
            let w = f.to_world(d.sample(u).dir);
            assert!(w.is_finite() && (w.length() - 1.0).abs() < 1e-5 && w.dot(n) >= -1e-6, "{w}");
            assert!(w.to_array().iter().all(|c| c.to_bits() != (-0.0f32).to_bits()));
            assert!((f.to_local(w) - d.sample(u).dir).length() < 1e-5);
        }
    }
}

#[test]
fn canonical_turns_negative_zero_into_positive_zero() {
    let v = canonical(Vec3::new(-0.0, -0.0, -0.0));
    assert!(v.to_array().iter().all(|c| c.to_bits() == 0));
    assert_eq!(canonical(Vec3::new(-1.0, 2.0, -0.5)), Vec3::new(-1.0, 2.0, -0.5));
}

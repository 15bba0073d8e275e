use super::*;

#[test]
fn hits_a_triangle_and_respects_tmax() {
    let tri = [Vec3::new(-1.0, -1.0, 1.0), Vec3::new(1.0, -1.0, 1.0), Vec3::new(0.0, 1.0, 1.0)];
    let (acc, _) = Accel::build(&[tri]);
    let r = Ray::new(Vec3::ZERO, Vec3::Z, f32::INFINITY);
    let h = acc.closest(&r).unwrap();
    assert!((h.t - 1.0).abs() < 1e-6);
    assert!(acc.occluded(&r));
    assert!(!acc.occluded(&Ray::new(Vec3::ZERO, Vec3::Z, 0.5)));
    assert!(!acc.occluded(&Ray::new(Vec3::ZERO, -Vec3::Z, f32::INFINITY)));
    // -0.0 components must not make the ray miss.
    assert!(acc.occluded(&Ray::new(Vec3::ZERO, Vec3::new(-0.0, -0.0, 1.0), f32::INFINITY)));
}

#[test]
fn the_avx2_single_ray_walk_answers_as_the_sse2_walk_and_brute_force() {
    // A soup of small triangles in a unit box, rays from inside it in every direction.
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut tris = Vec::new();
    for _ in 0..3000 {
        let c = Vec3::new(next(), next(), next());
        let e = |n: &mut dyn FnMut() -> f32| Vec3::new(n() - 0.5, n() - 0.5, n() - 0.5) * 0.08;
        tris.push([c, c + e(&mut next), c + e(&mut next)]);
    }
    let (acc, _) = Accel::build(&tris);
    let (mut hits, mut cases) = (0, 0);
    for _ in 0..4000 {
        let o = Vec3::new(next(), next(), next());
        let d = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5).normalize_or(Vec3::Z);
        for tmax in [0.05, 0.3, f32::INFINITY] {
            let ray = Ray::new(o, d, tmax);
            let want = acc.occluded_walk::<false>(&ray);
            assert_eq!(acc.occluded(&ray), want, "{o} {d} {tmax}");
            assert_eq!(acc.closest_brute_force(&ray).is_some(), want, "{o} {d} {tmax}");
            hits += want as u32;
            cases += 1;
        }
    }
    assert!(hits > cases / 10 && hits < cases * 9 / 10, "{hits} of {cases}");
}

#[test]
fn short_hits_below_obvhs_epsilon_are_found() {
    let s = 1e-6;
    let tri = [Vec3::new(-s, -s, s), Vec3::new(s, -s, s), Vec3::new(0.0, s, s)];
    let (acc, _) = Accel::build(&[tri]);
    assert!(acc.occluded(&Ray::new(Vec3::ZERO, Vec3::Z, f32::INFINITY)));
}

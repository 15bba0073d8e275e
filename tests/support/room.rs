//! The closed cube [-1, 1]³ of the closed-room tests (the leak at concave edges, and the
//! integrands' closed-form variances): six faces whose normals point into the room.

use glam::DVec3;

/// Its 12 triangles (each face split along its first diagonal), every vertex placed by `place`.
pub fn cube_triangles(place: impl Fn(DVec3) -> DVec3) -> Vec<[DVec3; 3]> {
    let v = DVec3::new;
    let faces = [
        [v(-1., -1., -1.), v(1., -1., -1.), v(1., 1., -1.), v(-1., 1., -1.)],
        [v(-1., -1., 1.), v(-1., 1., 1.), v(1., 1., 1.), v(1., -1., 1.)],
        [v(-1., -1., -1.), v(-1., -1., 1.), v(1., -1., 1.), v(1., -1., -1.)],
        [v(-1., 1., -1.), v(1., 1., -1.), v(1., 1., 1.), v(-1., 1., 1.)],
        [v(-1., -1., -1.), v(-1., 1., -1.), v(-1., 1., 1.), v(-1., -1., 1.)],
        [v(1., -1., -1.), v(1., -1., 1.), v(1., 1., 1.), v(1., 1., -1.)],
    ];
    faces.iter().map(|f| f.map(&place)).flat_map(|f| [[f[0], f[1], f[2]], [f[0], f[2], f[3]]]).collect()
}

//! `hemilab render --integrand` inside the closed cube (half-size 1, faces inward, camera at
//! (0, 0, 0.5) looking down −z, fov 80°, d infinite, 320x240): with each integrand's matched
//! distribution every ray has weight exactly 1 and is blocked, so every pixel is exactly 0
//! (occlusion exactly 1) at every ray count; a bad integrand exits 2 naming what is allowed.

use crate::support::common::Tmp;

const CUBE: &str = "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\n";

const SCENE: &str = "mesh = \"cube.obj\"\nresolution = [320, 240]\nao_distance = \"infinite\"\n\n\
[camera.perspective]\neye = [0.0, 0.0, 0.5]\ntarget = [0.0, 0.0, -1.0]\nup = [0.0, 1.0, 0.0]\nfov_y_deg = 80.0\n";

#[test]
fn matched_integrands_read_exactly_zero_in_the_closed_cube() {
    let t = Tmp::new("render-integrand");
    std::fs::write(t.path("cube.obj"), CUBE).unwrap();
    std::fs::write(t.path("cube.toml"), SCENE).unwrap();
    for (integrand, distribution) in [("visibility", "sine"), ("ao", "sine-cosine")] {
        for rays in ["1", "32", "256"] {
            let out = format!("{integrand}-{rays}.exr");
            let o = t.hemilab(&[
                "render",
                "cube.toml",
                "--integrand",
                integrand,
                "--distribution",
                distribution,
                "--rays",
                rays,
                "--output",
                &out,
                "--quiet",
            ]);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            let channels = hemilab::io::read_exr(&t.path(&out)).unwrap();
            let y = &channels.iter().find(|(n, _)| n == "Y").unwrap().1;
            let a = &channels.iter().find(|(n, _)| n == "A").unwrap().1;
            assert!(a.data.iter().all(|&c| c == 1.0), "every pixel sees the room");
            let off = y.data.iter().filter(|&&v| v != 0.0).count();
            assert_eq!(off, 0, "{integrand} {distribution} {rays} rays: {off} pixels not exactly 0");
        }
    }
    let o = t.hemilab(&["render", "cube.toml", "--integrand", "lobe", "--rays", "1", "--output", "x.exr"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("cos-lobe-N"));
    assert!(!t.path("x.exr").exists());
}

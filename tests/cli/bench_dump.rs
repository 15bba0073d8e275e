//! `hemilab bench --dump-rays FILE`: the bench's ray set in the HLRAYS1 format peer ray tracers read
//! (docs/performance.md). The file is read back here as a peer would read it, its sizes checked
//! against the bench's own report, and its rays traced by an independent brute-force test (f64,
//! every triangle, both faces, 0 < t < d): the occluded counts must equal hemilab's.

use crate::support::common::{Tmp, assert_error, hemilab_in_root as hemilab, scene};

/// A dump as a peer reads it.
struct Dump {
    tris: Vec<[[f64; 3]; 3]>,
    n: usize,
    origins: Vec<[f64; 3]>,
    normals: Vec<[f64; 3]>,
    dirs: Vec<[f64; 3]>,
}

fn read_dump(bytes: &[u8]) -> Dump {
    assert_eq!(&bytes[..8], b"HLRAYS1\0");
    let mut at = 8;
    let mut u32_ = || {
        let v = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
        at += 4;
        v as usize
    };
    let t = u32_();
    let vec3 = |at: usize| -> [f64; 3] {
        std::array::from_fn(|k| {
            f32::from_le_bytes(bytes[at + 4 * k..at + 4 * k + 4].try_into().unwrap()) as f64
        })
    };
    let tris: Vec<[[f64; 3]; 3]> =
        (0..t).map(|i| std::array::from_fn(|v| vec3(12 + 36 * i + 12 * v))).collect();
    let at = 12 + 36 * t;
    let (p, n) = (
        u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize,
        u32::from_le_bytes(bytes[at + 4..at + 8].try_into().unwrap()) as usize,
    );
    let base = at + 8;
    assert_eq!(bytes.len(), base + 12 * (2 * p + p * n), "the file holds exactly its counts' data");
    let origins = (0..p).map(|i| vec3(base + 12 * i)).collect();
    let normals = (0..p).map(|i| vec3(base + 12 * (p + i))).collect();
    let dirs = (0..p * n).map(|i| vec3(base + 12 * (2 * p + i))).collect();
    Dump { tris, n, origins, normals, dirs }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Möller–Trumbore in f64 without an epsilon: any triangle, either face, at 0 < t < d.
fn blocked(tris: &[[[f64; 3]; 3]], o: [f64; 3], d: [f64; 3], tmax: f64) -> bool {
    tris.iter().any(|[a, b, c]| {
        let (e1, e2) = (sub(*b, *a), sub(*c, *a));
        let p = cross(d, e2);
        let det = dot(e1, p);
        if det == 0.0 {
            return false;
        }
        let s = sub(o, *a);
        let u = dot(s, p) / det;
        let q = cross(s, e1);
        let v = dot(d, q) / det;
        let t = dot(e2, q) / det;
        (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0 && t > 0.0 && t < tmax
    })
}

#[test]
fn bench_dumps_its_exact_rays_for_peers() {
    let dir = Tmp::new("bench-dump");
    let file = dir.path("rays/cornell.bin");
    let out = hemilab(&[
        "bench",
        &scene("cornell-box.toml"),
        "--rays",
        "8",
        "--resolution",
        "16x12",
        "--repeats",
        "1",
        "--json",
        "--distances",
        "150,inf",
        "--dump-rays",
        file.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let dump = read_dump(&std::fs::read(&file).unwrap());
    assert_eq!(dump.tris.len() as u64, v["triangles"].as_u64().unwrap());
    assert_eq!(dump.origins.len() as u64, v["ray_set"]["pixels"].as_u64().unwrap());
    assert_eq!(dump.n, 8);
    assert_eq!(dump.dirs.len() as u64, v["ray_set"]["rays"].as_u64().unwrap());
    // Unit directions in the hemisphere of their pixel's normal, as the format's readers assume.
    for (i, d) in dump.dirs.iter().enumerate() {
        assert!((dot(*d, *d).sqrt() - 1.0).abs() < 1e-5, "ray {i}: {d:?}");
        assert!(dot(*d, dump.normals[i / dump.n]) >= -1e-6, "ray {i} below its surface");
    }
    for c in v["comparison"].as_array().unwrap() {
        let d = c["ao_distance"].as_f64().unwrap_or(f64::INFINITY);
        let count = (0..dump.dirs.len())
            .filter(|&i| blocked(&dump.tris, dump.origins[i / dump.n], dump.dirs[i], d))
            .count() as u64;
        let hemilab = c["occluded"]["hemilab"].as_u64().unwrap();
        assert_eq!(count, hemilab, "d = {d}: brute force over the dump against hemilab");
        assert!(hemilab > 0 && hemilab < c["rays"].as_u64().unwrap(), "d = {d}: {hemilab}");
    }
    // Nothing but the dump beside it (the write is atomic: no temporary left).
    assert_eq!(dir.listing(), ["rays", "rays/cornell.bin"]);
}

/// The peers have no alpha test, so a dump of a masked scene would not be traced alike: refused
/// before any work, naming the scene, and nothing written.
#[test]
fn bench_refuses_to_dump_a_masked_scene() {
    let dir = Tmp::new("bench-dump-masked");
    let file = dir.path("f.bin");
    let foliage = scene("foliage.toml");
    let out = hemilab(&["bench", &foliage, "--resolution", "8x6", "--dump-rays", file.to_str().unwrap()]);
    let e = assert_error(&out, &foliage);
    assert!(e.contains("alpha masks") && e.contains("OPAQUE"), "{e}");
    assert!(dir.listing().is_empty(), "{:?}", dir.listing());
}

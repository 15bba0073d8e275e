//! Writes a large terrain grid for load-time and memory measurements: `N` × `N` quads of a
//! gently rolling height field, 2 N² triangles, as OBJ, as glTF `.glb` (the same f32 vertices, so
//! both render the same image), and a scene TOML for each:
//! `cargo run --release --example write_grid -- /tmp/grid 2237` (2237² × 2 = 10.0 M triangles; the OBJ
//! is about 0.4 GB), then `/usr/bin/time -v hemilab render /tmp/grid/grid-obj.toml --rays 1
//! --resolution 32x24 --output /tmp/grid/out.exr`. Coordinates are printed with `{}` of the f32 value,
//! which round-trips exactly.
//!
//! A third argument orders the triangles (the BVH build must not depend on it; the image
//! does not): `ordered` (default; each quad's two triangles next to each other, row by row),
//! `split` (the first triangle of every quad, then every second one: a quad's halves N² apart) or
//! `shuffled` (a fixed pseudo-random permutation of all triangles). The vertices stay in grid order.

use hemilab::scene::gltf_write::{Doc, Node, Prim};
use std::io::Write;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let dir = PathBuf::from(args.next().unwrap_or_else(|| "/tmp/grid".into()));
    let n: u32 = args.next().map_or(Ok(2237), |s| s.parse())?;
    let order = args.next().unwrap_or_else(|| "ordered".into());
    std::fs::create_dir_all(&dir)?;
    let side = n + 1;
    let height =
        |x: f32, z: f32| 0.05 * ((x * 7.0).sin() + (z * 5.0).cos()) + 0.02 * (x * 31.0 + z * 17.0).sin();
    let mut positions = Vec::with_capacity((side * side) as usize);
    for j in 0..side {
        for i in 0..side {
            let (x, z) = (i as f32 / n as f32, j as f32 / n as f32);
            positions.push([x, height(x, z), z]);
        }
    }
    let mut indices = Vec::with_capacity((6 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            let a = j * side + i;
            let (b, c, d) = (a + 1, a + side + 1, a + side);
            indices.extend_from_slice(&[a, d, c, a, c, b]);
        }
    }
    let indices = reorder(indices, &order)?;
    let mut obj = std::io::BufWriter::new(std::fs::File::create(dir.join("grid.obj"))?);
    for p in &positions {
        writeln!(obj, "v {} {} {}", p[0], p[1], p[2])?;
    }
    for t in indices.chunks_exact(3) {
        writeln!(obj, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
    }
    obj.flush()?;
    let doc = Doc {
        meshes: vec![vec![Prim { positions, indices: Some(indices), mode: 4, ..Prim::default() }]],
        nodes: vec![Node { mesh: Some(0), ..Node::default() }],
        roots: vec![0],
        ..Doc::default()
    };
    std::fs::write(dir.join("grid.glb"), doc.to_glb())?;
    for (name, mesh) in [("grid-obj", "grid.obj"), ("grid-glb", "grid.glb")] {
        let toml = format!(
            "mesh = \"{mesh}\"\nresolution = [320, 240]\nao_distance = 0.05\n[camera.perspective]\n\
             eye = [0.5, 0.6, -0.4]\ntarget = [0.5, 0.0, 0.5]\nup = [0.0, 1.0, 0.0]\nfov_y_deg = 50.0\n"
        );
        std::fs::write(dir.join(format!("{name}.toml")), toml)?;
    }
    println!("{}: {} triangles, {order}", dir.display(), 2 * n as u64 * n as u64);
    Ok(())
}

/// The triangles (3 indices each) in the order `order` names (see the module's doc).
fn reorder(indices: Vec<u32>, order: &str) -> Result<Vec<u32>, String> {
    let tris: Vec<[u32; 3]> = indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect();
    let tris = match order {
        "ordered" => tris,
        "split" => tris.iter().step_by(2).chain(tris.iter().skip(1).step_by(2)).copied().collect(),
        "shuffled" => {
            // Fisher-Yates with splitmix64 from a fixed seed: the same file on every run.
            let mut tris = tris;
            let mut state = 0x9E37_79B9_7F4A_7C15u64;
            for i in (1..tris.len()).rev() {
                state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
                let mut z = state;
                z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
                z ^= z >> 31;
                tris.swap(i, (z % (i as u64 + 1)) as usize);
            }
            tris
        }
        other => return Err(format!("order must be ordered, split or shuffled, got {other:?}")),
    };
    Ok(tris.into_iter().flatten().collect())
}

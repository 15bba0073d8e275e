//! Do tiles rank configurations as the whole frame does? Reads a full-frame run's and a tiled run's
//! results.json (the same spec but `[tiles]`, docs/advise.md, section "Tiles") and prints, per
//! camera and pipeline, each configuration's mean RMSE and FLIP at the last frame in both, ranked
//! by the full frame, and whether the full frame's winner wins on tiles too or lies within the
//! tiled winner's paired margin (2 standard errors of the per-replicate RMSE difference).
//! RMSE and FLIP are deterministic (fixed seeds), so the table is reproducible; timings are not
//! read. A check to run on two real runs, not a test (two runs at 320x180 take minutes here):
//!
//! `cargo run --release --example tiles_agreement -- out/full out/tiles`

use hemilab::results::{JobResult, from_json};
use std::collections::BTreeMap;
use std::path::Path;

type Key = (String, String, String, String);
/// Per replicate: (RMSE, FLIP).
type Replicates = BTreeMap<u32, (f64, f64)>;
/// Per (camera, pipeline), per configuration.
type Views = BTreeMap<(String, String), BTreeMap<Key, Replicates>>;

fn load(dir: &str) -> Result<Vec<JobResult>, Box<dyn std::error::Error>> {
    Ok(from_json(&std::fs::read_to_string(Path::new(dir).join("results.json"))?)?)
}

/// Per (camera, pipeline): per configuration, replicate → (RMSE, FLIP) at the last frame.
fn last_frames(rs: &[JobResult]) -> Views {
    let mut out = Views::new();
    let last = rs.iter().map(|r| r.frame).max().unwrap_or(1);
    for r in rs.iter().filter(|r| r.frame == last) {
        let key = (r.distribution.clone(), r.sequence.clone(), r.seed_mode.clone(), r.schedule.clone());
        out.entry((r.camera.clone(), r.pipeline.clone()))
            .or_default()
            .entry(key)
            .or_default()
            .insert(r.replicate, (r.rmse, r.flip));
    }
    out
}

fn mean(v: impl Iterator<Item = f64>) -> f64 {
    let v: Vec<f64> = v.collect();
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() != 2 {
        return Err("usage: tiles_agreement FULL_DIR TILES_DIR".into());
    }
    let (full, tiles) = (last_frames(&load(&args[0])?), last_frames(&load(&args[1])?));
    for (view, configs) in &full {
        let Some(tiled) = tiles.get(view) else { continue };
        let rmse = |m: &Replicates| mean(m.values().map(|x| x.0));
        let flip = |m: &Replicates| mean(m.values().map(|x| x.1));
        let mut order: Vec<&Key> = configs.keys().collect();
        order.sort_by(|a, b| rmse(&configs[*a]).total_cmp(&rmse(&configs[*b])));
        let mut tiled_order: Vec<&Key> = tiled.keys().collect();
        tiled_order.sort_by(|a, b| rmse(&tiled[*a]).total_cmp(&rmse(&tiled[*b])));
        println!("\ncamera {}, pipeline {}, last frame:", view.0, view.1);
        println!("| configuration | full RMSE | full FLIP | tiles RMSE | tiles FLIP | tiles rank |");
        println!("|---|---|---|---|---|---|");
        for k in &order {
            let rank = tiled_order.iter().position(|t| t == k).map_or(0, |p| p + 1);
            let t = tiled.get(*k);
            println!(
                "| {} / {} / {} / {} | {:.5} | {:.4} | {:.5} | {:.4} | {rank} |",
                k.0,
                k.1,
                k.2,
                k.3,
                rmse(&configs[*k]),
                flip(&configs[*k]),
                t.map_or(f64::NAN, rmse),
                t.map_or(f64::NAN, flip)
            );
        }
        let (winner, tiled_winner) = (order[0], tiled_order[0]);
        let verdict = if winner == tiled_winner {
            "the same winner".to_string()
        } else {
            // Paired over replicates on tiles: the full winner minus the tiled winner.
            let (a, b) = (&tiled[winner], &tiled[tiled_winner]);
            let d: Vec<f64> = a.iter().filter_map(|(r, x)| b.get(r).map(|y| x.0 - y.0)).collect();
            let m = mean(d.iter().copied());
            let sd = (d.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (d.len().max(2) - 1) as f64).sqrt();
            let margin = 2.0 * sd / (d.len() as f64).sqrt();
            format!(
                "another winner on tiles; the full frame's is {m:.5} behind it, {} its paired margin {margin:.5}",
                if m <= margin { "within" } else { "outside" }
            )
        };
        println!("{verdict}");
    }
    Ok(())
}

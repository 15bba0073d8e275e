//! Point generation alone, per sequence: how many nanoseconds one point of each
//! sequence costs, so a sequence's share of a render's time is a figure of its own rather than a
//! guess from whole renders (Halton's and ZSobol's once cost ×3–4.6 the lattice's renders).

use crate::sampling::{SamplerConfig, SeedMode, Sequence};
use crate::timing::clock::thread_cpu_s;
use glam::Vec2;
use serde_json::{Value, json};

/// Points per pixel the figure is taken at: a render's usual count and a long one.
pub const COUNTS: [u32; 2] = [64, 1024];

/// Every built-in sequence's `fill_pixel` cost on one thread (its CPU time, `timing::clock`: a
/// shared machine's other work does not count), in ns per point, over `pixels`
/// consecutive pixels of a 160-wide image (keys and offsets as a render makes them), in `shift`
/// (every sequence's mode in the paper's sweep), `repeats` timed passes after one untimed:
/// min / median / max.
pub fn ns_per_point(pixels: u32, repeats: u32) -> Value {
    let mut rows = Vec::new();
    for sequence in Sequence::all() {
        for count in COUNTS {
            let Ok(cfg) = SamplerConfig::new(sequence, SeedMode::Shift, count, 1) else { continue };
            cfg.prepare();
            let mut out = vec![Vec2::ZERO; count as usize];
            let mut sink = 0.0f32;
            let mut pass = || {
                let start = thread_cpu_s();
                for p in 0..pixels {
                    cfg.fill_pixel(p % 160, p / 160, p as u64, &mut out);
                    sink += out[count as usize / 2].x;
                }
                (thread_cpu_s() - start) * 1e9 / (pixels as f64 * count as f64)
            };
            pass();
            let mut ns: Vec<f64> = (0..repeats.max(1)).map(|_| pass()).collect();
            std::hint::black_box(sink);
            ns.sort_by(f64::total_cmp);
            rows.push(json!({
                "sequence": sequence.name(),
                "points_per_pixel": count,
                "ns_per_point": { "min": ns[0], "median": ns[ns.len() / 2], "max": ns[ns.len() - 1] },
            }));
        }
    }
    json!({ "pixels": pixels, "seed_mode": "shift", "threads": 1, "rows": rows })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_sequence_has_a_figure_at_every_count() {
        let v = ns_per_point(4, 1);
        let rows = v["rows"].as_array().unwrap();
        for sequence in Sequence::all() {
            for count in COUNTS {
                let row = rows
                    .iter()
                    .find(|r| r["sequence"] == sequence.name() && r["points_per_pixel"] == count)
                    .unwrap_or_else(|| panic!("{} at {count}", sequence.name()));
                let ns = &row["ns_per_point"];
                let (lo, mid, hi) = (ns["min"].as_f64(), ns["median"].as_f64(), ns["max"].as_f64());
                assert!(lo.unwrap() >= 0.0 && lo <= mid && mid <= hi, "{row}");
            }
        }
    }
}

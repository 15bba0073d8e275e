//! Do two runs of the same spec rank the configurations' efficiency alike? Reads two output
//! directories' results.json and lists every pair of rows, at a common scene and ray count, that the
//! runs order differently although one of them puts the pair more than K combined spreads apart
//! (`compare::rank_disagreements`). Timings are not deterministic, so this is a check to run on
//! two real runs, not a test:
//!
//! `cargo run --release --example rank_agreement -- out/paper-a out/paper-b [K=3]`
//!
//! Also prints, per ray count, the median-time ratio of the rows that trace the same number of
//! rays with the same cost (Fibonacci shift against rotation) in each run.

use hemilab::compare::efficiency::rank_disagreements;
use hemilab::compare::row_of;
use hemilab::results::{Aggregate, aggregate, from_json};
use hemilab::spec::Row;
use std::path::Path;

fn load(dir: &str) -> Result<Vec<Aggregate>, Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string(Path::new(dir).join("results.json"))?;
    Ok(aggregate(&from_json(&text)?))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        return Err("usage: rank_agreement DIR_A DIR_B [K]".into());
    }
    let k: f64 = args.get(2).map_or(Ok(3.0), |s| s.parse())?;
    let (a, b) = (load(&args[0])?, load(&args[1])?);
    let mut rows: Vec<Row> = Vec::new();
    for r in a.iter().filter_map(row_of) {
        if !rows.contains(&r) {
            rows.push(r);
        }
    }
    let (bad, checked) = rank_disagreements(&a, &b, &rows, k);
    println!(
        "{checked} pairs more than {k} combined spreads apart in either run; {} ordered differently",
        bad.len()
    );
    for d in &bad {
        println!(
            "  {} {} rays: {} vs {}: {:.4e} / {:.4e} ({:.1} spreads) then {:.4e} / {:.4e} ({:.1} spreads)",
            d.scene, d.rays, d.a, d.b, d.first.0, d.first.1, d.spreads.0, d.second.0, d.second.1, d.spreads.1
        );
    }
    for (name, aggs) in [(&args[0], &a), (&args[1], &b)] {
        let ratio = |n: u32| {
            let t = |mode: &str| {
                aggs.iter()
                    .find(|x| {
                        x.distribution == "sine-cosine"
                            && x.sequence == "fibonacci"
                            && x.seed_mode == mode
                            && x.rays == n
                    })
                    .and_then(|x| x.time)
                    .map(|t| t.median)
            };
            Some(t("shift")? / t("rotation")?)
        };
        let mut rays: Vec<u32> = aggs.iter().map(|x| x.rays).collect();
        rays.sort_unstable();
        rays.dedup();
        let cells: Vec<String> =
            rays.iter().filter_map(|&n| ratio(n).map(|r| format!("{n}: {r:.3}"))).collect();
        println!("{name}: Fibonacci shift / rotation median time: {}", cells.join(", "));
    }
    if bad.is_empty() { Ok(()) } else { Err(format!("{} disagreements", bad.len()).into()) }
}

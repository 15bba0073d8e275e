//! Does advise at an engine's resolution (on tiles, from the frames its pipeline remembers) ship
//! what whole frames find best? Reads a spec run of the same candidates on whole frames (its
//! results.json: every replicate of every configuration and schedule, each camera and ray count,
//! the pipeline's records at its last frame) and an advise directory (advice.json), and prints
//! per camera and ray count: the run's best by RMSE with its near-ties (every candidate whose
//! paired MSE difference to the best is within 2 standard errors, as advise's own near-ties),
//! advise's pick, where the run ranks it, its RMSE there against the best's, and whether it is the
//! run's best or one of its near-ties; the same for FLIP. Deterministic (fixed seeds); times are
//! not read. docs/advise.md, section "At an engine's resolution", has the table and the commands:
//!
//! `cargo run --release --example advise_agreement -- RUN_DIR SCENE_NAME ADVISE_DIR`

use hemilab::results::{JobResult, from_json};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// "distribution/sequence/seed_mode@schedule".
type Candidate = String;
/// Per replicate: (MSE, FLIP).
type Replicates = BTreeMap<u32, (f64, f64)>;

fn read(path: &Path) -> Result<String, Box<dyn std::error::Error>> {
    std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()).into())
}

/// The paired mean and standard error of b − a over the replicates both have (the crate's one
/// paired margin, `compare::margin::paired`).
fn paired(a: &Replicates, b: &Replicates, pick: fn(&(f64, f64)) -> f64) -> (f64, f64) {
    let list = |r: &Replicates| r.iter().map(|(&k, v)| (k, pick(v))).collect::<Vec<_>>();
    let m = hemilab::compare::margin::paired(&list(a), &list(b));
    (m.mean, m.se)
}

fn mean(r: &Replicates, pick: fn(&(f64, f64)) -> f64) -> f64 {
    r.values().map(pick).sum::<f64>() / r.len().max(1) as f64
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [run, scene, advise] = args.as_slice() else {
        return Err("usage: advise_agreement RUN_DIR SCENE_NAME ADVISE_DIR".into());
    };
    let records: Vec<JobResult> = from_json(&read(&Path::new(run).join("results.json"))?)?;
    let records: Vec<&JobResult> =
        records.iter().filter(|r| &r.scene == scene && r.pipeline != "raw").collect();
    let last = records.iter().map(|r| r.frame).max().ok_or("no record of that scene after a pipeline")?;
    // (camera, rays) → candidate → replicate → (MSE, FLIP).
    let mut views: BTreeMap<(String, u32), BTreeMap<Candidate, Replicates>> = BTreeMap::new();
    for r in records.iter().filter(|r| r.frame == last) {
        let c = format!("{}/{}/{}@{}", r.distribution, r.sequence, r.seed_mode, r.schedule);
        views
            .entry((r.camera.clone(), r.rays))
            .or_default()
            .entry(c)
            .or_default()
            .insert(r.replicate, (r.rmse * r.rmse, r.flip));
    }
    let advice: Value = serde_json::from_str(&read(&Path::new(advise).join("advice.json"))?)?;
    let budgets = advice["ray_budgets"].as_array().ok_or("advice.json has no ray_budgets")?;
    let name = |c: &Value| {
        format!(
            "{}/{}/{}",
            c["distribution"].as_str().unwrap_or("?"),
            c["sequence"].as_str().unwrap_or("?"),
            c["seed_mode"].as_str().unwrap_or("?")
        )
    };
    println!(
        "| camera | rays | whole-frame best (RMSE) | near-ties there | advise ships | its rank there | its RMSE there | verdict | FLIP: whole-frame best | advise's FLIP pick | FLIP verdict |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for b in budgets {
        let (camera, rays) = (
            b["camera"].as_str().unwrap_or("?").to_string(),
            b["rays_per_pixel_per_frame"].as_u64().unwrap_or(0) as u32,
        );
        let Some(cands) = views.get(&(camera.clone(), rays)) else { continue };
        // advise's pick: "any" schedule (STBN's schedules agree over its cycle) matches either.
        let schedule = b["recommended_schedule"].as_str().unwrap_or("any");
        let ships = name(&b["recommended"]);
        let flip_pick = &b["recommended_by_flip"];
        let flip_ships = if flip_pick.is_null() { ships.clone() } else { name(&flip_pick["configuration"]) };
        let flip_schedule =
            if flip_pick.is_null() { schedule } else { flip_pick["schedule"].as_str().unwrap_or("any") };
        let find = |label: &str, schedule: &str| -> Option<Candidate> {
            cands
                .keys()
                .find(|k| {
                    k.starts_with(&format!("{label}@"))
                        && (schedule == "any" || k.ends_with(&format!("@{schedule}")))
                })
                .cloned()
        };
        let verdict = |pick: fn(&(f64, f64)) -> f64,
                       label: &str,
                       schedule: &str|
         -> (String, usize, f64, f64, String, Vec<String>) {
            let mut order: Vec<&Candidate> = cands.keys().collect();
            order.sort_by(|a, b| mean(&cands[*a], pick).total_cmp(&mean(&cands[*b], pick)));
            let best = order[0];
            let ties: Vec<String> = order[1..]
                .iter()
                .filter(|c| {
                    let (m, se) = paired(&cands[best], &cands[**c], pick);
                    m <= 2.0 * se
                })
                .map(|c| c.to_string())
                .collect();
            let Some(mine) = find(label, schedule) else {
                return (best.clone(), 0, f64::NAN, f64::NAN, "not in the run".into(), ties);
            };
            let rank = order.iter().position(|c| **c == mine).map_or(0, |p| p + 1);
            let v = if &mine == best {
                "the same".to_string()
            } else if ties.contains(&mine) {
                "within the best's paired margin".to_string()
            } else {
                let (m, se) = paired(&cands[best], &cands[&mine], pick);
                format!("outside it ({:.1} se)", m / se)
            };
            (best.clone(), rank, mean(&cands[&mine], pick), mean(&cands[best], pick), v, ties)
        };
        let (best, rank, mine, top, v, ties) = verdict(|x| x.0, &ships, schedule);
        let (fbest, _, _, _, fv, _) = verdict(|x| x.1, &flip_ships, flip_schedule);
        println!(
            "| {camera} | {rays} | {best} ({:.5}) | {} | {ships}@{schedule} | {rank} of {} | {:.5} | {v} | {fbest} | {flip_ships}@{flip_schedule} | {fv} |",
            top.sqrt(),
            if ties.is_empty() { "none".to_string() } else { ties.join(", ") },
            cands.len(),
            mine.sqrt(),
        );
    }
    Ok(())
}

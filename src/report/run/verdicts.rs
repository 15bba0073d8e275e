//! The report's opening table: each of the paper's claims on each scene of the run — holds, fails or
//! not significant, with its margin in standard errors of paired differences — and, folded away at the
//! end of the page, the margins at every ray count. The claim logic is `report::verdict`'s; this file
//! picks the ray counts the spec measured and formats the cells.

use crate::compare::claims::{self, Claim, Outcome, Verdict};
use crate::report::Table;
use crate::report::run::data::ReportInput;
use crate::spec::GroupKind;

/// Every claim on every scene of the spec. Table claims use the ray counts of the `[[table]]`s that
/// include the scene; slope claims the ray counts of its first `[[convergence]]`.
pub fn all(data: &ReportInput) -> Vec<Verdict> {
    let spec = &data.loaded.spec;
    let mut out = Vec::new();
    for (si, scene) in spec.scenes.iter().enumerate() {
        let mut rays: Vec<u32> = spec
            .groups
            .iter()
            .filter(|g| g.kind == GroupKind::Table && g.scenes.contains(&si))
            .flat_map(|g| g.rays.iter().copied())
            .collect();
        rays.sort_unstable();
        rays.dedup();
        let sweep: Vec<u32> = spec
            .groups
            .iter()
            .find(|g| g.kind == GroupKind::Convergence && g.scenes.contains(&si))
            .map_or(Vec::new(), |g| g.rays.clone());
        out.extend(claims::scene_verdicts(data.results, &scene.name, &rays, &sweep));
    }
    out
}

fn cell(v: &Verdict) -> String {
    match v.outcome {
        Outcome::NotMeasured => "–".into(),
        o => format!("{} ({})", o.label(), claims::fmt_se(v.margin_se)),
    }
}

/// (the scene × claim table, the per-ray-count details); `None` when the run measured none of the
/// claims (e.g. a spec without the paper's rows).
pub fn tables(data: &ReportInput) -> Option<(Table, Table)> {
    let all = all(data);
    if all.iter().all(|v| v.outcome == Outcome::NotMeasured) {
        return None;
    }
    let claims: Vec<Claim> = Claim::ALL
        .into_iter()
        .filter(|c| all.iter().any(|v| v.claim == *c && v.outcome != Outcome::NotMeasured))
        .collect();
    let mut header = vec!["scene".to_string()];
    header.extend(claims.iter().map(|c| c.label().to_string()));
    let rows = data
        .loaded
        .spec
        .scenes
        .iter()
        .map(|s| {
            let mut row = vec![s.name.clone()];
            for c in &claims {
                row.push(all.iter().find(|v| v.scene == s.name && v.claim == *c).map_or("–".into(), cell));
            }
            row
        })
        .collect();
    let n = data.loaded.spec.replicates as usize;
    let summary = Table {
        title: format!(
            "Verdict: the paper's claims on every scene (weakest margin over the ray counts, in standard \
             errors of the paired difference over {n} replicates; significant beyond ±{:.2} SE, Student's t \
             at {} % two-sided)",
            claims::critical_se(n),
            claims::ALPHA * 100.0
        ),
        header,
        rows,
    };
    let details = Table {
        title: "Verdict details: margin at every ray count".into(),
        header: ["scene", "claim", "verdict", "margins"].map(String::from).to_vec(),
        rows: all
            .iter()
            .filter(|v| v.outcome != Outcome::NotMeasured)
            .map(|v| {
                vec![v.scene.clone(), v.claim.label().into(), v.outcome.label().into(), v.detail.clone()]
            })
            .collect(),
    };
    Some((summary, details))
}

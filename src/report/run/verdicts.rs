//! The report's verdict table: each of the paper's claims on each scene of the run — holds, fails or
//! not significant family-wise (Holm over the table's cells at 1 %), with the per-cell verdict and
//! margin in standard errors of paired differences beside it — and, folded away at the end of the
//! page, the margins at every ray count. The claim logic is `compare::claims`'; this file picks the
//! ray counts the spec measured and formats the cells.

use crate::compare::claims::{self, Claim, Outcome, Verdict};
use crate::report::Table;
use crate::report::run::data::ReportInput;
use crate::spec::GroupKind;

/// Every claim on every scene of the spec, judged per cell and family-wise over all of them (the
/// table's cells are the family). Table claims use the ray counts of the `[[table]]`s that include
/// the scene; slope claims the ray counts of its first `[[convergence]]`. The claims are the
/// paper's, about AO: a scene measured for another integrand (`kitchen-visibility`) is judged by
/// `integrands`' own table instead, where "sine-cosine < uniform" is not what theory says.
pub fn all(data: &ReportInput) -> Vec<Verdict> {
    let spec = &data.loaded.spec;
    let mut out = Vec::new();
    let ao = |s: &&crate::spec::SceneRef| s.integrand == crate::sampling::Integrand::Ao;
    for (si, scene) in spec.scenes.iter().enumerate().filter(|(_, s)| ao(s)) {
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
    claims::family_wise(&mut out);
    out
}

/// "holds (+99.5 SE; Holm p 3e-7)", and the per-cell verdict where it differs: "not significant
/// (holds per cell, +6.1 SE; Holm p 0.03)".
fn cell(v: &Verdict) -> String {
    if v.outcome == Outcome::NotMeasured {
        return "–".into();
    }
    let per_cell =
        if v.family == v.outcome { String::new() } else { format!("{} per cell, ", v.outcome.label()) };
    format!("{} ({per_cell}{}; Holm p {})", v.family.label(), claims::fmt_se(v.margin_se), fmt_p(v.holm_p))
}

/// A p-value to two significant digits.
fn fmt_p(p: f64) -> String {
    if p >= 0.01 {
        format!("{p:.2}")
    } else if p > 0.0 {
        format!("{p:.1e}")
    } else {
        "0".into()
    }
}

/// One sentence for the page: how many cells hold family-wise against per cell, and at what level.
pub fn family_text(data: &ReportInput) -> Option<String> {
    let all = all(data);
    let measured = all.iter().filter(|v| v.outcome != Outcome::NotMeasured).count();
    if measured == 0 {
        return None;
    }
    let (per_cell, family) = claims::holding(&all);
    let fails = |f: fn(&Verdict) -> Outcome| all.iter().filter(|v| f(v) == Outcome::Fails).count();
    Some(format!(
        "Verdicts: {family} of the table's {measured} cells hold family-wise (Holm–Bonferroni over the \
         {measured} cells, family-wise level {a} %: the chance of any false verdict in the table is at most \
         that), {per_cell} per cell at {a} % each; {} fail family-wise, {} per cell.",
        fails(|v| v.family),
        fails(|v| v.outcome),
        a = claims::ALPHA * 100.0
    ))
}

/// (the scene × claim table, the per-ray-count details); `None` when the run measured none of the
/// claims (e.g. a spec without the paper's rows).
pub fn tables(data: &ReportInput) -> Option<(Table, Table)> {
    let all = all(data);
    if all.iter().all(|v| v.outcome == Outcome::NotMeasured) {
        return None;
    }
    let claims: Vec<Claim> = Claim::all()
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
        .filter(|s| s.integrand == crate::sampling::Integrand::Ao)
        .map(|s| {
            let mut row = vec![s.name.clone()];
            for c in &claims {
                row.push(all.iter().find(|v| v.scene == s.name && v.claim == *c).map_or("–".into(), cell));
            }
            row
        })
        .collect();
    let n = data.loaded.spec.replicates as usize;
    let m = all.iter().filter(|v| v.outcome != Outcome::NotMeasured).count();
    let summary = Table {
        title: format!(
            "Verdict: the paper's claims on every scene, family-wise at {a} % (Holm–Bonferroni over the table's \
             {m} cells: the chance of any false verdict in the table is at most {a} %), with the weakest margin \
             over the ray counts in standard errors of the paired difference over {n} replicates (per cell \
             significant beyond ±{:.2} SE, Student's t at {a} % two-sided) and Holm's adjusted p-value",
            claims::critical_se(n),
            a = claims::ALPHA * 100.0
        ),
        header,
        rows,
    };
    let details = Table {
        title: "Verdict details: margin at every ray count".into(),
        header: ["scene", "claim", "family-wise", "per cell", "cell p", "Holm p", "margins"]
            .map(String::from)
            .to_vec(),
        rows: all
            .iter()
            .filter(|v| v.outcome != Outcome::NotMeasured)
            .map(|v| {
                vec![
                    v.scene.clone(),
                    v.claim.label(),
                    v.family.label().into(),
                    v.outcome.label().into(),
                    fmt_p(v.p_value),
                    fmt_p(v.holm_p),
                    v.detail.clone(),
                ]
            })
            .collect(),
    };
    Some((summary, details))
}

//! The `integrands` axis in specs and plans: specs without it plan exactly what they
//! did (keys, reference estimators), each other integrand adds the scene again under its own name
//! with a reference of its own, and a bad name is refused with its line and what is allowed.

use hemilab::plan::{plan, reference_estimator};
use hemilab::results;
use hemilab::sampling::{Distribution, Integrand};
use hemilab::spec::parse_spec;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn spec_of(text: &str, path: &Path) -> hemilab::spec::Spec {
    parse_spec(text, path).unwrap_or_else(|e| panic!("{e}"))
}

/// Every shipped spec but integrands.toml has AO only, its job keys have no integrand in them and
/// its references the spec's estimator: a spec without the key names the same images as before.
#[test]
fn specs_without_the_key_plan_what_they_did() {
    for e in std::fs::read_dir(root().join("experiments")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "toml") || p.file_stem().unwrap() == "integrands" {
            continue;
        }
        let spec = spec_of(&std::fs::read_to_string(&p).unwrap(), &p);
        assert!(spec.scenes.iter().all(|s| s.integrand == Integrand::Ao), "{}", p.display());
        assert!(
            plan(&spec)
                .jobs
                .iter()
                .all(|j| j.measurement.integrand == Integrand::Ao && !j.canonical().contains("integrand"))
        );
        for si in 0..spec.scenes.len() {
            assert_eq!(reference_estimator(&spec, si), spec.reference.estimator);
        }
    }
    // Records written before the column existed read as AO.
    let text = std::fs::read_to_string(root().join("experiments/outputs/paper/results.json")).unwrap();
    let committed = results::from_json(&text).unwrap();
    assert!(!committed.is_empty() && committed.iter().all(|r| r.integrand == "ao"));
}

#[test]
fn each_other_integrand_is_the_scene_again_with_its_own_reference() {
    let p = root().join("experiments/integrands.toml");
    let text = std::fs::read_to_string(&p).unwrap();
    let spec = spec_of(&text, &p);
    let names: Vec<&str> = spec.scenes.iter().map(|s| s.name.as_str()).collect();
    assert_eq!(&names[..3], &["kitchen", "cornell-box", "terrain"]);
    assert!(names.contains(&"kitchen-visibility") && names.contains(&"terrain-cos-lobe-32"), "{names:?}");
    assert_eq!(names.len(), 12);
    for (si, s) in spec.scenes.iter().enumerate() {
        let want = match s.integrand {
            Integrand::Ao => spec.reference.estimator.distribution,
            i => i.matched_distribution(),
        };
        assert_eq!(reference_estimator(&spec, si).distribution, want, "{}", s.name);
    }
    let by_name = |n: &str| spec.scenes.iter().position(|s| s.name == n).unwrap();
    assert_eq!(reference_estimator(&spec, by_name("kitchen-visibility")).distribution, Distribution::Sine);
    assert_eq!(
        reference_estimator(&spec, by_name("kitchen-cos-lobe-32")).distribution,
        Distribution::Uniform
    );
    assert_eq!(
        reference_estimator(&spec, by_name("kitchen-cos-lobe-4")).distribution,
        Distribution::SineCosine
    );
    // The AO jobs are those of the same spec without the key.
    let full = plan(&spec);
    let line = text.lines().find(|l| l.starts_with("integrands = ")).unwrap();
    let bare_text = text.replace(line, "");
    let bare = plan(&spec_of(&bare_text, &p));
    let ao: Vec<String> =
        full.jobs.iter().filter(|j| j.measurement.integrand == Integrand::Ao).map(|j| j.key()).collect();
    let bare_table: Vec<String> =
        bare.jobs.iter().filter(|j| j.measurement.integrand == Integrand::Ao).map(|j| j.key()).collect();
    for k in &ao {
        assert!(bare_table.contains(k), "AO job {k} differs from the spec without `integrands`");
    }
    // Every other integrand's job has a key of its own.
    let mut keys: Vec<String> = full.jobs.iter().map(|j| j.key()).collect();
    let n = keys.len();
    keys.sort();
    keys.dedup();
    assert_eq!(keys.len(), n);
}

#[test]
fn a_bad_integrand_is_refused_with_its_line() {
    let text = "scenes = [\"../scenes/cornell-box.toml\"]\n[[table]]\nname = \"t\"\nrays = [8]\n\
                distributions = [\"sine\"]\nsequences = [\"random\"]\nintegrands = [\"ao\", \"cos-lobe-1\"]\n";
    let e = parse_spec(text, Path::new("experiments/bad.toml")).expect_err("refused").to_string();
    for part in ["experiments/bad.toml", "line 7", "integrands", "cos-lobe-1", "cos-lobe-N"] {
        assert!(e.contains(part), "expected {part:?} in {e}");
    }
}

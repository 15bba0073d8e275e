//! The README quotes only committed outputs, and those outputs are what the code makes of the
//! committed records: every `<!-- quote NAME -->` block of README.md is, byte for byte, the block of
//! that name in `experiments/outputs/<spec>/quotes.md`, which is rebuilt here from the same
//! directory's `results.json` and `timing.json`; and outside quoted blocks and code the README
//! states no measured number (no decimal fraction, no percentage). Editing a quoted number, or
//! typing a new one, fails this test. To refresh after a rerun
//! (`hemilab run experiments/paper.toml --out experiments/outputs/paper`, likewise `scenes`):
//! `cargo run --release --example readme_quotes`.

use hemilab::report::run::quotes::{self, Cost};
use hemilab::results;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every spec with committed outputs: (spec name, its outputs directory).
fn committed() -> Vec<(String, PathBuf)> {
    let dir = root().join("experiments/outputs");
    let mut v: Vec<(String, PathBuf)> = std::fs::read_dir(&dir)
        .expect("experiments/outputs")
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("quotes.md").exists())
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), p))
        .collect();
    v.sort();
    v
}

fn rebuilt(name: &str, out: &Path) -> String {
    let spec_path = root().join(format!("experiments/{name}.toml"));
    let spec = hemilab::spec::parse_spec(&std::fs::read_to_string(&spec_path).unwrap(), &spec_path)
        .unwrap_or_else(|e| panic!("{}: {e}", spec_path.display()));
    let records = results::from_json(&std::fs::read_to_string(out.join("results.json")).unwrap()).unwrap();
    let timing =
        hemilab::timing::RunTiming::from_json(&std::fs::read_to_string(out.join("timing.json")).unwrap())
            .unwrap();
    quotes::quotes(&spec, &records, Some(Cost::of(&timing.session, records.len())))
}

#[test]
fn committed_quotes_are_what_the_code_makes_of_the_committed_records() {
    let all = committed();
    assert!(all.iter().any(|(n, _)| n == "paper"), "experiments/outputs/paper is committed");
    for (name, out) in all {
        let committed = std::fs::read_to_string(out.join("quotes.md")).unwrap();
        assert_eq!(
            committed,
            rebuilt(&name, &out),
            "{}: quotes.md is not what its records give",
            out.display()
        );
    }
}

#[test]
fn every_readme_quote_is_a_committed_quote() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let mut known = Vec::new();
    for (_, out) in committed() {
        known.extend(quotes::blocks(&std::fs::read_to_string(out.join("quotes.md")).unwrap()));
    }
    let quoted = quotes::blocks(&readme);
    assert!(quoted.len() >= 3, "the README quotes its results ({} blocks)", quoted.len());
    for (name, text) in quoted {
        let Some((_, want)) = known.iter().find(|(n, _)| *n == name) else {
            panic!("README quotes '{name}', which no committed quotes.md holds")
        };
        assert_eq!(
            &text, want,
            "README's quote '{name}' differs from the committed one: run the readme_quotes example"
        );
    }
}

/// The README without its quoted blocks, fenced code and inline code.
fn prose(readme: &str) -> String {
    let mut s = readme.to_string();
    for (_, b) in quotes::blocks(readme) {
        s = s.replace(&b, "");
    }
    let mut out = String::new();
    let mut fenced = false;
    for line in s.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced {
            let mut inline = false;
            for part in line.split('`') {
                if !inline {
                    out.push_str(part);
                }
                inline = !inline;
            }
            out.push('\n');
        }
    }
    out
}

#[test]
fn the_readme_types_no_measured_number() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let text = prose(&readme);
    let mut found = Vec::new();
    for line in text.lines() {
        let b = line.as_bytes();
        for k in 0..b.len() {
            let digit = |j: usize| j < b.len() && b[j].is_ascii_digit();
            let fraction = b[k] == b'.' && k > 0 && digit(k - 1) && digit(k + 1);
            let percent =
                b[k] == b'%' && k > 0 && (digit(k - 1) || (b[k - 1] == b' ' && k > 1 && digit(k - 2)));
            if fraction || percent {
                found.push(line.trim().to_string());
                break;
            }
        }
    }
    assert!(
        found.is_empty(),
        "numbers typed into the README (quote them from committed outputs, or move them to docs/):\n{}",
        found.join("\n")
    );
}

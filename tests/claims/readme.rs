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

/// The README's quoted blocks and those of the docs/ pages it moved them to.
#[test]
fn every_readme_quote_is_a_committed_quote() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let mut known = Vec::new();
    for (_, out) in committed() {
        known.extend(quotes::blocks(&std::fs::read_to_string(out.join("quotes.md")).unwrap()));
    }
    let quoted = quotes::blocks(&readme);
    assert!(quoted.len() >= 3, "the README quotes its results ({} blocks)", quoted.len());
    let mut pages = vec![("README.md".to_string(), readme.clone())];
    for e in std::fs::read_dir(root().join("docs")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "md") {
            let name = format!("docs/{}", p.file_name().unwrap().to_string_lossy());
            pages.push((name, std::fs::read_to_string(&p).unwrap()));
        }
    }
    for (page, body) in pages {
        for (name, text) in quotes::blocks(&body) {
            let Some((_, want)) = known.iter().find(|(n, _)| *n == name) else {
                panic!("{page} quotes '{name}', which no committed quotes.md holds")
            };
            assert_eq!(
                &text, want,
                "{page}'s quote '{name}' differs from the committed one: run the readme_quotes example"
            );
        }
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

/// The backticked module names (`name/` or `name.rs`) of the README's table "How the code is laid
/// out".
fn layout_names(readme: &str) -> Vec<String> {
    let start = readme.find("## How the code is laid out").expect("the README has its layout section");
    let section = &readme[start..];
    let end = section[3..].find("\n## ").map_or(section.len(), |i| i + 3);
    let mut names = Vec::new();
    for row in section[..end].lines().filter(|l| l.starts_with('|')) {
        for (i, part) in row.split('`').enumerate() {
            let module = part.strip_suffix('/').or_else(|| part.strip_suffix(".rs"));
            let plain = module
                .is_some_and(|m| !m.is_empty() && m.chars().all(|c| c.is_ascii_lowercase() || c == '_'));
            if i % 2 == 1 && plain {
                names.push(part.to_string());
            }
        }
    }
    names
}

/// Every file and directory below `dir`, as `name/` or `name.rs`, with its depth (0: top level).
fn tree(dir: &Path, depth: usize, out: &mut Vec<(usize, String)>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if p.is_dir() {
            out.push((depth, format!("{name}/")));
            tree(&p, depth + 1, out);
        } else if name.ends_with(".rs") {
            out.push((depth, name));
        }
    }
}

/// The README's layout table and `src/` agree both ways: every top-level module of `src/` (file
/// or directory) is in the table, and every module the table names exists in `src/` (at the top
/// level or inside a stage's directory) — a module added, moved or renamed fails here until the
/// table says so.
#[test]
fn the_readme_layout_table_matches_src() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let named = layout_names(&readme);
    let mut all = Vec::new();
    tree(&root().join("src"), 0, &mut all);
    let unnamed: Vec<&String> =
        all.iter().filter(|(d, n)| *d == 0 && !named.contains(n)).map(|(_, n)| n).collect();
    let absent: Vec<&String> = named.iter().filter(|n| !all.iter().any(|(_, m)| m == *n)).collect();
    assert!(
        unnamed.is_empty() && absent.is_empty(),
        "README's layout table: src/ has {unnamed:?} that it does not name; it names {absent:?} that src/ does not have"
    );
}

/// docs/scenes.md counts the scenes of `scenes/` in words, and the count is right.
#[test]
fn docs_scenes_counts_the_committed_scenes() {
    let n = std::fs::read_dir(root().join("scenes"))
        .unwrap()
        .filter(|e| e.as_ref().unwrap().path().extension().is_some_and(|x| x == "toml"))
        .count();
    let words = [
        "zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten", "eleven",
        "twelve",
    ];
    let word = words[n];
    let text = std::fs::read_to_string(root().join("docs/scenes.md")).unwrap();
    let title = text.lines().next().unwrap();
    assert!(
        title.to_lowercase().contains(word),
        "docs/scenes.md's title says {title:?}; scenes/ has {n} scenes"
    );
    for w in words.iter().enumerate().filter(|(i, _)| *i != n).map(|(_, w)| w) {
        let stale = format!("{w} scenes of `scenes/`");
        assert!(!text.to_lowercase().contains(&stale), "docs/scenes.md says '{stale}'; scenes/ has {n}");
    }
}

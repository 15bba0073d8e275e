//! The README's command reference and `--help` name the same options: a newcomer found
//! `render --quiet`, `bench --resolution` and `points --seed` in one and not the other.

use std::process::Command;

const COMMANDS: &[&str] = &["run", "plan", "reference", "merge", "render", "bench", "points", "advise"];

/// The long options `hemilab CMD --help` lists (but --help and --version).
fn help_options(cmd: &str) -> Vec<String> {
    let out = Command::new(env!("CARGO_BIN_EXE_hemilab")).args([cmd, "--help"]).output().unwrap();
    assert!(out.status.success(), "hemilab {cmd} --help failed");
    let text = String::from_utf8(out.stdout).unwrap();
    let mut opts: Vec<String> = text
        .lines()
        .filter_map(|l| {
            let l = l.trim_start();
            let l = l
                .strip_prefix('-')
                .filter(|r| !r.starts_with('-'))
                .map_or(l, |r| &r[r.find("--").unwrap_or(0)..]);
            l.strip_prefix("--").map(|r| {
                format!("--{}", r.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-')).next().unwrap())
            })
        })
        .filter(|o| o != "--help" && o != "--version")
        .collect();
    opts.sort();
    opts.dedup();
    opts
}

/// The long options in the usage cells of the README's command-reference rows for `hemilab CMD`
/// (a command may have several rows, e.g. `run` and `run --shard`).
fn readme_options(readme: &str, cmd: &str) -> Vec<String> {
    let prefix = format!("| `hemilab {cmd} ");
    let rows: Vec<&str> = readme.lines().filter(|l| l.starts_with(&prefix)).collect();
    assert!(!rows.is_empty(), "README has no row for {cmd}");
    let mut opts: Vec<String> = rows
        .iter()
        .flat_map(|row| {
            // The usage part only: the first cell (a `\|` inside it is an escaped bar, not a cell end).
            let usage = row.replace("\\|", "/");
            let usage = usage.split(" | ").next().unwrap().to_string();
            usage
                .match_indices("--")
                .map(|(i, _)| {
                    let r = &usage[i + 2..];
                    format!(
                        "--{}",
                        r.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-')).next().unwrap()
                    )
                })
                .collect::<Vec<_>>()
        })
        .filter(|o| o.len() > 2)
        .collect();
    opts.sort();
    opts.dedup();
    opts
}

#[test]
fn every_help_option_is_in_the_readme_and_back() {
    let readme = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    for cmd in COMMANDS {
        let (help, doc) = (help_options(cmd), readme_options(&readme, cmd));
        let missing: Vec<_> = help.iter().filter(|o| !doc.contains(o)).collect();
        let stale: Vec<_> = doc.iter().filter(|o| !help.contains(o)).collect();
        assert!(
            missing.is_empty() && stale.is_empty(),
            "hemilab {cmd}: in --help only {missing:?}, in README only {stale:?}"
        );
    }
}

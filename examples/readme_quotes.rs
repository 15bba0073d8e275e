//! Refreshes the numbers the README quotes, after a rerun of a spec into `experiments/outputs/<spec>/`
//! (`hemilab run experiments/paper.toml --out experiments/outputs/paper`):
//! `cargo run --release --example readme_quotes`. For every such directory, its `quotes.md` is made
//! again from its `results.json` and `timing.json` (as `tests/claims/readme.rs` does); then every
//! `<!-- quote NAME -->` block of README.md and of the docs/ pages is replaced by the block of that name (a name no quotes
//! file holds is an error), and the figures in `experiments/figures/` are copied from the runs.

use hemilab::report::run::quotes::{self, Cost};
use hemilab::{io, results, spec};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut known = Vec::new();
    for e in std::fs::read_dir(root.join("experiments/outputs"))? {
        let out = e?.path();
        if !out.join("results.json").exists() {
            continue;
        }
        let name = out.file_name().ok_or("a directory name")?.to_string_lossy().into_owned();
        let spec_path = root.join(format!("experiments/{name}.toml"));
        let spec = spec::parse_spec(&io::read_string(&spec_path)?, &spec_path)?;
        let records = results::from_json(&io::read_string(&out.join("results.json"))?)?;
        let timing = hemilab::timing::RunTiming::from_json(&io::read_string(&out.join("timing.json"))?)?;
        let text = quotes::quotes(&spec, &records, Some(Cost::of(&timing.session, records.len())));
        io::write_atomic(&out.join("quotes.md"), text.as_bytes())?;
        known.extend(quotes::blocks(&text));
    }
    // The README and the docs/ pages it moved blocks to.
    let mut pages = vec![root.join("README.md")];
    for e in std::fs::read_dir(root.join("docs"))? {
        let p = e?.path();
        if p.extension().is_some_and(|x| x == "md") {
            pages.push(p);
        }
    }
    for path in pages {
        let mut page = io::read_string(&path)?;
        let mut changed = 0;
        for (name, old) in quotes::blocks(&page.clone()) {
            let new =
                &known.iter().find(|(n, _)| *n == name).ok_or(format!("no committed quote '{name}'"))?.1;
            if *new != old {
                page = page.replace(&old, new);
                changed += 1;
            }
        }
        if changed > 0 {
            io::write_atomic(&path, page.as_bytes())?;
        }
        println!("{}: {changed} quoted blocks refreshed", path.display());
    }
    // The figures the README shows, from the same runs: `experiments/figures/NAME.png` is the
    // paper run's `NAME.png`, and `SPEC_NAME.png` another spec's `NAME.png`.
    let figures = root.join("experiments/figures");
    let mut copied = 0;
    for e in std::fs::read_dir(&figures)? {
        let file = e?.file_name().to_string_lossy().into_owned();
        if !file.ends_with(".png") {
            continue;
        }
        let outputs = root.join("experiments/outputs");
        let from = match file.split_once('_') {
            Some((spec, rest)) if outputs.join(spec).join(rest).exists() => outputs.join(spec).join(rest),
            _ => outputs.join("paper").join(&file),
        };
        if from.exists() {
            io::write_atomic(&figures.join(&file), &io::read_bytes(&from)?)?;
            copied += 1;
        }
    }
    println!("{}: {copied} figures copied from the runs' outputs", figures.display());
    Ok(())
}

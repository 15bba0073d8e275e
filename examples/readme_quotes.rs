//! Copies the quoted blocks of README.md from the committed outputs, after a rerun of a spec into
//! `experiments/outputs/<spec>/` (`hemilab run experiments/paper.toml --out experiments/outputs/paper`):
//! `cargo run --release --example readme_quotes`. Every `<!-- quote NAME -->` block of the README
//! is replaced by the block of that name in `experiments/outputs/*/quotes.md`; a name no quotes
//! file holds is an error. `tests/claims/readme.rs` checks the result.

use hemilab::report::run::quotes;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut known = Vec::new();
    for e in std::fs::read_dir(root.join("experiments/outputs"))? {
        let q = e?.path().join("quotes.md");
        if q.exists() {
            known.extend(quotes::blocks(&std::fs::read_to_string(q)?));
        }
    }
    let path = root.join("README.md");
    let mut readme = std::fs::read_to_string(&path)?;
    let mut changed = 0;
    for (name, old) in quotes::blocks(&readme.clone()) {
        let new = &known.iter().find(|(n, _)| *n == name).ok_or(format!("no committed quote '{name}'"))?.1;
        if *new != old {
            readme = readme.replace(&old, new);
            changed += 1;
        }
    }
    hemilab::io::write_atomic(&path, readme.as_bytes())?;
    println!("{}: {changed} quoted blocks refreshed", path.display());
    Ok(())
}

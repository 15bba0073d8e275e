//! One-off migration: adds the `pixels` hash (`hemilab::reference::pixel_hash`) to every reference
//! manifest in a directory that lacks it, every other byte of the manifest and every byte of the
//! image kept. `cargo run --release --example reference_hashes -- reference` was run once on the
//! committed references; `tests/stages/reference_hashes.rs` checks each committed manifest against
//! `reference::store::with_pixel_hash`, so a reference edited later is refused, not migrated.

fn main() {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "reference".into());
    let mut changed = 0;
    for json in hemilab::io::list_dir(std::path::Path::new(&dir)).expect("a readable directory") {
        if json.extension().is_none_or(|e| e != "json") || !json.with_extension("exr").exists() {
            continue;
        }
        let text = std::fs::read_to_string(&json).expect("a readable manifest");
        let new = hemilab::reference::store::with_pixel_hash(&json).unwrap_or_else(|e| panic!("{e}"));
        if new != text {
            hemilab::io::write_atomic(&json, new.as_bytes()).expect("write the manifest");
            changed += 1;
        }
    }
    println!("{changed} manifest(s) in {dir} given their pixel hash");
}

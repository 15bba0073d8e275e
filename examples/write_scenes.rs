//! Writes the procedural meshes of `scenes/` (atrium, slats, terrain) as plain OBJ into a directory:
//! `cargo run --release --example write_scenes -- /tmp/scenes`, then compress each by hand with
//! `zstd -19 --rm X.obj -o scenes/X.obj.zst` (hemilab only *reads* zstd). `tests/stages/scene_files.rs`
//! checks that the committed meshes are exactly what `hemilab::scene::generate` writes. The foliage
//! scene is written as glTF (`foliage.gltf`, its `foliage.bin` and the leaf PNG), ready
//! to copy to scenes/ as it is (`tests/stages/scene_alpha.rs` checks it against
//! `hemilab::scene::foliage`).

use hemilab::scene::generate;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "/tmp/scenes".into()));
    for (name, text) in
        [("atrium", generate::atrium()), ("slats", generate::slats()), ("terrain", generate::terrain())]
    {
        let path = dir.join(format!("{name}.obj"));
        hemilab::io::write_atomic(&path, text.as_bytes())?;
        println!("{}: {} bytes", path.display(), text.len());
    }
    let (json, bin) = hemilab::scene::foliage::foliage().to_gltf("foliage.bin");
    hemilab::io::write_atomic(&dir.join("foliage.gltf"), json.as_bytes())?;
    hemilab::io::write_atomic(&dir.join("foliage.bin"), &bin)?;
    let png = hemilab::scene::foliage::leaf_png();
    hemilab::io::write_atomic(&dir.join(hemilab::scene::foliage::LEAF_PNG), &png)?;
    println!("{}: {} + {} bytes", dir.join("foliage.gltf").display(), json.len(), bin.len());
    Ok(())
}

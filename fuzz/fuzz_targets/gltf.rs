//! A `.gltf` or `.glb` file, its external files refused: read, or one error; a panic inside the
//! `gltf` crate that `scene::gltf_check` missed shows as "reader failed", which counts as a find.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let mut fetch = |uri: &str| Err(format!("no file '{uri}' while fuzzing"));
    if let Err(e) = hemilab::scene::gltf_mesh::parse_gltf(data, &mut fetch) {
        assert!(!e.contains("reader failed") && !e.contains('\n'), "{e}");
    }
});

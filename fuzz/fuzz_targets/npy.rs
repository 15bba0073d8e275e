//! A point set as an `.npy` file: read, or one error naming the file.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("hemilab-fuzz-npy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("p.npy"), data).unwrap();
    if let Err(e) = hemilab::load::points::points(&dir, "p.npy") {
        assert!(!e.contains('\n'), "{e}");
    }
});

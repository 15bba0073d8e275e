//! A noise texture (the bytes as a PNG on even first bytes, else as an EXR), read for each use.
#![no_main]

use hemilab::sampling::texture::TextureUse;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("hemilab-fuzz-texture-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let name = if data.first().is_some_and(|b| b % 2 == 0) { "t.png" } else { "t.exr" };
    std::fs::write(dir.join(name), data).unwrap();
    for use_ in TextureUse::ALL {
        if let Err(e) = hemilab::load::texture::texture(&dir, name, use_) {
            assert!(!e.contains("reader failed") && !e.contains('\n'), "{e}");
        }
    }
});

//! An experiment spec (TOML): read, or errors that each name a line or a key.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let _ = hemilab::spec::parse_spec(text, std::path::Path::new("fuzz.toml"));
});

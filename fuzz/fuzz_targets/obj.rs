//! A Wavefront OBJ (or zstd-compressed OBJ): read, or one error naming the line.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = hemilab::scene::mesh::parse_obj(data);
});

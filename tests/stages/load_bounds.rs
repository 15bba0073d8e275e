//! The readers of the files a spec names (noise textures, point sets) take only what a file's
//! header promises and a stated maximum allows: a pattern padded to a width no name could have, an
//! `.npy` whose shape overflows, a device that never ends are each one error naming the file, never
//! a panic, an abort or a read that does not return. And the smaller promises: `%5d` pads with
//! spaces as printf does, a word after the file that is not a use says which uses there are, and an
//! EXR value outside [0, 1] is refused as docs/textures.md says.

use super::support::common::Tmp;
use hemilab::image::{Channel, Image, encode_exr};
use hemilab::load::points::points;
use hemilab::load::texture::texture;
use hemilab::sampling::texture::TextureUse;

fn grey(t: &Tmp, name: &str) {
    image::GrayImage::from_fn(4, 4, |x, y| image::Luma([(x * 64 + y * 16) as u8]))
        .save(t.path(name))
        .unwrap();
}

#[test]
fn a_pattern_wider_than_any_slice_number_is_refused() {
    let t = Tmp::new("bounds-width");
    for written in ["s_%099999999999d.png", "s_%10d.png", "s_%-5d.png", "s_%+d.png"] {
        let e = texture(&t, written, TextureUse::Offset).unwrap_err();
        assert!(e.contains(&format!("texture pattern '{written}'")) && e.contains("N up to 9"), "{e}");
    }
}

#[test]
fn a_width_pads_with_spaces_and_a_zero_width_with_zeros() {
    let t = Tmp::new("bounds-pad");
    for k in 0..3 {
        grey(&t, &format!("sp_{k:>3}.png"));
        grey(&t, &format!("zp_{k:03}.png"));
    }
    for written in ["sp_%3d.png", "zp_%03d.png"] {
        texture(&t, written, TextureUse::Offset).unwrap_or_else(|e| panic!("{written}: {e}"));
    }
    // Space-padded files are not read by a zero-padded pattern, nor the other way round.
    let e = texture(&t, "sp_%03d.png", TextureUse::Offset).unwrap_err();
    assert!(e.contains("matches no file"), "{e}");
    let e = texture(&t, "zp_%3d.png", TextureUse::Offset).unwrap_err();
    assert!(e.contains("matches no file"), "{e}");
}

#[test]
fn a_word_after_the_file_that_is_not_a_use_lists_the_uses() {
    let t = Tmp::new("bounds-use");
    grey(&t, "t.png");
    let e = texture(&t, "t.png:diagonal", TextureUse::Offset).unwrap_err();
    assert!(e.contains("unknown texture use 'diagonal'") && e.contains("offset, rotation, vector"), "{e}");
    assert!(!e.contains("not found"), "{e}");
    // Through the command-line form too (an absolute path).
    let e = hemilab::load::texture_arg(&format!("texture:{}", t.path("t.png:diagonal").display()))
        .unwrap_err()
        .to_string();
    assert!(e.contains("unknown texture use 'diagonal'"), "{e}");
}

#[test]
fn devices_are_refused_not_read_forever() {
    let root = std::path::Path::new("/");
    let e = texture(root, "dev/zero", TextureUse::Offset).unwrap_err();
    assert!(e.contains("/dev/zero") && e.contains("not a regular file"), "{e}");
    let e = points(root, "dev/zero").unwrap_err();
    assert!(e.contains("/dev/zero") && e.contains("not a regular file"), "{e}");
    let e = hemilab::load::load_scene(std::path::Path::new("/dev/zero")).err().unwrap().to_string();
    assert!(e.contains("/dev/zero"), "{e}");
}

/// An `.npy` of `shape` (header only, with `data` bytes after it).
fn npy(shape: &str, data: usize) -> Vec<u8> {
    let mut header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut b = b"\x93NUMPY\x01\x00".to_vec();
    b.extend((header.len() as u16).to_le_bytes());
    b.extend(header.as_bytes());
    b.extend(std::iter::repeat_n(0u8, data));
    b
}

#[test]
fn an_npy_shape_beyond_its_bytes_is_refused_before_allocating() {
    let t = Tmp::new("bounds-npy");
    let huge = 1u64 << 62;
    for (shape, phrase) in [
        (format!("({huge}, 2)"), "needs more than 2^64".to_string()),
        (format!("(2, {huge}, 2)"), "needs more than 2^64".to_string()),
        ("(1000, 2)".to_string(), "holds 64 bytes of data, its shape [1000, 2] needs 16000".to_string()),
        ("(3, x, 2)".to_string(), "has 'x', not a size".to_string()),
    ] {
        std::fs::write(t.path("p.npy"), npy(&shape, 64)).unwrap();
        let e = points(&t, "p.npy").unwrap_err();
        assert!(e.contains("p.npy") && e.contains(&phrase), "{shape}: {e}");
    }
    std::fs::write(t.path("p.npy"), npy("(4, 2)", 64)).unwrap();
    points(&t, "p.npy").unwrap();
}

#[test]
fn exr_values_outside_zero_to_one_are_refused_as_the_docs_say() {
    let t = Tmp::new("bounds-exr");
    let docs = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/textures.md")).unwrap();
    assert!(docs.contains("is refused with the file and texel, not taken mod 1"));
    for (bad, ok) in [(1.5f32, false), (-0.25, false), (1.0, true), (0.0, true)] {
        let mut v: Vec<f32> = (0..16).map(|i| i as f32 / 16.0).collect();
        v[5] = bad;
        let img = Image::from_vec(4, 4, v);
        std::fs::write(t.path("v.exr"), encode_exr(&[Channel { name: "Y", image: &img }]).unwrap()).unwrap();
        match texture(&t, "v.exr", TextureUse::Rotation) {
            Ok(_) => assert!(ok, "{bad} accepted"),
            Err(e) => {
                assert!(!ok, "{bad}: {e}");
                assert!(
                    e.contains("v.exr") && e.contains("texel (1, 1)") && e.contains("outside [0, 1]"),
                    "{e}"
                );
            }
        }
    }
}

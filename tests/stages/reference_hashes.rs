//! Every committed reference is content-addressed: its manifest's `pixels` is the hash of its
//! image (`reference::pixel_hash`), every value finite, and the manifest is exactly what the
//! one-off migration (`examples/reference_hashes.rs`, `store::with_pixel_hash`) makes of it, so
//! the migration changed nothing but that key; and the hash sees any change of any pixel.

use hemilab::image::Image;
use hemilab::reference::{Manifest, pixel_hash, store};
use std::path::Path;

#[test]
fn every_committed_reference_carries_the_hash_of_its_pixels() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("reference");
    let mut checked = 0;
    for json in hemilab::io::list_dir(&dir).unwrap() {
        if json.extension().is_none_or(|e| e != "json") {
            continue;
        }
        let text = std::fs::read_to_string(&json).unwrap();
        let m = Manifest::from_json(&text).unwrap();
        let hash = m.pixels.as_deref().unwrap_or_else(|| panic!("{}: no pixels hash", json.display()));
        assert!(hash.starts_with("fnv1a64:") && hash.len() == 8 + 16, "{hash}");
        let again = store::with_pixel_hash(&json).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(again, text, "{}: the manifest is what the migration makes of it", json.display());
        checked += 1;
    }
    assert!(checked >= 60, "{checked} committed references");
}

#[test]
fn the_pixel_hash_sees_every_change() {
    let y = Image::from_vec(3, 2, vec![0.0, 0.25, 0.5, 0.75, 1.0, 0.5]);
    let se = Image::from_vec(3, 2, vec![0.01; 6]);
    let a = Image::from_vec(3, 2, vec![1.0, 1.0, 1.0, 1.0, 1.0, 0.0]);
    let h = pixel_hash(&y, &se, &a);
    assert_eq!(h, pixel_hash(&y.clone(), &se.clone(), &a.clone()), "deterministic");
    let mut changed = Vec::new();
    for i in 0..6 {
        let mut y2 = y.clone();
        y2.data[i] = f32::from_bits(y2.data[i].to_bits() ^ 1);
        changed.push(pixel_hash(&y2, &se, &a));
        let mut a2 = a.clone();
        a2.data[i] = 0.5;
        changed.push(pixel_hash(&y, &se, &a2));
    }
    // The same values in another shape, or channels swapped, are another image.
    changed.push(pixel_hash(
        &Image::from_vec(2, 3, y.data.clone()),
        &Image::from_vec(2, 3, se.data.clone()),
        &Image::from_vec(2, 3, a.data.clone()),
    ));
    changed.push(pixel_hash(&se, &y, &a));
    for c in &changed {
        assert_ne!(*c, h);
    }
}

//! The wall in front of the `gltf` crate (`scene::gltf_check`, `scene::guard`): each glTF file that
//! once panicked inside the crate, aborted on an allocation or looped forever is one error naming
//! the object at fault, and the checks, not the last-line panic catcher, find it.

use super::support::common::Tmp;
use super::support::gltf_ext::masked_square;
use hemilab::load::load_scene;
use hemilab::scene::gltf_mesh::parse_gltf;
use hemilab::scene::gltf_write::{glb, meshopt_compress, quantize};
use serde_json::{Value, json};

/// Looking straight down at the unit square [0, 1]² (z = 0) from z = 3.
const SCENE: &str = "mesh = \"m.glb\"\nresolution = [32, 24]\nao_distance = 1.0\n[camera.perspective]\n\
    eye = [0.5, 0.5, 3.0]\ntarget = [0.5, 0.5, 0.0]\nup = [0.0, 1.0, 0.0]\nfov_y_deg = 45.0\n";

/// `parse_gltf` of the masked square with its JSON changed by `edit`: the error.
fn refused(edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> String {
    let (mut doc, mut bin) = masked_square().encode(None);
    edit(&mut doc, &mut bin);
    let mut fetch = |uri: &str| Err(format!("no file '{uri}' here"));
    match parse_gltf(&glb(&doc, &bin), &mut fetch) {
        Ok(_) => panic!("accepted: {doc}"),
        Err(e) => {
            // The checks found it: the crate never panicked.
            assert!(!e.contains("reader failed"), "caught as a panic, not checked: {e}");
            assert_eq!(e.lines().count(), 1, "{e}");
            e
        }
    }
}

fn expect(e: &str, phrase: &str) {
    assert!(e.contains(phrase), "'{e}' lacks '{phrase}'");
}

#[test]
fn an_indices_accessor_of_floats_is_refused() {
    let e = refused(|doc, _| {
        let a = doc["meshes"][1]["primitives"][0]["indices"].as_u64().unwrap() as usize;
        doc["accessors"][a]["componentType"] = json!(5126);
    });
    expect(&e, "indices: accessors[");
    expect(&e, "UNSIGNED_BYTE (5121), UNSIGNED_SHORT (5123) or UNSIGNED_INT (5125)");
}

#[test]
fn a_camera_whose_type_does_not_match_its_object_is_refused() {
    for (kind, other) in [("orthographic", "perspective"), ("perspective", "orthographic")] {
        let e = refused(|doc, _| {
            let object = if other == "perspective" {
                json!({"yfov": 0.8, "znear": 0.1})
            } else {
                json!({"xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 10.0})
            };
            doc["cameras"] = json!([{"type": kind, other: object}]);
            doc["nodes"][0]["camera"] = json!(0);
        });
        expect(&e, &format!("cameras[0]: its `type` is \"{kind}\" but it has no `{kind}` object"));
    }
}

#[test]
fn quantized_positions_with_a_stride_below_the_element_are_refused() {
    let e = refused(|doc, bin| {
        quantize(doc, bin, "POSITION", 5122, false); // SHORT VEC3: 6 bytes
        let a = doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"].as_u64().unwrap() as usize;
        let v = doc["accessors"][a]["bufferView"].as_u64().unwrap() as usize;
        doc["bufferViews"][v]["byteStride"] = json!(4);
    });
    expect(&e, "byteStride 4 is smaller than one element (6 bytes)");
}

#[test]
fn a_primitive_naming_accessors_in_a_file_without_them_is_refused() {
    let e = refused(|doc, _| {
        doc.as_object_mut().unwrap().remove("accessors");
    });
    expect(&e, "meshes[0].primitives[0].attributes.");
    expect(&e, "no `accessors` array");
}

#[test]
fn an_image_with_neither_uri_nor_buffer_view_is_refused() {
    let e = refused(|doc, _| doc["images"][0] = json!({"mimeType": "image/png"}));
    expect(&e, "images[0]: has neither a `uri` nor a `bufferView`");
    let e = refused(|doc, _| {
        doc["images"][0].as_object_mut().unwrap().remove("mimeType");
    });
    expect(&e, "images[0]: an image in a `bufferView` needs its `mimeType`");
}

#[test]
fn a_meshopt_view_claiming_two_to_the_31_elements_is_refused_before_decoding() {
    let e = refused(|doc, bin| {
        *bin = meshopt_compress(doc, bin, false);
        let views = doc["bufferViews"].as_array_mut().unwrap();
        let v = views.iter_mut().find(|v| v["extensions"]["EXT_meshopt_compression"].is_object()).unwrap();
        v["extensions"]["EXT_meshopt_compression"]["count"] = json!(1u64 << 31);
    });
    expect(&e, "EXT_meshopt_compression: decodes to 2147483648 x");
    // A fallback buffer that claims 2^40 bytes is not allocated.
    let e = refused(|doc, bin| {
        *bin = meshopt_compress(doc, bin, false);
        let buffers = doc["buffers"].as_array_mut().unwrap();
        let b = buffers.iter_mut().find(|b| b["extensions"]["EXT_meshopt_compression"]["fallback"] == true);
        b.unwrap()["byteLength"] = json!(1u64 << 40);
    });
    expect(&e, "fallback buffer of 1099511627776 bytes");
}

#[test]
fn a_cycle_among_nodes_is_refused_not_walked() {
    let e = refused(|doc, _| doc["nodes"][0]["children"] = json!([0]));
    expect(&e, "nodes: a cycle among `children` (0 → 0)");
    let e = refused(|doc, _| {
        doc["nodes"][0]["children"] = json!([1]);
        doc["nodes"][1]["children"] = json!([0]);
    });
    expect(&e, "a cycle among `children`");
    let e = refused(|doc, _| {
        doc["nodes"].as_array_mut().unwrap().push(json!({"children": [1]}));
        doc["nodes"][0]["children"] = json!([1]);
    });
    expect(&e, "nodes[1] is a child of nodes[0] and nodes[2]");
}

#[test]
fn an_alpha_cutoff_outside_zero_to_one_names_the_material() {
    for cutoff in [-1.0, 2.0] {
        let e = refused(|doc, _| doc["materials"][0]["alphaCutoff"] = json!(cutoff));
        expect(&e, "materials[0]: alphaCutoff");
        expect(&e, "is outside [0, 1]");
    }
}

#[test]
fn accessors_and_views_beyond_their_data_are_refused() {
    let e = refused(|doc, _| doc["accessors"][0]["count"] = json!(1u64 << 40));
    expect(&e, "accessors[0] (bufferViews[");
    let e = refused(|doc, _| doc["bufferViews"][0]["byteLength"] = json!(u64::MAX));
    expect(&e, "bufferViews[0]: bytes");
    let e = refused(|doc, _| doc["accessors"][0]["count"] = json!(0));
    expect(&e, "accessors[0]: `count` is 0");
}

/// The files a glTF names are read as the OBJ's are: a device is refused, not read forever.
#[test]
fn a_buffer_uri_naming_a_device_is_refused() {
    let t = Tmp::new("gltf-dev-zero");
    let (json, _) = masked_square().to_gltf("/dev/zero");
    std::fs::write(t.path("m.gltf"), json).unwrap();
    std::fs::write(t.path("s.toml"), SCENE.replace("m.glb", "m.gltf")).unwrap();
    let e = load_scene(&t.path("s.toml")).err().unwrap().to_string();
    assert!(e.contains("/dev/zero") && e.contains("not a regular file"), "{e}");
}

/// A GLB header whose declared length is under its own 12 bytes (the cargo-fuzz `gltf` target's find:
/// the crate subtracts unchecked), or longer than the file, or of another version: one error each.
#[test]
fn a_glb_header_that_does_not_hold_is_refused() {
    let mut fetch = |uri: &str| Err(format!("no file '{uri}' here"));
    let (doc, bin) = masked_square().encode(None);
    let good = glb(&doc, &bin);
    let with = |version: u32, length: u32| {
        let mut b = good.clone();
        b[4..8].copy_from_slice(&version.to_le_bytes());
        b[8..12].copy_from_slice(&length.to_le_bytes());
        b
    };
    let fuzzed = b"glTF\n\0\0\0\0\0\0\0{".to_vec();
    let n = good.len() as u32;
    for (bytes, phrase) in [
        (fuzzed, "GLB version 10"),
        (with(2, 0), "declares 0 bytes"),
        (with(2, 11), "declares 11 bytes"),
        (with(2, n + 1), &format!("declares {} bytes", n + 1) as &str),
        (with(1, n), "GLB version 1"),
        (b"glTF\x02\0".to_vec(), "a GLB header is 12 bytes"),
    ] {
        let e = parse_gltf(&bytes, &mut fetch).err().expect("refused");
        assert!(!e.contains("reader failed"), "caught as a panic, not checked: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
        expect(&e, phrase);
    }
    assert!(parse_gltf(&with(2, n), &mut fetch).is_ok(), "the file as written still reads");
}

//! References are content-addressed: a manifest carries the hash of its image's pixels, checked on
//! every load, so a committed reference edited afterwards (Y + 0.05, one NaN pixel, all NaN) is one
//! error naming the image (exit 2), never measured against and never rebuilt over; and a spec with
//! the same view but other reference settings builds its own reference under a name of its own,
//! leaving the committed one, which other specs rely on, byte for byte as it was.

use crate::support::common::*;
use hemilab::image::{Channel, Image};
use std::path::{Path, PathBuf};

/// The committed reference of `experiments/smoke.toml` (Cornell box, 32x32).
const SMOKE: &str = "cornell-box-32x32-1e9dc6e6";

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// A copy of the smoke spec's committed reference in `t/ref`.
fn copy_smoke_reference(t: &Tmp) {
    std::fs::create_dir_all(t.path("ref")).unwrap();
    for ext in ["exr", "json"] {
        std::fs::copy(repo(&format!("reference/{SMOKE}.{ext}")), t.path(&format!("ref/{SMOKE}.{ext}")))
            .unwrap();
    }
}

/// The reference's channels after `edit` of its mean, written back over the copy.
fn edit_copy(t: &Tmp, edit: &dyn Fn(&mut Image)) {
    let path = t.path(&format!("ref/{SMOKE}.exr"));
    let channels = hemilab::io::read_exr(&path).unwrap();
    let get = |n: &str| channels.iter().find(|(c, _)| c == n).unwrap().1.clone();
    let (mut y, se, a) = (get("Y"), get("stderr"), get("A"));
    edit(&mut y);
    let list = [
        Channel { name: "Y", image: &y },
        Channel { name: "stderr", image: &se },
        Channel { name: "A", image: &a },
    ];
    hemilab::io::write_exr(&path, &list).unwrap();
}

#[test]
fn an_edited_committed_reference_is_refused_naming_its_image() {
    let smoke = repo("experiments/smoke.toml");
    let smoke = smoke.to_str().unwrap();
    type Edit = Box<dyn Fn(&mut Image)>;
    let cases: [(&str, Edit, &str); 3] = [
        ("plus", Box::new(|y: &mut Image| y.data.iter_mut().for_each(|v| *v += 0.05)), "was changed after"),
        (
            "one-nan",
            Box::new(|y: &mut Image| y.data[5 * 32 + 7] = f32::NAN),
            "channel Y at pixel (7, 5) is NaN",
        ),
        ("all-nan", Box::new(|y: &mut Image| y.data.iter_mut().for_each(|v| *v = f32::NAN)), "is NaN"),
    ];
    for (name, edit, says) in cases {
        let t = Tmp::new(&format!("ref-edited-{name}"));
        copy_smoke_reference(&t);
        // Untouched, the copy serves the spec.
        let o = t.hemilab(&["reference", smoke, "--reference-dir", "ref", "--quiet"]);
        assert!(o.status.success() && stdout(&o).contains("kept"), "{}", stderr(&o));
        edit_copy(&t, &edit);
        let edited = std::fs::read(t.path(&format!("ref/{SMOKE}.exr"))).unwrap();
        let manifest = std::fs::read(t.path(&format!("ref/{SMOKE}.json"))).unwrap();
        for args in [
            vec!["run", smoke, "--reference-dir", "ref", "--out", "out", "--quiet"],
            vec!["reference", smoke, "--reference-dir", "ref", "--quiet"],
            vec!["run", smoke, "--reference-dir", "ref", "--out", "out", "--no-build-reference", "--quiet"],
        ] {
            let o = t.hemilab(&args);
            let e = assert_error(&o, &format!("ref/{SMOKE}.exr"));
            assert!(e.contains(says), "{name}: {e}");
            assert!(!t.path("out/results.json").exists(), "{name}: nothing measured");
            assert_eq!(
                std::fs::read(t.path(&format!("ref/{SMOKE}.exr"))).unwrap(),
                edited,
                "not rebuilt over"
            );
            assert_eq!(std::fs::read(t.path(&format!("ref/{SMOKE}.json"))).unwrap(), manifest);
        }
    }
}

/// The smoke spec's view with an adaptive `rays = "auto"` reference: it gets its own file beside
/// the committed one (once it was written over it), is reused by a rerun, and the smoke spec still
/// finds its own.
#[test]
fn other_reference_settings_of_a_view_get_their_own_name() {
    let t = Tmp::new("ref-own-name");
    copy_smoke_reference(&t);
    std::fs::create_dir_all(t.path("exp")).unwrap();
    std::os::unix::fs::symlink(repo("scenes"), t.path("scenes")).unwrap();
    let smoke = std::fs::read_to_string(repo("experiments/smoke.toml")).unwrap();
    assert!(smoke.contains("dir = \"../reference\"") && smoke.contains("rays = 1024\n"));
    let adaptive = smoke
        .replace("dir = \"../reference\"", "dir = \"../ref\"")
        .replace("rays = 1024\n", "rays = \"auto\"\nallocation = \"adaptive\"\n");
    t.spec("exp/adaptive.toml", &adaptive);
    t.spec("exp/smoke.toml", &smoke.replace("dir = \"../reference\"", "dir = \"../ref\""));
    let committed = [
        std::fs::read(repo(&format!("reference/{SMOKE}.exr"))).unwrap(),
        std::fs::read(repo(&format!("reference/{SMOKE}.json"))).unwrap(),
    ];
    let o = t.hemilab(&["reference", "exp/adaptive.toml", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let copy = |ext: &str| std::fs::read(t.path(&format!("ref/{SMOKE}.{ext}"))).unwrap();
    assert_eq!([copy("exr"), copy("json")], committed, "the committed reference is untouched");
    let mut own: Vec<String> = std::fs::read_dir(t.path("ref"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(&format!("{SMOKE}-")) && !n.ends_with(".lock"))
        .collect();
    own.sort();
    assert_eq!(own.len(), 2, "an image and a manifest of its own: {own:?}");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(t.path("ref").join(&own[1])).unwrap()).unwrap();
    assert!(manifest["adaptive"].is_object(), "{manifest}");
    assert!(manifest["pixels"].as_str().unwrap().starts_with("fnv1a64:"), "{manifest}");
    // Both are found again, each by its own spec.
    for spec in ["exp/adaptive.toml", "exp/smoke.toml"] {
        let o = t.hemilab(&["reference", spec, "--quiet"]);
        assert!(o.status.success() && stdout(&o).contains("kept"), "{spec}: {}{}", stdout(&o), stderr(&o));
    }
    assert_eq!([copy("exr"), copy("json")], committed);
}

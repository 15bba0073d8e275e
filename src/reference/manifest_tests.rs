//! The manifest: its JSON form, what matches, and its file names.

use super::*;
use crate::sampling::{Distribution, SeedMode, Sequence};

fn wanted() -> Manifest {
    let scene = SceneRef {
        path: "experiments/../scenes/kitchen.toml".into(),
        id: "../scenes/kitchen.toml".into(),
        name: "kitchen".into(),
        line: 1,
        integrand: crate::sampling::Integrand::Ao,
    };
    let est = Row::new(Distribution::SineCosine, Sequence::Fibonacci, SeedMode::Shift);
    Manifest::wanted(
        &scene,
        "fnv:0123",
        CameraRecord::Legacy("eye 0 1 2; at 0 0 0; fov 60".into()),
        [160, 120],
        AoDistance::Finite(1.0),
        est,
        4096,
        4,
        1,
    )
}

#[test]
fn json_round_trip() {
    let mut m = wanted();
    m.noise_floor = Some(1.25e-3);
    m.time_s = Some(12.5);
    let text = m.to_json();
    assert_eq!(Manifest::from_json(&text).unwrap(), m);
    assert!(text.contains(&format!("\"hemilab_version\": \"{}\"", env!("CARGO_PKG_VERSION"))));
    assert!(Manifest::from_json("{\"scene\": \"x\"}").is_err());
}

#[test]
fn identical_manifest_matches() {
    let mut stored = wanted();
    stored.noise_floor = Some(1e-3);
    assert_eq!(stored.matches(&wanted()), Ok(()));
}

#[test]
fn every_mismatch_is_listed() {
    let mut stored = wanted();
    stored.scene_hash = "fnv:9999".into();
    stored.resolution = [320, 240];
    stored.ao_distance = AoDistance::Infinite.canonical();
    stored.rays = 1024;
    stored.hemilab_version = "0.0.1".into();
    let diffs = stored.matches(&wanted()).unwrap_err();
    let all = diffs.join("\n");
    for key in ["scene_hash", "resolution", "ao_distance", "rays", "hemilab_version"] {
        assert!(all.contains(key), "{key} missing from:\n{all}");
    }
    assert_eq!(diffs.len(), 5, "{all}");
    assert!(all.contains("rays: stored 1024, wanted 4096"), "{all}");
}

#[test]
fn auto_rays_accept_any_count_below_the_floor() {
    let mut stored = wanted();
    stored.rays = 16384;
    stored.replicates = 8;
    assert!(stored.matches_auto(&wanted(), 1e-3).is_err(), "no floor recorded");
    stored.noise_floor = Some(5e-4);
    assert_eq!(stored.matches_auto(&wanted(), 1e-3), Ok(()));
    let e = stored.matches_auto(&wanted(), 1e-4).unwrap_err();
    assert!(e[0].starts_with("noise_floor"), "{e:?}");
    stored.seed = 2;
    assert!(stored.matches_auto(&wanted(), 1e-3).unwrap_err()[0].starts_with("seed"));
}

#[test]
fn settings_stem_names_what_determines_the_image() {
    let a = wanted();
    let mut measured = a.clone();
    measured.noise_floor = Some(1e-3);
    measured.time_s = Some(2.0);
    measured.pixels = Some("fnv1a64:0123456789abcdef".into());
    assert_eq!(measured.settings_stem(), a.settings_stem(), "what was measured is not a setting");
    let mut rays = a.clone();
    rays.rays = 99;
    assert_ne!(rays.settings_stem(), a.settings_stem());
    assert_eq!(rays.file_stem(), a.file_stem(), "one view, one first name");
    assert!(a.settings_stem().starts_with(&format!("{}-", a.file_stem())));
    assert_eq!(a.settings_stem().len(), a.file_stem().len() + 9);
    // The hash is no part of the manifest's match.
    assert_eq!(measured.matches(&a), Ok(()));
}

#[test]
fn file_stem_ignores_rays() {
    let mut a = wanted();
    let b = a.clone();
    a.rays = 99;
    assert_eq!(a.file_stem(), b.file_stem());
    assert!(a.file_stem().starts_with("kitchen-160x120-"));
    a.resolution = [80, 60];
    assert_ne!(a.file_stem(), b.file_stem());
}

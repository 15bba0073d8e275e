//! Adaptive references (`allocation = "adaptive"`) through the real binary: unbiased (they agree
//! with an evenly sampled reference of independent seeds within their standard errors), cheaper for
//! the same floor, exactly described by their manifest (a rerun reuses them, a changed setting
//! rebuilds), and bad settings are refused with the key.

use crate::support::common;

use common::{Tmp, scene};
use hemilab::image::{Image, decode_exr};

fn spec(allocation: &str, rays: &str, seed: u32) -> String {
    format!(
        r#"name = "adaptive"
scenes = ["{}"]
resolution = [40, 30]
replicates = 2
seed = 3

[reference]
rays = {rays}
replicates = 12
seed = {seed}
allocation = "{allocation}"

[[table]]
name = "t"
rays = [16]
rows = [ {{ distribution = "sine-cosine", sequence = "fibonacci", seed_mode = "shift" }} ]
"#,
        scene("cornell-box.toml")
    )
}

/// (mean, stderr, coverage) of the one reference in `dir`, and its manifest text.
fn reference(dir: &std::path::Path) -> (Image, Image, Image, String) {
    let mut exr = None;
    let mut json = None;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        match p.extension().and_then(|x| x.to_str()) {
            Some("exr") => exr = Some(p),
            Some("json") => json = Some(p),
            _ => {}
        }
    }
    let channels = decode_exr(&std::fs::read(exr.expect("an EXR")).unwrap()).unwrap();
    let take = |n: &str| channels.iter().find(|c| c.0 == n).unwrap().1.clone();
    (take("Y"), take("stderr"), take("A"), std::fs::read_to_string(json.expect("a manifest")).unwrap())
}

#[test]
fn adaptive_reference_is_unbiased_cheaper_and_exactly_described() {
    let t = Tmp::new("adaptive-ref");
    let even = t.spec("even.toml", &spec("even", "4096", 5));
    let adaptive = t.spec("adaptive.toml", &spec("adaptive", "\"auto\"", 6));
    for (s, dir) in [(&even, "even"), (&adaptive, "adaptive")] {
        let o = t.hemilab(&[
            "reference".as_ref(),
            s.as_os_str(),
            "--reference-dir".as_ref(),
            dir.as_ref(),
            "--quiet".as_ref(),
        ]);
        assert!(o.status.success(), "{}", common::stderr(&o));
    }
    let (a, sa, cov, manifest) = reference(&t.path("adaptive"));
    let (b, sb, _, _) = reference(&t.path("even"));
    // Unbiased: over pixels with a spread, (a - b) / √(se_a² + se_b²) has mean ~0 and sd ~1 (Student's
    // t with 11 dof per reference: variance about 1.2).
    let z: Vec<f64> = (0..a.len())
        .filter(|&i| cov.data[i] > 0.5 && sa.data[i] > 0.0 && sb.data[i] > 0.0)
        .map(|i| {
            (a.data[i] as f64 - b.data[i] as f64)
                / ((sa.data[i] as f64).powi(2) + (sb.data[i] as f64).powi(2)).sqrt()
        })
        .collect();
    let n = z.len() as f64;
    let mean = z.iter().sum::<f64>() / n;
    let rms = (z.iter().map(|x| x * x).sum::<f64>() / n).sqrt();
    assert!(n > 500.0, "{n} pixels with a spread");
    assert!(mean.abs() < 4.0 * 1.2f64.sqrt() / n.sqrt(), "adaptive - even: mean z {mean:.3} over {n} pixels");
    assert!((0.8..1.4).contains(&rms), "rms z {rms:.3}");
    // Pixels without a spread in either are exact (open or fully occluded) and agree.
    for i in (0..a.len()).filter(|&i| cov.data[i] > 0.5 && sa.data[i] == 0.0 && sb.data[i] == 0.0) {
        assert!((a.data[i] - b.data[i]).abs() < 1e-6, "pixel {i}: {} vs {}", a.data[i], b.data[i]);
    }
    // The manifest names the rule and records what it came to; fewer rays than the even 4096.
    let m: serde_json::Value = serde_json::from_str(&manifest).unwrap();
    let ad = &m["adaptive"];
    assert_eq!(ad["rule"], hemilab::reference::ADAPTIVE_RULE, "{manifest}");
    assert_eq!(m["rays"], 16, "the pilot runs at the spec's largest ray count: {manifest}");
    let covered = cov.data.iter().filter(|&&c| c > 0.5).count() as f64;
    let mean_rays = ad["total_rays"].as_u64().unwrap() as f64 / covered;
    assert!((16.0..4096.0).contains(&mean_rays), "{mean_rays} rays per pixel on average");
    eprintln!(
        "adaptive vs even: mean z {mean:+.3}, rms z {rms:.3} over {n} pixels; {mean_rays:.0} rays per pixel"
    );
    // A run reuses it (no "rendering a new one"); changing the allocation rebuilds.
    let o = t.run_ok(&adaptive, "out", "adaptive", &[]);
    assert!(!common::stderr(&o).contains("rendering a new one"), "{}", common::stderr(&o));
    let o = t.run(
        &t.spec("even2.toml", &spec("even", "\"auto\"", 6)),
        "out2",
        "adaptive",
        &["--no-build-reference"],
    );
    assert!(common::stderr(&o).contains("allocation: stored adaptive"), "{}", common::stderr(&o));
}

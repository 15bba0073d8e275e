//! The sampler interface: the registry is the one list every stage reads (names round-trip, a
//! registered sequence is parsed, listed and rendered like a built-in one), and `prepare` makes
//! every table and mask a configuration reads, so that no timed render generates one.

use glam::Vec2;
use hemilab::sampling::seed::{fix_add, fix_from_bits, fix_to_f32, hash};
use hemilab::sampling::{
    PixelSet, PointSequence, SamplerConfig, SeedMode, Sequence, SequenceInfo, blue_noise, pmj02, register,
    stbn,
};

#[test]
fn every_name_parses_back_to_its_sequence_and_words_point_at_names() {
    for s in Sequence::all() {
        assert_eq!(s.name().parse::<Sequence>().unwrap(), s);
        assert_eq!(s.to_string(), s.name());
        for w in s.info().words {
            let e = w.parse::<Sequence>().unwrap_err();
            assert!(e.ends_with(&format!("is written `{}`)", s.name())), "{e}");
        }
    }
    let e = "sobel".parse::<Sequence>().unwrap_err();
    assert!(e.contains("unknown sequence 'sobel'") && e.contains("fibonacci, stratified"), "{e}");
    // The shipped samplers in the report's order.
    let names: Vec<&str> = Sequence::shipped().into_iter().map(Sequence::name).collect();
    assert_eq!(names, ["halton", "r2", "zsobol", "pmj02bn"]);
}

/// A sequence written outside the crate: a shifted rank-1 lattice (i/n, frac(i φ)).
struct Golden;

impl PointSequence for Golden {
    fn info(&self) -> &SequenceInfo {
        &SequenceInfo {
            name: "golden-test",
            label: "golden",
            words: &[],
            fresh_per_pixel: false,
            shipped: None,
        }
    }

    fn fill(&self, set: &PixelSet, out: &mut [Vec2]) {
        let (key, dx, dy) = set.keyed();
        let (kx, ky) = (fix_from_bits(hash(key, 1)), fix_from_bits(hash(key, 2)));
        let n = set.count as u64;
        for (i, p) in out.iter_mut().enumerate() {
            let x = ((i as u64 * 2 + 1) << 23) / n; // (i + ½)/n on the 24-bit grid
            let y = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 40;
            let (x, y) = (fix_add(fix_add(x as u32, kx), dx), fix_add(fix_add(y as u32, ky), dy));
            *p = Vec2::new(fix_to_f32(x), fix_to_f32(y));
        }
    }
}

#[test]
fn a_registered_sequence_is_named_listed_and_filled_like_a_built_in() {
    let golden = register(Box::new(Golden)).unwrap();
    assert_eq!("golden-test".parse::<Sequence>().unwrap(), golden);
    assert!(Sequence::all().contains(&golden) && Sequence::names().contains(&"golden-test"));
    assert!(register(Box::new(Golden)).unwrap_err().to_string().contains("exists already"));
    let cfg = SamplerConfig::new(golden, SeedMode::Shift, 8, 3).unwrap();
    let (mut a, mut b) = (vec![Vec2::ZERO; 8], vec![Vec2::ZERO; 8]);
    cfg.fill_pixel(1, 2, 9, &mut a);
    cfg.fill_pixel(1, 2, 9, &mut b);
    assert_eq!(a, b, "deterministic");
    assert!(a.iter().all(|p| (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y)));
    // Under `shift` each pixel gets its own set; the x strata stay one point each.
    cfg.fill_pixel(2, 2, 10, &mut b);
    assert_ne!(a, b);
    let mut strata: Vec<usize> = a.iter().map(|p| (p.x * 8.0) as usize).collect();
    strata.sort_unstable();
    strata.dedup();
    assert_eq!(strata.len(), 8);
}

#[test]
fn prepare_makes_every_table_and_mask_a_configuration_reads() {
    // Every sequence × seed mode: after `prepare` the tables it reads exist, so a render (timed or
    // not) can only read them; `fill_pixel` never generates a table that `prepare` did not make.
    for s in Sequence::all() {
        for &m in SeedMode::ALL {
            let cfg = SamplerConfig::new(s, m, 4, 1).unwrap();
            cfg.prepare();
            if s == Sequence::Pmj02bn {
                assert!(pmj02::table_ready(), "{s} {m}");
            }
            match m {
                SeedMode::BlueNoise => assert!(blue_noise::masks_ready(), "{s} {m}"),
                SeedMode::Stbn => assert!(stbn::masks_ready(), "{s} {m}"),
                _ => {}
            }
        }
    }
}

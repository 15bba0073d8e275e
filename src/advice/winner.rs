//! The winner map: per pixel, which configuration has the least MSE at a budget, and whether its
//! win over the runner-up is a discovery.
//!
//! A single pixel's squared error from a handful of replicates is too noisy to rank anything
//! (a χ²-like draw per replicate), so each pixel's squared error is first pooled over its covered
//! 3 × 3 neighbourhood — the map resolves features of about three pixels. Then, per pixel, the
//! replicates are split in two halves: on the first the configuration with the least mean wins and
//! the next is its runner-up; on the second, which had no say in that pick, the runner-up's pooled
//! squared error minus the winner's is formed replicate by replicate (replicate r has the same
//! seed in every configuration: paired) and gives a one-sided p-value (Student's t, n − 1 degrees
//! of freedom). Picking and testing on the same replicates would not hold any level: with two tied
//! configurations the lesser of two equal means always "wins", which doubled a 1 % test's rate.
//!
//! Over the covered pixels of one map the p-values go through the Benjamini–Hochberg procedure
//! at [`FDR`]: the coloured pixels are expected to hold at most that share of false wins. Pooling
//! makes neighbouring p-values positively dependent, under which the procedure keeps its level,
//! and a per-pixel test at a fixed level does not: ~3,000 pixels at 1 % colour ~30 by chance, in
//! clusters of 3–4 (one chance low draw pooled into its neighbours). Where no configuration
//! differs at all the procedure colours nothing in at least 1 − FDR of the maps; the tests below
//! check that, and that chance wins form no clusters.

/// Mean squared error of each covered pixel over its covered 3 × 3 neighbourhood; NaN outside the
/// coverage (`covered[i]` false). `err` is row-major, `width` pixels per row.
pub fn pooled_squared_error(err: &[f32], covered: &[bool], width: usize) -> Vec<f64> {
    let height = err.len().checked_div(width).unwrap_or(0);
    let mut out = vec![f64::NAN; err.len()];
    for y in 0..height {
        for x in 0..width {
            let i = y * width + x;
            if !covered[i] {
                continue;
            }
            let (mut sum, mut n) = (0.0f64, 0usize);
            for yy in y.saturating_sub(1)..(y + 2).min(height) {
                for xx in x.saturating_sub(1)..(x + 2).min(width) {
                    let j = yy * width + xx;
                    if covered[j] {
                        sum += (err[j] as f64).powi(2);
                        n += 1;
                    }
                }
            }
            out[i] = sum / n as f64;
        }
    }
    out
}

/// Two ray counts' pooled images at weight `w` along log time, geometrically per pixel as
/// `compare::budget::at_budget` does for a whole image's MSE (exact at the ends; a zero stays zero).
pub fn interpolate(a: &[f64], b: &[f64], w: f64) -> Vec<f64> {
    a.iter().zip(b).map(|(&x, &y)| crate::compare::budget::geo(x, y, w)).collect()
}

/// The false discovery rate the coloured pixels of one map are held to (Benjamini–Hochberg).
pub const FDR: f64 = 0.05;

/// One-sided p-value of a paired difference with mean `d` and standard error `se` over `n`
/// replicates (H0: no difference; small when `d` is large and positive).
fn one_sided_p(d: f64, se: f64, n: usize) -> f64 {
    if n < 2 || !d.is_finite() {
        return 1.0;
    }
    if se == 0.0 || !se.is_finite() {
        return if d > 0.0 { 0.0 } else { 1.0 };
    }
    let t = d / se;
    let two = crate::stats::student_t_two_sided_p(t, (n - 1) as f64);
    if t > 0.0 { 0.5 * two } else { 1.0 - 0.5 * two }
}

/// Which of `p` (one per tested hypothesis) Benjamini–Hochberg rejects at false discovery rate
/// `q`: all with p at most the largest p₍ₖ₎ ≤ k q / m.
pub fn benjamini_hochberg(p: &[f64], q: f64) -> Vec<bool> {
    let m = p.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p[a].total_cmp(&p[b]));
    let cut = (0..m).rev().find(|&k| p[order[k]] <= (k + 1) as f64 * q / m as f64);
    let mut out = vec![false; m];
    if let Some(k) = cut {
        for &i in &order[..=k] {
            out[i] = true;
        }
    }
    out
}

/// What the map shows at one pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pixel {
    /// No surface: not measured.
    Background,
    /// Covered, but no configuration wins significantly (or all tie, e.g. all exact).
    Unresolved,
    /// This configuration (an index into the caller's list) wins significantly.
    Won(usize),
}

/// The map: `mse[c][r][p]` is configuration c's pooled squared error in pixel p for replicate r
/// (the same replicates, in the same order, for every configuration). The first half of the
/// replicates picks each pixel's winner and runner-up, the second tests them; Benjamini–Hochberg
/// at `q` over the covered pixels decides which wins are shown. Fewer than four replicates: no
/// test (a half needs two).
pub fn winners(mse: &[Vec<Vec<f64>>], covered: &[bool], q: f64) -> Vec<Pixel> {
    let n = mse.first().map_or(0, Vec::len);
    let (pick, test) = (0..n / 2, n / 2..n);
    let mut out = vec![Pixel::Background; covered.len()];
    let mut tested: Vec<(usize, usize, f64)> = Vec::new(); // (pixel, winner, p)
    for (p, px) in out.iter_mut().enumerate() {
        if !covered[p] {
            continue;
        }
        *px = Pixel::Unresolved;
        if n < 4 {
            continue;
        }
        let mean = |c: usize| pick.clone().map(|r| mse[c][r][p]).sum::<f64>() / pick.len() as f64;
        let mut order: Vec<(f64, usize)> = (0..mse.len()).map(|c| (mean(c), c)).collect();
        order.retain(|m| m.0.is_finite());
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let [(_, best), (_, second), ..] = order[..] else { continue };
        let diffs: Vec<f64> = test.clone().map(|r| mse[second][r][p] - mse[best][r][p]).collect();
        let (d, se) = crate::stats::mean_and_standard_error(&diffs);
        tested.push((p, best, one_sided_p(d, se, diffs.len())));
    }
    let ps: Vec<f64> = tested.iter().map(|t| t.2).collect();
    for (&(p, best, _), hit) in tested.iter().zip(benjamini_hochberg(&ps, q)) {
        if hit {
            out[p] = Pixel::Won(best);
        }
    }
    out
}

/// Pixels won per configuration, unresolved pixels, and covered pixels.
pub fn tally(pixels: &[Pixel], configurations: usize) -> (Vec<usize>, usize, usize) {
    let mut won = vec![0; configurations];
    let (mut unresolved, mut covered) = (0, 0);
    for p in pixels {
        match p {
            Pixel::Background => continue,
            Pixel::Unresolved => unresolved += 1,
            Pixel::Won(c) => won[*c] += 1,
        }
        covered += 1;
    }
    (won, unresolved, covered)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pooling_averages_covered_neighbours_only() {
        // 3 × 2, the middle of the top row not covered.
        let err = [1.0f32, 9.0, 2.0, 0.0, 1.0, 3.0];
        let covered = [true, false, true, true, true, true];
        let p = pooled_squared_error(&err, &covered, 3);
        assert!(p[1].is_nan());
        assert!((p[0] - (1.0 + 0.0 + 1.0) / 3.0).abs() < 1e-12, "{p:?}");
        assert!((p[4] - (1.0 + 4.0 + 0.0 + 1.0 + 9.0) / 5.0).abs() < 1e-12, "{p:?}");
        let w = interpolate(&[4.0, 0.0], &[1.0, 5.0], 0.5);
        assert!((w[0] - 2.0).abs() < 1e-12 && w[1] == 0.0);
        assert_eq!(interpolate(&[4.0, 0.0], &[1.0, 5.0], 1.0), [1.0, 5.0]);
    }

    #[test]
    fn clear_wins_are_coloured_and_ties_are_not() {
        // Four pixels (the last not covered), 8 replicates. Pixel 0: config 1 lower in every
        // replicate by a steady margin → won by 1. Pixel 1: configs alternate → unresolved.
        // Pixel 2: all exact → unresolved.
        let covered = [true, true, true, false];
        let rep = |r: usize, c: usize| -> Vec<f64> {
            let wobble = 0.1 * (r % 3) as f64;
            match c {
                0 => vec![2.0 + wobble, if r.is_multiple_of(2) { 1.0 } else { 2.0 }, 0.0, 0.0],
                1 => vec![1.0 + wobble, if r.is_multiple_of(2) { 2.0 } else { 1.0 }, 0.0, 0.0],
                _ => vec![5.0, 5.0, 0.0, 0.0],
            }
        };
        let mse: Vec<Vec<Vec<f64>>> = (0..3).map(|c| (0..8).map(|r| rep(r, c)).collect()).collect();
        let map = winners(&mse, &covered, FDR);
        assert_eq!(map, [Pixel::Won(1), Pixel::Unresolved, Pixel::Unresolved, Pixel::Background]);
        assert_eq!(tally(&map, 3), (vec![0, 1, 0], 2, 3));
        // One configuration alone has nothing to beat; three replicates cannot be split and tested.
        let alone = winners(&[vec![vec![1.0; 4]; 8]], &covered, FDR);
        assert_eq!(alone[0], Pixel::Unresolved);
        let three: Vec<Vec<Vec<f64>>> = mse.iter().map(|c| c[..3].to_vec()).collect();
        assert_eq!(winners(&three, &covered, FDR)[0], Pixel::Unresolved);
    }

    #[test]
    fn benjamini_hochberg_rejects_the_step_up_set() {
        // m = 5, q = 0.1: thresholds 0.02, 0.04, 0.06, 0.08, 0.1; p₍₃₎ = 0.05 ≤ 0.06 is the largest.
        let p = [0.05, 0.5, 0.001, 0.03, 0.09];
        assert_eq!(benjamini_hochberg(&p, 0.1), [true, false, true, true, false]);
        assert_eq!(benjamini_hochberg(&[0.5, 0.6], 0.1), [false, false]);
        assert!(benjamini_hochberg(&[], 0.1).is_empty());
        assert!((one_sided_p(2.0, 1.0, 16) - 0.032).abs() < 1e-3, "{}", one_sided_p(2.0, 1.0, 16));
        assert!(one_sided_p(-2.0, 1.0, 16) > 0.96 && one_sided_p(1.0, 0.0, 8) == 0.0);
    }

    /// A seeded uniform stream in (0, 1).
    fn uniforms(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        }
    }

    /// Connected groups (4-neighbours) of coloured pixels, by size.
    fn clusters(map: &[Pixel], width: usize) -> Vec<usize> {
        let mut seen = vec![false; map.len()];
        let mut sizes = Vec::new();
        for start in 0..map.len() {
            if seen[start] || !matches!(map[start], Pixel::Won(_)) {
                continue;
            }
            let (mut stack, mut size) = (vec![start], 0);
            seen[start] = true;
            while let Some(i) = stack.pop() {
                size += 1;
                let (x, y) = (i % width, i / width);
                let mut near = vec![];
                if x > 0 {
                    near.push(i - 1)
                }
                if x + 1 < width {
                    near.push(i + 1)
                }
                if y > 0 {
                    near.push(i - width)
                }
                if i + width < map.len() {
                    near.push(i + width)
                }
                for j in near {
                    if !seen[j] && matches!(map[j], Pixel::Won(_)) {
                        seen[j] = true;
                        stack.push(j);
                    }
                }
            }
            sizes.push(size);
        }
        sizes
    }

    /// Maps of 64 × 48 pixels, 7 configurations and 16 replicates: each pixel's raw squared error
    /// exponential with mean `scale(c, x)`, then pooled 3 × 3 as advise pools it.
    fn simulated(seed: u64, scale: &dyn Fn(usize, usize) -> f64) -> Vec<Pixel> {
        let (w, h) = (64, 48);
        let covered = vec![true; w * h];
        let mut u = uniforms(seed);
        let mse: Vec<Vec<Vec<f64>>> = (0..7)
            .map(|c| {
                (0..16)
                    .map(|_| {
                        let raw: Vec<f32> =
                            (0..w * h).map(|i| (scale(c, i % w) * -u().ln()).sqrt() as f32).collect();
                        pooled_squared_error(&raw, &covered, w)
                    })
                    .collect()
            })
            .collect();
        winners(&mse, &covered, FDR)
    }

    #[test]
    fn equal_configurations_colour_nothing_beyond_chance() {
        // The null: seven equal configurations, and two equal best with five 5 × worse. The
        // procedure colours nothing in at least 1 − FDR of such maps; of 40, at most 6 may have any
        // coloured pixel (binomial(40, 0.05) exceeds 6 with probability 0.005), and chance wins
        // must not form clusters: never a group of more than a pooled neighbourhood (9 pixels).
        for (tied, name) in [(7, "seven tied"), (2, "two tied")] {
            let (mut any, mut coloured, mut biggest) = (0, 0, 0);
            for m in 0..40 {
                let map = simulated(1000 * tied as u64 + m, &|c, _| if c < tied { 1.0 } else { 5.0 });
                let (won, _, cov) = tally(&map, 7);
                let n: usize = won.iter().sum();
                coloured += n;
                any += usize::from(n > 0);
                biggest = biggest.max(clusters(&map, 64).into_iter().max().unwrap_or(0));
                assert_eq!(cov, 64 * 48);
            }
            let share = coloured as f64 / (40.0 * 64.0 * 48.0);
            assert!(any <= 6, "{name}: {any} of 40 null maps coloured something");
            assert!(share <= FDR / 10.0, "{name}: {share} of null pixels coloured");
            assert!(biggest <= 9, "{name}: a chance cluster of {biggest} pixels");
        }
    }

    #[test]
    fn false_wins_stay_below_the_rate_and_real_ones_are_found() {
        // Left half: configuration 3 has half the others' MSE (a real win); right half: all equal.
        // Coloured pixels on the right (away from the 1-pixel band pooling blurs) are false
        // discoveries: their share of all coloured pixels stays near FDR, and most of the left is found.
        let (mut false_wins, mut all, mut found) = (0usize, 0usize, 0usize);
        for m in 0..10 {
            let map = simulated(77 + m, &|c, x| if c == 3 && x < 32 { 0.5 } else { 1.0 });
            for (i, p) in map.iter().enumerate() {
                let x = i % 64;
                if let Pixel::Won(c) = p {
                    all += 1;
                    if x > 32 || *c != 3 {
                        false_wins += 1;
                    } else if x < 31 {
                        found += 1;
                    }
                }
            }
        }
        let fdr = false_wins as f64 / all.max(1) as f64;
        assert!(fdr <= 1.5 * FDR, "false discovery share {fdr} ({false_wins} of {all})");
        let power = found as f64 / (10.0 * 31.0 * 48.0);
        assert!(power > 0.5, "a 2 × lower MSE is found in {power} of its pixels");
    }
}

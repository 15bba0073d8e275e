//! The winner map: per pixel, which configuration has the least MSE at a budget over the
//! replicates, and whether its win over the runner-up is significant.
//!
//! A single pixel's squared error from a handful of replicates is too noisy to rank anything
//! (it is a χ²-like draw per replicate), so each pixel's squared error is first pooled over its
//! covered 3 × 3 neighbourhood — the map resolves features of about three pixels. Then, per pixel:
//! the configuration with the least mean over the replicates wins; the runner-up's pooled squared
//! error minus the winner's is formed replicate by replicate (replicate r has the same seed in
//! every configuration, so this is paired), and the win is *significant* when that difference's
//! mean exceeds `threshold` paired standard errors (Student's t, one-sided 1 %, n − 1 degrees of
//! freedom). The winner and runner-up are picked from the same replicates: when exactly two
//! configurations tie, that doubles the test's level (the lesser of two equal means is the winner
//! either way); when several tie, the two least are closer than chance would put two given ones,
//! and fewer pass. Simulated with exponential squared errors and 16 replicates, equal
//! configurations colour 1.4 % (two tied) down to 0.2 % (seven tied) of the pixels (the test below
//! checks both). Picking on one half of the replicates and testing on the other would hold 1 % in
//! every case, at the cost of half the replicates' power.

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
/// `advice::at_budget` does for a whole image's MSE (exact at the ends; a zero stays zero).
pub fn interpolate(a: &[f64], b: &[f64], w: f64) -> Vec<f64> {
    a.iter().zip(b).map(|(&x, &y)| super::geo(x, y, w)).collect()
}

/// One-sided level of the per-pixel test.
pub const LEVEL: f64 = 0.01;

/// Paired standard errors the runner-up must trail by, for `replicates` replicates (2.60 for 16);
/// infinite (nothing is significant) with fewer than two.
pub fn threshold(replicates: usize) -> f64 {
    if replicates < 2 {
        return f64::INFINITY;
    }
    crate::stats::student_t_quantile(2.0 * LEVEL, (replicates - 1) as f64)
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
/// (the same replicates, in the same order, for every configuration).
pub fn winners(mse: &[Vec<Vec<f64>>], covered: &[bool], threshold: f64) -> Vec<Pixel> {
    let n = mse.first().map_or(0, Vec::len);
    let mut out = vec![Pixel::Background; covered.len()];
    for (p, px) in out.iter_mut().enumerate() {
        if !covered[p] {
            continue;
        }
        *px = Pixel::Unresolved;
        let mean = |c: usize| mse[c].iter().map(|r| r[p]).sum::<f64>() / n as f64;
        let mut order: Vec<(f64, usize)> = (0..mse.len()).map(|c| (mean(c), c)).collect();
        order.retain(|m| m.0.is_finite());
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let [(_, best), (_, second), ..] = order[..] else { continue };
        let diffs: Vec<f64> = (0..n).map(|r| mse[second][r][p] - mse[best][r][p]).collect();
        let (d, se) = crate::stats::mean_and_standard_error(&diffs);
        if diffs.len() >= 2 && d > 0.0 && (se == 0.0 || d / se > threshold) {
            *px = Pixel::Won(best);
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
    fn significant_wins_are_coloured_and_ties_are_not() {
        let covered = [true, true, true, false];
        // Pixel 0: config 1 lower in every replicate by a steady margin → won by 1.
        // Pixel 1: configs alternate → unresolved. Pixel 2: all exact → unresolved.
        let c0 = vec![vec![2.0, 1.0, 0.0, 0.0], vec![2.1, 2.0, 0.0, 0.0], vec![1.9, 1.0, 0.0, 0.0]];
        let c1 = vec![vec![1.0, 2.0, 0.0, 0.0], vec![1.1, 1.0, 0.0, 0.0], vec![0.95, 2.0, 0.0, 0.0]];
        let c2 = vec![vec![5.0, 5.0, 0.0, 0.0], vec![5.0, 5.0, 0.0, 0.0], vec![5.0, 5.0, 0.0, 0.0]];
        let map = winners(&[c0, c1, c2], &covered, threshold(3));
        assert_eq!(map, [Pixel::Won(1), Pixel::Unresolved, Pixel::Unresolved, Pixel::Background]);
        assert_eq!(tally(&map, 3), (vec![0, 1, 0], 2, 3));
        assert!((threshold(16) - 2.602).abs() < 1e-3, "{}", threshold(16));
        assert_eq!(threshold(1), f64::INFINITY);
        // One configuration alone has nothing to beat.
        let alone = winners(&[vec![vec![1.0; 4], vec![1.0; 4]]], &covered, 1.0);
        assert_eq!(alone[0], Pixel::Unresolved);
    }

    #[test]
    fn equal_configurations_rarely_win() {
        // Seven configurations, `tied` of them with the same squared-error distribution
        // (exponential, roughly what a pooled χ² is) and the rest five times worse; 16 replicates,
        // 20 000 pixels. Two tied: the pick doubles the level; seven tied: the two least are close.
        let mut state = 12345u64;
        let mut uniform = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let pixels = 20_000;
        let covered = vec![true; pixels];
        for (tied, most) in [(2, 0.025), (7, 0.006)] {
            let mse: Vec<Vec<Vec<f64>>> = (0..7)
                .map(|c| {
                    let k = if c < tied { 1.0 } else { 5.0 };
                    (0..16).map(|_| (0..pixels).map(|_| -k * uniform().ln()).collect()).collect()
                })
                .collect();
            let (won, _, _) = tally(&winners(&mse, &covered, threshold(16)), 7);
            let rate = won.iter().sum::<usize>() as f64 / pixels as f64;
            assert!(rate < most, "{tied} tied: false wins {rate}");
        }
    }
}

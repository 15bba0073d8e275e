//! sin and cos of an angle given in quarter turns, with exact argument reduction: the warps' angles
//! are fractions of a turn (phi = 2 pi u), so the reduction to [-pi/4, pi/4] is a subtraction of
//! the nearest integer, exact in f32, instead of a multiplication by pi followed by libm's own
//! reduction. Branch-free, plain IEEE mul/add (no FMA), so a loop over a pixel's points
//! vectorizes and every lane, scalar or SIMD, SSE2 or AVX2, gives the same bits on every machine
//! (libm's sinf differs between libm versions and between its FMA and non-FMA variants).
//!
//! The core polynomials are Norbert Juffa's minimax approximations of sin(pi t) and cos(pi t) on
//! |t| <= 1/4 (his `sincospif`, 2016), evaluated without FMA; `tests` checks every input of the
//! samplers' 24-bit grid against f64: at most 2 ulp (sin, cos); 81 % of the results (31.2 M of
//! 38.3 M) correctly rounded.

/// Adding and subtracting 1.5 · 2^23 rounds an f32 of magnitude below 2^22 to the nearest integer
/// (ties to even), with SSE2 arithmetic only.
const ROUND: f32 = 12_582_912.0;

/// (sin(pi/2 · q), cos(pi/2 · q)) for |q| < 2^22 (q: the angle in quarter turns).
#[inline(always)]
pub fn sin_cos_quarter(q: f32) -> (f32, f32) {
    let shifted = q + ROUND; // 1.5 · 2^23 + the nearest integer k: its ulp is 1
    let k = shifted - ROUND; // k, exact
    // k mod 4 from the low bits of `shifted` (mantissa 2^22 + k, and 2^22 is a multiple of 4), the
    // same bits as `k as i32 & 3`: a bit cast and an AND per lane, where Rust's saturating `as`
    // (NaN and overflow checks) made the compiler leave the vector loop for every lane.
    let quadrant = shifted.to_bits();
    // In half turns, |t| <= 1/4; exact (the difference of two nearby floats, then a power of 2).
    let t = (q - k) * 0.5;
    let s2 = t * t;
    // Coefficients as bits (Juffa's hex literals), so no decimal rounding stands between them.
    let f = f32::from_bits;
    let mut c = f(0x3e6c_f000); // 0x1.d9e000p-3
    c = c * s2 + f(0xbfaa_e200); // -0x1.55c400p+0
    c = c * s2 + f(0x4081_e0e7); // 0x1.03c1cep+2
    c = c * s2 + f(0xc09d_e9e6); // -0x1.3bd3ccp+2
    c = c * s2 + 1.0;
    let mut r = f(0xbf18_8000); // -0x1.310000p-1
    r = r * s2 + f(0x4023_39bf); // 0x1.46737ep+1
    r = r * s2 + f(0xc0a5_5dff); // -0x1.4abbfep+2
    r *= t * s2;
    let s = t * std::f32::consts::PI + r;
    // Quadrant: sin(pi/2 k + x), cos(pi/2 k + x) from sin x, cos x (k mod 4 in two's complement).
    let (s, c) = if quadrant & 2 != 0 { (0.0 - s, 0.0 - c) } else { (s, c) };
    if quadrant & 1 != 0 { (c, 0.0 - s) } else { (s, c) }
}

/// (sin 2 pi u, cos 2 pi u), u in turns.
#[inline(always)]
pub fn sin_cos_turns(u: f32) -> (f32, f32) {
    sin_cos_quarter(4.0 * u)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulps(got: f32, want: f64) -> f64 {
        let w = want as f32;
        let ulp = if w == 0.0 { f32::from_bits(1) } else { w.abs().next_up() - w.abs() };
        ((got as f64 - want) / ulp as f64).abs()
    }

    /// Every input on the samplers' 24-bit grid of [0, 1] turns (and of a quarter-turn argument
    /// in [-2, 2]) against f64 sin and cos: within 2 ulp, or 2^-26 absolute near a zero.
    #[test]
    fn every_grid_input_is_within_two_ulp() {
        let (mut worst, mut exact, mut total) = (0.0f64, 0u64, 0u64);
        let mut check = |q: f32| {
            let (s, c) = sin_cos_quarter(q);
            let a = std::f64::consts::FRAC_PI_2 * q as f64;
            for (got, want) in [(s, a.sin()), (c, a.cos())] {
                let e = ulps(got, want);
                let ok = e <= 2.0 || (got as f64 - want).abs() <= 1.0 / 67_108_864.0;
                assert!(ok, "q = {q}: {got} vs {want} ({e} ulp)");
                if want.abs() > 1e-3 {
                    worst = worst.max(e);
                    exact += (got == want as f32) as u64;
                    total += 1;
                }
            }
        };
        for k in 0..=(1u32 << 24) {
            check(4.0 * (k as f32 / 16_777_216.0));
        }
        for k in (0..=(1u32 << 24)).step_by(7) {
            check(4.0 * (k as f32 / 16_777_216.0) - 2.0);
        }
        assert!(worst <= 2.0, "{worst}");
        assert!(exact as f64 > 0.8 * total as f64, "{exact} of {total} correctly rounded");
    }

    /// The quadrant read from the shifted float's bits is `k as i32` mod 4 for every |q| < 2^22
    /// (sampled: every integer and half-integer up to 2^12, then a stride), negative q included.
    #[test]
    fn quadrant_bits_are_the_integer_mod_4() {
        let qs = (-8192..=8192)
            .map(|i| i as f32 * 0.5)
            .chain((-4_194_000..4_194_000).step_by(997).map(|i| i as f32 + 0.25))
            .chain([4_194_303.0, -4_194_303.0, 0.49999997, -0.49999997, 1.5, 2.5, -1.5, -2.5]);
        for q in qs {
            let shifted = q + ROUND;
            let k = shifted - ROUND;
            assert_eq!(shifted.to_bits() & 3, (k as i32 & 3) as u32, "q = {q}");
        }
    }

    #[test]
    fn quadrants_and_exact_points() {
        assert_eq!(sin_cos_turns(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_turns(0.25), (1.0, 0.0));
        assert_eq!(sin_cos_turns(0.5).1, -1.0);
        assert_eq!(sin_cos_turns(0.75).0, -1.0);
        assert_eq!(sin_cos_turns(1.0), (0.0, 1.0));
        let (s, c) = sin_cos_quarter(-0.5);
        assert!((s + 0.5f32.sqrt()).abs() < 1e-7 && (c - 0.5f32.sqrt()).abs() < 1e-7);
    }
}

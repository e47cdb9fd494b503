//! The cube root in plain arithmetic, with no division, so that a loop over contacts that
//! takes one (the JKR contact radius, [`super::jkr`]) vectorises and stays cheap: the
//! library's `cbrt` is a call the compiler cannot widen, and divisions are the slowest
//! vector instructions.
//!
//! The root is found through its reciprocal y = x^{-1/3}, whose Newton iteration
//! y ← y (4 − x y³)/3 needs no division. The guess divides the exponent by three through
//! the high 32 bits of the number's representation (Kahan's bit trick, as in the cube roots
//! of the classic C libraries): for x = 2^e (1 + f) the high word is (e + 1023)·2^20 plus
//! the mantissa's top bits, and (1023 + 341)·2^20 less a third of it is the high word of
//! about 2^{−e/3}, within 9 %. Four steps, each doubling the correct digits, leave y within
//! 2·10⁻¹³; then t = x y² and one Newton step for t³ = x, t ← t − (t³ − x) y²/3 (y² stands
//! for 1/t², an error of second order), round t to within an ulp of the exact root.

/// The real cube root of `x` [any unit³] and its reciprocal, for x between 10⁻³⁰⁰ and
/// 10³⁰⁰: the root within one ulp of `f64::cbrt`, the reciprocal within 2·10⁻¹³ of
/// x^{-1/3} (relative).
#[inline(always)]
pub fn cube_root_and_reciprocal(x: f64) -> (f64, f64) {
    // The high word is below 2^31 for a positive number, so the product fits 64 bits and
    // (hi · 0x5555_5556) >> 32 is ⌊hi/3⌋, a multiplication the vector units have.
    let hi = x.to_bits() >> 32;
    let mut y = f64::from_bits((((1023 + 341) << 20) - ((hi * 0x5555_5556) >> 32)) << 32);
    for _ in 0..4 {
        let y3 = y * y * y;
        y = y * (4.0 - x * y3) * (1.0 / 3.0);
    }
    let y2 = y * y;
    let t = x * y2;
    (t - (t * t * t - x) * (y2 * (1.0 / 3.0)), y)
}

/// The real cube root of `x` [any unit³], for x between 10⁻³⁰⁰ and 10³⁰⁰; within one ulp
/// of `f64::cbrt` ([`cube_root_and_reciprocal`]).
#[inline(always)]
pub fn cube_root(x: f64) -> f64 {
    cube_root_and_reciprocal(x).0
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn within_one_ulp_of_the_library_root_over_the_domain() {
        // 10^5 numbers with random mantissas and exponents from 2^-996 to 2^996 (the domain,
        // 10^±300), and exact cubes: the iteration's rounding leaves at most one ulp (the
        // library root is itself within an ulp), and the reciprocal its stated 2·10⁻¹³.
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(3);
        for _ in 0..100_000 {
            let x = rng.gen_range(1.0..2.0) * 2f64.powi(rng.gen_range(-996..996));
            let (a, y) = cube_root_and_reciprocal(x);
            let b = x.cbrt();
            assert!(
                a.to_bits().abs_diff(b.to_bits()) <= 1,
                "x = {x:e}: {a:e} against {b:e}"
            );
            assert!((y * b - 1.0).abs() <= 2e-13, "x = {x:e}: 1/∛x {y:e}");
        }
        for k in [1.0, 8.0, 27.0, 3.375, 1e15, 0.125] {
            assert_eq!(cube_root(k), k.cbrt(), "{k}");
        }
    }
}

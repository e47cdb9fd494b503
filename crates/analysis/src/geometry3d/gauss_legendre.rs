//! Gauss–Legendre nodes and weights on [−1, 1], computed once by Newton's method on the
//! Legendre polynomial P_n (Abramowitz & Stegun 25.4.29: x_i roots of P_n,
//! w_i = 2 / ((1 − x_i²) P_n'(x_i)²)).

use std::sync::OnceLock;

/// Points of the rule used for the sphere–slab–annulus volumes. On each piece of the
/// integration range the integrand is analytic after the end-point map of `sphere_slab`, so
/// the error falls geometrically with the order: at worst 1.4e-10 of the sphere volume with
/// 12 points, 3e-13 with 16, round-off from 20 on (the convergence test in `sphere_slab`).
pub(crate) const ORDER: usize = 20;

/// The `ORDER`-point rule as (node, weight) pairs, nodes increasing.
pub(crate) fn rule() -> &'static [(f64, f64); ORDER] {
    static RULE: OnceLock<[(f64, f64); ORDER]> = OnceLock::new();
    RULE.get_or_init(|| {
        let mut pairs = [(0.0, 0.0); ORDER];
        for (pair, computed) in pairs.iter_mut().zip(compute(ORDER)) {
            *pair = computed;
        }
        pairs
    })
}

/// P_n(x) and P_n'(x) by the three-term recurrence (k+1)P_{k+1} = (2k+1)xP_k − kP_{k−1} and
/// P_n' = n(xP_n − P_{n−1})/(x² − 1) (valid inside (−1, 1), where all roots lie).
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut previous, mut current) = (1.0, x);
    for k in 1..n {
        let k = k as f64;
        let next = ((2.0 * k + 1.0) * x * current - k * previous) / (k + 1.0);
        previous = current;
        current = next;
    }
    let derivative = n as f64 * (x * current - previous) / (x * x - 1.0);
    (current, derivative)
}

/// The n-point rule (n ≥ 1), nodes increasing.
pub(crate) fn compute(n: usize) -> Vec<(f64, f64)> {
    let mut pairs = Vec::with_capacity(n);
    for i in 0..n {
        // Tricomi's first guess for the (i+1)-th largest root; Newton converges from it
        // quadratically in a few steps.
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        for _ in 0..100 {
            let (p, dp) = legendre(n, x);
            let step = p / dp;
            x -= step;
            if step.abs() < 1e-16 {
                break;
            }
        }
        let (_, dp) = legendre(n, x);
        pairs.push((-x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rule_integrates_polynomials_up_to_degree_2n_minus_1_exactly() {
        // ∫₋₁¹ x^m dx = 2/(m + 1) for even m, 0 for odd m. An n-point Gauss rule is exact up to
        // m = 2n − 1 (1e-14 covers the rounding of n terms), and not for m = 2n, where its
        // error is 2^{2n+1}(n!)⁴/((2n+1)((2n)!)²) (A&S 25.4.30 with f^{(2n)} = (2n)!, 2.8e-12
        // for n = 20); matching it to 1e-14 shows the nodes are the Legendre roots.
        let pairs = rule();
        let exact = |m: usize| {
            if m.is_multiple_of(2) {
                2.0 / (m as f64 + 1.0)
            } else {
                0.0
            }
        };
        for m in 0..2 * ORDER {
            let sum: f64 = pairs.iter().map(|(x, w)| w * x.powi(m as i32)).sum();
            assert!((sum - exact(m)).abs() < 1e-14, "degree {m}: {sum}");
        }
        let m = 2 * ORDER;
        let sum: f64 = pairs.iter().map(|(x, w)| w * x.powi(m as i32)).sum();
        let factorial = |k: usize| (1..=k).map(|i| i as f64).product::<f64>();
        let n = ORDER;
        let expected_error = 2f64.powi(2 * n as i32 + 1) * factorial(n).powi(4)
            / ((2 * n + 1) as f64 * factorial(2 * n).powi(2));
        assert!(
            (exact(m) - sum - expected_error).abs() < 1e-14,
            "{}",
            exact(m) - sum
        );
        // Symmetric nodes, increasing, inside (−1, 1).
        for (i, (x, w)) in pairs.iter().enumerate() {
            let (mirror, mirror_weight) = pairs[ORDER - 1 - i];
            assert!((x + mirror).abs() < 1e-15 && (w - mirror_weight).abs() < 1e-15);
            assert!(x.abs() < 1.0 && *w > 0.0);
        }
        assert!(pairs.windows(2).all(|p| p[0].0 < p[1].0));
    }

    #[test]
    fn small_rules_match_their_closed_forms() {
        // n = 2: ±1/√3 with weights 1; n = 3: 0, ±√(3/5) with weights 8/9, 5/9.
        let two = compute(2);
        assert!((two[1].0 - 1.0 / 3f64.sqrt()).abs() < 1e-15 && (two[1].1 - 1.0).abs() < 1e-15);
        let three = compute(3);
        assert!(three[1].0.abs() < 1e-15 && (three[1].1 - 8.0 / 9.0).abs() < 1e-15);
        assert!((three[2].0 - 0.6f64.sqrt()).abs() < 1e-15);
        assert!((three[2].1 - 5.0 / 9.0).abs() < 1e-15);
    }
}

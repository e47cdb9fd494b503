//! Johnson–Kendall–Roberts adhesion (Johnson, Kendall & Roberts 1971, Proc. R. Soc. A 324,
//! 301; Johnson 1985, Contact Mechanics §5.5; docs/physics.md §2.4): the elastic contact of
//! two spheres whose surfaces stick with a work of adhesion w = Δγ [J/m²] (2γ for two like
//! surfaces of surface energy γ).
//!
//! With E* and R* of the pair and a the contact radius, the overlap and the force are
//!
//! - δ(a) = a²/R* − √(2π w a / E*),
//! - F(a) = 4E* a³/(3R*) − √(8π w E* a³) (positive: repulsive).
//!
//! A contact forms when the surfaces touch (δ = 0, where F = −(8/9) F_c), holds in tension,
//! and breaks where δ(a) is smallest, at δ_c = −(3/4)(π² w² R*/E*²)^{1/3} with force
//! −(5/6)π w R*: separation is displacement-driven in a DEM contact. F_c = (3/2)π w R* is the
//! pull-off force under load control, the least F on the curve.

use std::f64::consts::PI;

use super::cube_root::cube_root_and_reciprocal;

/// The pull-off force F_c = (3/2) π w R* [N] of work of adhesion `w` [J/m²] and effective
/// radius `r_eff` [m]: the largest tension the contact holds.
#[inline]
pub fn pull_off_force(w: f64, r_eff: f64) -> f64 {
    1.5 * PI * w * r_eff
}

/// The overlap δ_c = −(3/4)(π² w² R*/E*²)^{1/3} [m] at which a contact breaks (negative:
/// the surfaces are apart).
#[inline]
pub fn breaking_overlap(e_star: f64, r_eff: f64, w: f64) -> f64 {
    -0.75 * (PI * PI * w * w * r_eff / (e_star * e_star)).cbrt()
}

/// The contact radius where the contact breaks, a_f = (π w R*²/(8E*))^{1/3} [m].
#[inline]
pub fn breaking_contact_radius(e_star: f64, r_eff: f64, w: f64) -> f64 {
    (PI * w * r_eff * r_eff / (8.0 * e_star)).cbrt()
}

/// The contact radius at zero load, a_0 = (9π w R*²/(2E*))^{1/3} [m].
#[inline]
pub fn zero_load_contact_radius(e_star: f64, r_eff: f64, w: f64) -> f64 {
    (4.5 * PI * w * r_eff * r_eff / e_star).cbrt()
}

/// The overlap δ(a) = a²/R* − √(2π w a/E*) [m] of contact radius `a` [m].
#[inline]
pub fn overlap_at(e_star: f64, r_eff: f64, w: f64, a: f64) -> f64 {
    a * a / r_eff - (2.0 * PI * w * a / e_star).sqrt()
}

/// The force F(a) = 4E* a³/(3R*) − √(8π w E* a³) [N] of contact radius `a` [m].
#[inline]
pub fn force_at(e_star: f64, r_eff: f64, w: f64, a: f64) -> f64 {
    JkrPair::new(e_star, w).force_at(r_eff, a)
}

/// Whether a bonded contact at `overlap` [m] still holds: δ ≥ δ_c, compared without the cube
/// root as (−δ)³ ≤ (27/64) π² w² R*/E*² where δ < 0.
#[inline]
pub fn holds(e_star: f64, r_eff: f64, w: f64, overlap: f64) -> bool {
    JkrPair::new(e_star, w).holds(r_eff, overlap)
}

/// The contact radius a [m] of a bonded contact at overlap `overlap` [m]: the largest root of
/// δ(a) = overlap, or `None` below the breaking overlap, where the contact has no state
/// ([`JkrPair::contact_radius`]).
#[inline]
pub fn contact_radius(e_star: f64, r_eff: f64, w: f64, overlap: f64) -> Option<f64> {
    let pair = JkrPair::new(e_star, w);
    pair.holds(r_eff, overlap)
        .then(|| pair.contact_radius(r_eff, overlap))
}

/// A bonded JKR contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JkrForce {
    /// Normal force F(a) [N], positive when repulsive.
    pub force: f64,
    /// Contact radius a [m].
    pub contact_radius: f64,
    /// Normal stiffness 2E* a [N/m] of the dashpot: Hertz's S_n at the JKR contact radius,
    /// so that the damping is the dry one when w → 0.
    pub stiffness: f64,
}

/// The JKR force at `overlap` [m], or `None` where a bonded contact breaks.
#[inline]
pub fn jkr(e_star: f64, r_eff: f64, w: f64, overlap: f64) -> Option<JkrForce> {
    let pair = JkrPair::new(e_star, w);
    pair.holds(r_eff, overlap)
        .then(|| pair.force(r_eff, overlap))
}

/// The numbers of one material pair's JKR curve that depend neither on R* nor on the
/// overlap, formed once per pair so that a contact's evaluation is arithmetic only: the
/// functions above go through it, and so does the batched kernel's lane, with the same
/// bits.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct JkrPair {
    /// Effective Young's modulus E* [Pa].
    pub e_star: f64,
    /// c = √(2π w/E*) [m^{1/2}], of δ(a) = a²/R* − c √a.
    pub c: f64,
    /// (3/2) π w [N/m]: the pull-off force is this times R*.
    pub pull_off: f64,
    /// (27/64)(π w/E*)² [m²]: a bonded contact holds while (−δ)³ is at most this times R*.
    pub break_cubed: f64,
    /// √(8π w E*) [N/m^{3/2}]: F's adhesive term √(8π w E* a³) is this times a^{3/2}.
    pub adhesion: f64,
}

impl JkrPair {
    /// The curve's constants for effective modulus `e_star` [Pa] and work of adhesion `w`
    /// [J/m²].
    pub fn new(e_star: f64, w: f64) -> Self {
        Self {
            e_star,
            c: (2.0 * PI * w / e_star).sqrt(),
            pull_off: 1.5 * PI * w,
            break_cubed: 27.0 / 64.0 * (PI * w / e_star) * (PI * w / e_star),
            adhesion: (8.0 * PI * w * e_star).sqrt(),
        }
    }

    /// The pull-off force F_c [N] at effective radius `r_eff` [m] ([`pull_off_force`]).
    #[inline(always)]
    pub fn pull_off_force(&self, r_eff: f64) -> f64 {
        self.pull_off * r_eff
    }

    /// Whether a bonded contact at `overlap` [m] holds ([`holds`]); without a branch.
    #[inline(always)]
    pub fn holds(&self, r_eff: f64, overlap: f64) -> bool {
        let d = -overlap;
        (overlap >= 0.0) | (d * d * d <= self.break_cubed * r_eff)
    }

    /// The force F(a) [N] of contact radius `a` [m] ([`force_at`]).
    #[inline(always)]
    pub fn force_at(&self, r_eff: f64, a: f64) -> f64 {
        self.force_with(1.0 / r_eff, a.sqrt())
    }

    /// F(a) [N] with 1/R* [1/m] and s = √a [m^{1/2}] given: the adhesive term
    /// √(8π w E*) a^{3/2} is then a product, s³, with no root of its own.
    #[inline(always)]
    fn force_with(&self, inv_r: f64, s: f64) -> f64 {
        let a = s * s;
        let a3 = a * a * a;
        (4.0 / 3.0) * self.e_star * a3 * inv_r - self.adhesion * (a * s)
    }

    /// The contact radius a [m] at `overlap` [m] of a contact that holds there
    /// ([`JkrPair::holds`]; elsewhere the number means nothing). Without a branch or a
    /// library call, so that the batched kernel's lanes take it.
    #[inline(always)]
    pub fn contact_radius(&self, r_eff: f64, overlap: f64) -> f64 {
        let s = self.root_contact_radius(r_eff, 1.0 / r_eff, overlap);
        s * s
    }

    /// The root s = √a [m^{1/2}] of the contact radius of [`JkrPair::contact_radius`], with
    /// 1/R* [1/m] given.
    ///
    /// In s = √a the equation δ(a) = overlap is the depressed quartic s⁴ − cR* s − δR* = 0,
    /// solved in closed form (Ferrari): with m the positive root of the resolvent cubic
    /// m³ + δR* m − c²R*²/8 = 0, (s² + m)² = 2m (s − cR*/(4m))², and the largest root is
    /// s = (√(2m) + √(2cR*/√(2m) − 2m))/2. The cubic's discriminant (c²R*²/16)² + (δR*/3)³
    /// is ≥ 0 exactly where δ ≥ δ_c, so Cardano's real form gives m = u − δR*/(3u),
    /// u = ∛(c²R*²/16 + √disc), with 1/u the cube root's reciprocal. One Newton step on the
    /// quartic then removes the cancellation in m at large overlaps and the reciprocal's
    /// error (both of first order), leaving the root to round-off.
    #[inline(always)]
    fn root_contact_radius(&self, r_eff: f64, inv_r: f64, overlap: f64) -> f64 {
        let c = self.c;
        let half_q = c * c * r_eff * r_eff * (1.0 / 16.0);
        let third_p = overlap * r_eff * (1.0 / 3.0);
        let disc = (half_q * half_q + third_p * third_p * third_p)
            .max(0.0)
            .sqrt();
        let (u, inv_u) = cube_root_and_reciprocal(half_q + disc);
        let m = u - third_p * inv_u;
        let root_2m = (2.0 * m).sqrt();
        let s = 0.5 * (root_2m + (2.0 * c * r_eff / root_2m - 2.0 * m).max(0.0).sqrt());
        let s3 = s * s * s;
        let slope = 4.0 * s3 * inv_r - c;
        // At the breaking overlap the root is where the slope vanishes: no step there.
        let step = (s3 * s * inv_r - c * s - overlap) / slope;
        if slope > 0.0 {
            s - step
        } else {
            s
        }
    }

    /// The bonded contact at `overlap` [m], for a contact that holds there.
    #[inline(always)]
    pub fn force(&self, r_eff: f64, overlap: f64) -> JkrForce {
        let inv_r = 1.0 / r_eff;
        let s = self.root_contact_radius(r_eff, inv_r, overlap);
        let a = s * s;
        JkrForce {
            force: self.force_with(inv_r, s),
            contact_radius: a,
            stiffness: 2.0 * self.e_star * a,
        }
    }
}

/// The work [J] a contact takes on one approach and separation without damping: the area
/// between the curve and F = 0 from δ_c to 0, ∫ −F dδ, which the loading (no force before
/// touching) does not give back.
///
/// With F = A a³ − B a^{3/2} and δ' = 2a/R* − (C/2) a^{−1/2} (A = 4E*/(3R*), B = √(8πwE*),
/// C = √(2πw/E*)), F δ' integrates in closed form between a_f and a at δ = 0,
/// a₁ = (2π w R*²/E*)^{1/3}.
pub fn loop_energy(e_star: f64, r_eff: f64, w: f64) -> f64 {
    let a_coef = 4.0 * e_star / (3.0 * r_eff);
    let b_coef = (8.0 * PI * w * e_star).sqrt();
    let c_coef = (2.0 * PI * w / e_star).sqrt();
    let primitive = |a: f64| {
        2.0 * a_coef / (5.0 * r_eff) * a.powi(5)
            - (a_coef * c_coef / 2.0 + 2.0 * b_coef / r_eff) * (2.0 / 7.0) * a.powf(3.5)
            + b_coef * c_coef / 4.0 * a * a
    };
    let a_touch = (2.0 * PI * w * r_eff * r_eff / e_star).cbrt();
    let a_break = breaking_contact_radius(e_star, r_eff, w);
    primitive(a_break) - primitive(a_touch)
}

/// The speed [m/s] below which an undamped head-on impact sticks: all kinetic energy
/// ½ m* v² is taken by the loop, v_s = √(2 W / m*) with W = [`loop_energy`] (the energy
/// balance of Thornton & Ning 1998, Powder Technol. 99, 154, on the JKR curve itself).
pub fn sticking_velocity(e_star: f64, r_eff: f64, m_eff: f64, w: f64) -> f64 {
    (2.0 * loop_energy(e_star, r_eff, w) / m_eff).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    // A soft, sticky pair: E* = 1e8 Pa, R* = 1 mm, w = 0.05 J/m².
    const E: f64 = 1.0e8;
    const R: f64 = 1.0e-3;
    const W: f64 = 0.05;

    #[test]
    fn the_inverse_gives_back_the_overlap() {
        // Round trip δ → a → δ over the whole bonded range: 1e-12 relative to the overlap
        // scale |δ_c| is a few hundred ulps of the terms that cancel in δ(a).
        let dc = breaking_overlap(E, R, W);
        // From just above δ_c (where the test of `holds` is decided by round-off) to 9|δ_c|.
        for k in 1..=200 {
            let d = dc + (k as f64) * (-10.0 * dc) / 200.0;
            let a = contact_radius(E, R, W, d).expect("bonded above δ_c");
            assert!(
                (overlap_at(E, R, W, a) - d).abs() <= 1e-12 * dc.abs(),
                "δ = {d}"
            );
        }
        assert!(contact_radius(E, R, W, dc * 1.000_001).is_none());
        assert!(holds(E, R, W, dc * 0.999_999) && !holds(E, R, W, dc * 1.000_001));
    }

    #[test]
    fn the_curve_meets_its_landmarks() {
        // Closed forms of the curve's points (Johnson 1985 §5.5), to round-off (1e-12).
        let fc = pull_off_force(W, R);
        let a0 = zero_load_contact_radius(E, R, W);
        assert!(force_at(E, R, W, a0).abs() <= 1e-12 * fc);
        // The least force on the curve is −F_c, at a = a_0/4^{1/3}.
        assert_relative_eq!(
            force_at(E, R, W, a0 / 4f64.cbrt()),
            -fc,
            max_relative = 1e-12
        );
        // At the break, a_f = a_0/36^{1/3}, δ = δ_c and F = −(5/9) F_c = −(5/6)π w R*.
        let af = breaking_contact_radius(E, R, W);
        assert_relative_eq!(af, a0 / 36f64.cbrt(), max_relative = 1e-12);
        assert_relative_eq!(
            overlap_at(E, R, W, af),
            breaking_overlap(E, R, W),
            max_relative = 1e-12
        );
        assert_relative_eq!(force_at(E, R, W, af), -5.0 / 9.0 * fc, max_relative = 1e-12);
        // On touching, δ = 0 and F = −(8/9) F_c.
        let at0 = jkr(E, R, W, 0.0).unwrap();
        assert_relative_eq!(at0.force, -8.0 / 9.0 * fc, max_relative = 1e-12);
    }

    #[test]
    fn without_adhesion_the_curve_is_hertz() {
        // w → 0: a → √(R* δ) and F → Hertz; w = 1e-12 J/m² moves them by about 1e-5.
        let d = 1e-6;
        let j = jkr(E, R, 1e-12, d).unwrap();
        let h = super::super::normal::hertz(E, R, d);
        assert_relative_eq!(j.force, h.force, max_relative = 1e-4);
        assert_relative_eq!(j.contact_radius, h.contact_radius, max_relative = 1e-4);
    }

    #[test]
    fn the_loop_energy_is_the_area_under_the_curve() {
        // Midpoint rule in a over 2·10^5 panels: error O(h²) ≈ 1e-9 relative.
        let (af, a1) = (
            breaking_contact_radius(E, R, W),
            (2.0 * PI * W * R * R / E).cbrt(),
        );
        let n = 200_000;
        let h = (a1 - af) / n as f64;
        let mut area = 0.0;
        for k in 0..n {
            let a = af + (k as f64 + 0.5) * h;
            let slope = (overlap_at(E, R, W, a + 0.5 * h) - overlap_at(E, R, W, a - 0.5 * h)) / h;
            area -= force_at(E, R, W, a) * slope * h;
        }
        assert_relative_eq!(loop_energy(E, R, W), area, max_relative = 1e-7);
        assert!(loop_energy(E, R, W) > 0.0);
    }

    #[test]
    fn the_sticking_velocity_scales_as_the_dimensional_analysis_says() {
        // v_s = C (F_c⁵/(E*² R* m*³))^{1/6} with a constant C fixed by the JKR curve alone:
        // the same C for two very different pairs, to round-off of the closed forms.
        let c = |e: f64, r: f64, m: f64, w: f64| {
            let fc = pull_off_force(w, r);
            sticking_velocity(e, r, m, w) / (fc.powi(5) / (e * e * r * m.powi(3))).powf(1.0 / 6.0)
        };
        let first = c(E, R, 1e-5, W);
        assert_relative_eq!(first, c(7e9, 3e-5, 2e-10, 0.3), max_relative = 1e-10);
        assert_relative_eq!(first, 1.0348, max_relative = 1e-4);
    }
}

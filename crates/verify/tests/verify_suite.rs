//! Runs every verification case of docs/physics.md §9 at the fast resolution and requires every row
//! to pass within the tolerance the spec documents for it (each case's module explains its
//! tolerance; the fast resolution uses 1000 steps per contact, see `Resolution`).

use std::sync::OnceLock;

use verify::{cot, run_all, Resolution, Row};

/// The whole suite's rows at the fast resolution, run once for the tests that read them.
fn fast_rows() -> &'static [Row] {
    static ROWS: OnceLock<Vec<Row>> = OnceLock::new();
    ROWS.get_or_init(|| run_all(Resolution::Fast))
}

fn failures(rows: &[Row]) -> String {
    rows.iter()
        .filter(|r| !r.pass)
        .map(|r| {
            format!(
                "{} {}: expected {} measured {} tolerance {}\n",
                r.test, r.quantity, r.expected, r.measured, r.tolerance
            )
        })
        .collect()
}

#[test]
fn every_verification_row_passes_at_fast_resolution() {
    let failed = failures(fast_rows());
    assert!(failed.is_empty(), "failing rows:\n{failed}");
}

#[test]
fn the_rows_with_tolerances_from_the_step_count_pass_at_full_resolution() {
    // H1 (discretisation, as 1/N² and 1/N of the steps per contact) and W1–W3 (round-off,
    // from the steps run and the coordinates' size) scale their tolerances with the
    // resolution; `hopperflow verify` runs the full one, which the suite above does not.
    // These four cases take well under a second at full resolution.
    let mut rows = Vec::new();
    for case in [
        verify::h1::run,
        verify::w1::run,
        verify::w2::run,
        verify::w3::run,
    ] {
        match case(Resolution::Full) {
            Ok(r) => rows.extend(r),
            Err(e) => rows.push(Row::failed("full", &e.to_string())),
        }
    }
    // 14 + 10 + 6 + 4 rows, as `every_case_reports_exactly_its_rows` counts them.
    assert_eq!(rows.len(), 34);
    let failed = failures(&rows);
    assert!(failed.is_empty(), "failing rows:\n{failed}");
}

#[test]
fn the_cohesion_rows_pass_at_full_resolution() {
    // J1–J3 tie their tolerances for the break, the rupture and the impact energies to the
    // step of the sweep or the impact, 1/N; `hopperflow verify` runs the full N.
    let mut rows = Vec::new();
    for case in [verify::j1::run, verify::j2::run, verify::j3::run] {
        match case(Resolution::Full) {
            Ok(r) => rows.extend(r),
            Err(e) => rows.push(Row::failed("full", &e.to_string())),
        }
    }
    assert_eq!(rows.len(), 14);
    let failed = failures(&rows);
    assert!(failed.is_empty(), "failing rows:\n{failed}");
}

#[test]
fn every_case_reports_exactly_its_rows() {
    // A case that silently dropped rows (an early return, a skipped loop) would still pass the
    // test above. Each count follows from the case's structure, which its module documents.
    let expected = [
        // 2 materials × (δ_max, F_max, t_c, rebound speed, F–δ curve).
        ("CO1", 10),
        ("CO2", 10),
        // 2 materials × 5 e_in, 3 Table-1 targets × 3 speeds, 9 clamped e_in.
        ("CO3", 28),
        // Al oxide 6 stick angles × (e_t, ω', θ_r) and 6 sliding angles × 3, Al alloy 6 stick
        // angles × (e_t, θ_r), 2 Mindlin–Deresiewicz rows at 10°.
        ("CO4", 50),
        // 2 materials × (5 sliding β_t, 4 sliding tan θ_r from 70°, 9 stick β_t).
        ("CO5", 36),
        // 11 Ψ1 × (Ψ2 and Ω at ν = 0.30, Ψ2 at ν = 0.25, Ψ2 and Ω for Table 1), 3 separation rows.
        ("CO-T", 58),
        // pp e = 1 (3), pp e = 0.2 (2), rigid wall (2), same-material wall (2), production Δt (1).
        ("P1", 10),
        // 2 pairs × (δ_max, F_max, t_c, e and momentum at e = 1; e and momentum damped).
        ("H1", 14),
        // stop time, distance, creep after the stop, creep at 20°, acceleration at 35°.
        ("A1", 5),
        // One launch (Fast): t1, s1, v1, s2, t2.
        ("A2", 5),
        // a at 30°, a and α at 70°, threshold, EPSD creep, CDT creep, CDT spin.
        ("A3", 7),
        // no-slip curve, cap, engine-run slope and ξ growth; Mindlin–Deresiewicz curve, cap,
        // finite-difference slope, k_t(0); rotated |ξ| and ξ·n.
        ("A4", 10),
        // 4 places at rest × (motion gap, contact count), rolling × (gap, count).
        ("W1", 10),
        // 3 drops (edge, corner, face diagonal) × (rebound gap, contact count).
        ("W2", 6),
        // cylinder and cone × inside and outside.
        ("W3", 4),
        // energy drift, spheres inside.
        ("W4", 2),
        // plane and mesh conveyor × (contact-point speed, centre speed).
        ("W5", 4),
        // per-triangle sum against the total, normal force against the weight.
        ("W6", 2),
        // curve, no force before touching, least force, break, loop energy.
        ("J1", 5),
        // stick at 0.9 v_s, part at 1.1 v_s, parting speed and v_s at 2 v_s.
        ("J2", 4),
        // no force before touching, overlapping and gap curves, rupture, impact energy.
        ("J3", 5),
        // curve, no force across the gap, parting speed.
        ("J4", 3),
        // energy, carried momentum, flip interval, peak of ω₂.
        ("RB1", 4),
        // spin constancy, body-frame and world precession rates.
        ("RB2", 3),
        // one bead × 2, dumbbell × 2, lens, rod × 3.
        ("RB3", 8),
        // slide: held, acceleration, no turn; tip: held, tipped.
        ("RB4", 5),
    ];
    let rows = fast_rows();
    for (case, n) in expected {
        let count = rows.iter().filter(|r| r.test == case).count();
        assert_eq!(count, n, "case {case} reported {count} rows, expected {n}");
    }
    // No rows outside the listed cases.
    let total: usize = expected.iter().map(|(_, n)| n).sum();
    assert_eq!(rows.len(), total);
}

#[test]
fn the_poisson_separation_rows_fail_when_both_series_share_one_ratio() {
    // The separation rows exist because the per-point CO-T tolerance (0.05) exceeds the whole
    // difference between the ν = 0.25 and ν = 0.30 series (≤ 0.040). They must pass with the
    // right ratios and fail when either series is run at the other's ratio, or the two swapped.
    for psi1 in cot::SEPARATION_PSI1 {
        let nu25 = cot::elastic_psi2(0.25, psi1, Resolution::Fast).unwrap_or(f64::NAN);
        let nu30 = cot::elastic_psi2(0.30, psi1, Resolution::Fast).unwrap_or(f64::NAN);
        assert!(cot::separation_row(psi1, nu25, nu30).pass, "Ψ1 = {psi1}");
        assert!(!cot::separation_row(psi1, nu30, nu30).pass, "Ψ1 = {psi1}");
        assert!(!cot::separation_row(psi1, nu25, nu25).pass, "Ψ1 = {psi1}");
        assert!(!cot::separation_row(psi1, nu30, nu25).pass, "Ψ1 = {psi1}");
    }
}

#[test]
fn the_engine_run_slope_row_tells_the_no_slip_law_from_mindlin_deresiewicz() {
    // The A4 slope row measures the chord of F_t(ξ) between ξ = δ_slip/8 and δ_slip/2. For the
    // Mindlin–Deresiewicz law, F_t = μF_ne(1 − (1 − z)^{3/2}) with z from 1/12 to 1/3, that chord
    // is (0.4557 − 0.1223)/0.25 = 1.334 μF_ne/δ_t,max = 0.889 S_t; its dashpot, which softens
    // with k_t(ξ), moves it by a few thousandths, hence the 0.01 band. Either way the row,
    // held to 1e-10, would fail.
    let material = dem::Material::fan2023();
    let g_star = dem::material::effective_shear_modulus(&material, Some(&material));
    let held = verify::a4::held_contact(2.0e-5, 0.5, dem::TangentialLaw::MindlinDeresiewicz);
    let held = held.unwrap_or(verify::a4::HeldContact {
        overlap: f64::NAN,
        slope: f64::NAN,
        displacement_ratio: f64::NAN,
    });
    let ratio = held.slope / (8.0 * g_star * (1.5e-3 * held.overlap).sqrt());
    assert!((ratio - 0.889).abs() < 0.01, "chord over S_t {ratio}");
}

#[test]
fn mindlin_deresiewicz_law_fails_the_no_slip_reference_at_ten_degrees() {
    // The discriminating check of CO4 only has value if the two laws really differ there:
    // the §3.3 law gives e_t(10°) = 0.596 against the §3.1 reference 0.703, a gap of 0.107,
    // five times the 0.02 tolerance.
    let rows = verify::co4::run(Resolution::Fast).unwrap_or_default();
    let get = |q: &str| {
        rows.iter()
            .find(|r| r.quantity == q)
            .map(|r| r.measured)
            .unwrap_or(f64::NAN)
    };
    let no_slip = get("Al oxide 10°: e_t [-]");
    let deresiewicz = get("Al oxide 10°, Mindlin-Deresiewicz law: e_t [-]");
    assert!(
        (no_slip - deresiewicz).abs() > 0.08,
        "{no_slip} vs {deresiewicz}"
    );
}

#[test]
fn rows_serialise_to_json_and_back_unchanged() {
    let rows = verify::a4::run(Resolution::Fast).unwrap_or_default();
    assert!(!rows.is_empty());
    let text = serde_json::to_string(&rows).unwrap_or_default();
    let back: Vec<Row> = serde_json::from_str(&text).unwrap_or_default();
    assert_eq!(back.len(), rows.len());
    for (a, b) in rows.iter().zip(&back) {
        // serde_json prints the shortest round-tripping decimal; allow the last ulp anyway.
        assert_eq!(a.test, b.test);
        assert_eq!(a.pass, b.pass);
        assert!((a.measured - b.measured).abs() <= 2.0 * f64::EPSILON * a.measured.abs());
    }
}

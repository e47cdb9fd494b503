//! Tests of the integrator: the flat form against the per-body form bit for bit, the
//! parallel ranges against one pass, and the displacement reductions.

use super::*;
use crate::particles::{MaterialId, ParticleInit};
use rand::{Rng, SeedableRng};

/// Gravity [m/s²] with three unequal components, so that a weight written from the
/// wrong component of the flat force array shows.
const G: DVec3 = DVec3::new(0.3, -1.7, -9.81);

/// The flat, many-lane pass must give the box of the displacements exactly: the same
/// extremes, in every component, as one body at a time, for counts below, at and past
/// the 24 numbers of a vector chunk. Displacements are uniform in a cube of ±50 µm, so
/// the extremes fall on different bodies and lanes from one count to the next.
#[test]
fn displacement_box_is_that_of_one_body_at_a_time() {
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(11);
    for n in [0, 1, 2, 7, 8, 9, 23, 24, 25, 64, 203] {
        let reference: Vec<DVec3> = (0..n)
            .map(|_| DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 0.1)
            .collect();
        let position: Vec<DVec3> = reference
            .iter()
            .map(|r| *r + DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 1e-4 - 5e-5)
            .collect();
        let (lo, hi) = position.iter().zip(&reference).fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), (x, r)| (lo.min(*x - *r), hi.max(*x - *r)),
        );
        let expected = if n == 0 { 0.0 } else { (hi - lo).length() };
        // Exact: extremes are found, not computed, and the diagonal is the same formula.
        assert_eq!(
            displacement_box_diagonal(&position, &reference).to_bits(),
            expected.to_bits(),
            "{n} bodies"
        );
    }
}

/// 203 equal free spheres (not a multiple of the vector width, so the remainder loop
/// runs too) with random positions, velocities, spins, forces and torques.
fn bed(seed: u64) -> (ParticleSet, Vec<DVec3>) {
    bed_of(seed, 203)
}

/// [`bed`] with `n` particles.
fn bed_of(seed: u64, n: usize) -> (ParticleSet, Vec<DVec3>) {
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut u = move |s: f64| DVec3::new(rng.gen(), rng.gen(), rng.gen()) * s - s / 2.0;
    let mut p = ParticleSet::default();
    let mut reference = Vec::new();
    for _ in 0..n {
        let mut init = ParticleInit::at_rest(u(0.1), 1.5e-3, MaterialId(0));
        init.velocity = u(2.0);
        init.angular_velocity = u(500.0);
        p.push(&init, 2500.0);
        reference.push(init.position + u(1e-4));
    }
    for k in 0..p.len() {
        p.force[k] = u(1e-2);
        p.torque[k] = u(1e-5);
    }
    (p, reference)
}

#[test]
fn flat_form_is_bit_identical_to_the_particle_by_particle_form() {
    // The flat form claims the same operations per component in the same order, so
    // every number must agree exactly, with and without a pending kick.
    for (seed, pending) in [(1, false), (2, true)] {
        let (mut general, reference) = bed(seed);
        let mut flat = general.clone();
        let uniform = uniform_free_body(&flat);
        assert!(uniform.is_some(), "equal free spheres share one body");
        let (half, dt) = (1.25e-6, 2.5e-6);
        let a = kick_drift_per_body(Bodies::of(&mut general, &reference), (half, dt), G, pending);
        let b = kick_drift(&mut flat, &reference, (half, dt), pending, uniform, G, None);
        assert_eq!(a, b, "displacement and probes");
        assert_eq!(general.position, flat.position);
        assert_eq!(general.velocity, flat.velocity);
        assert_eq!(general.omega, flat.omega);
        // Both forms leave the evaluation's starting values: the weight m g, the same
        // product as `forces::start` forms, exactly, and zero torque.
        for p in [&general, &flat] {
            for k in 0..p.len() {
                assert_eq!(p.force[k], p.mass[k] * G, "particle {k}");
                assert_eq!(p.torque[k], DVec3::ZERO, "particle {k}");
            }
        }
        assert_eq!(
            kick_per_body(&mut general, half),
            kick(&mut flat, half, uniform)
        );
        assert_eq!(general.velocity, flat.velocity);
        assert_eq!(general.omega, flat.omega);
    }
}

#[test]
fn flat_form_reports_what_the_general_form_reports() {
    // A NaN force must fail the velocity probe of `kick`, and a displaced particle
    // must give the largest displacement, in both forms.
    let (mut general, _) = bed(3);
    general.force[150].y = f64::NAN;
    let mut flat = general.clone();
    let uniform = uniform_free_body(&flat);
    assert!(!kick_per_body(&mut general, 1e-6));
    assert!(!kick(&mut flat, 1e-6, uniform));
    let (mut general, mut reference2) = bed(4);
    reference2[77] -= DVec3::new(0.0, 0.0, 5e-3);
    let mut flat = general.clone();
    let uniform = uniform_free_body(&flat);
    let a = kick_drift_per_body(
        Bodies::of(&mut general, &reference2),
        (1e-6, 2e-6),
        G,
        false,
    );
    let b = kick_drift(
        &mut flat,
        &reference2,
        (1e-6, 2e-6),
        false,
        uniform,
        G,
        None,
    );
    assert_eq!(a, b);
    assert!(
        a.0 >= 2.4e-5,
        "the moved particle sets the maximum: {}",
        a.0
    );
}

#[test]
fn flags_or_unequal_bodies_take_the_general_form() {
    let (mut p, _) = bed(5);
    assert!(uniform_free_body(&p).is_some());
    p.flags[10] = FLAG_ROTATION_LOCKED;
    assert!(uniform_free_body(&p).is_none(), "a flag");
    let (mut p, _) = bed(5);
    p.inv_mass[3] *= 2.0;
    assert!(uniform_free_body(&p).is_none(), "a different mass");
}

#[test]
fn parallel_ranges_match_one_pass_bit_for_bit() {
    // With a pool the particles are moved in ranges on several threads. Each particle's
    // arithmetic is unchanged and the reductions are a maximum and two flags, so every
    // number and the reported maximum must agree exactly, in both forms. 10 000 particles
    // on three threads make twelve ranges; the largest displacement and a NaN force are
    // placed in a late range, so that the merge, not the first range, must carry them.
    let pool = crate::team::Team::new(3).expect("a three-thread pool");
    for general in [false, true] {
        for pending in [false, true] {
            let (mut one, mut reference) = bed_of(7, 10_000);
            reference[9000] -= DVec3::new(0.0, 3e-3, 0.0);
            if general {
                one.flags[40] = FLAG_ROTATION_LOCKED;
            }
            let mut many = one.clone();
            let uniform = uniform_free_body(&one);
            assert_eq!(uniform.is_none(), general);
            let step = (1.25e-6, 2.5e-6);
            let a = kick_drift(&mut one, &reference, step, pending, uniform, G, None);
            let b = kick_drift(
                &mut many,
                &reference,
                step,
                pending,
                uniform,
                G,
                Some(&pool),
            );
            assert_eq!(a, b, "displacement and probes");
            // Moved 3 mm from a reference within 0.1 mm of it: d² ≥ (2.9 mm)².
            assert!(
                a.0 >= 8.4e-6,
                "the moved particle sets the maximum: {}",
                a.0
            );
            assert_eq!(one.position, many.position);
            assert_eq!(one.velocity, many.velocity);
            assert_eq!(one.omega, many.omega);
            assert_eq!(one.force, many.force, "the weights");
            assert_eq!(one.torque, many.torque);
        }
    }
    let (mut one, reference) = bed_of(8, 10_000);
    one.force[9500].x = f64::NAN;
    let mut many = one.clone();
    let uniform = uniform_free_body(&one);
    let step = (1.25e-6, 2.5e-6);
    let a = kick_drift(&mut one, &reference, step, true, uniform, G, None);
    let b = kick_drift(&mut many, &reference, step, true, uniform, G, Some(&pool));
    assert!(
        !a.2 && !b.2,
        "a NaN force fails the velocity probe on any thread count"
    );
    assert!(!a.1 && !b.1, "and the position probe");
}

#[test]
fn the_tracked_flat_pass_on_a_pool_matches_one_thread_bit_for_bit() {
    // The pass the simulation takes for alike free bodies, with and without the
    // displacement measure, on one thread and on a three-thread pool (twelve ranges): the
    // same bodies and the same findings, the step's reach included. The largest velocity and
    // displacement sit in a late range, so that the merge must carry them.
    let pool = crate::team::Team::new(3).expect("a three-thread pool");
    for measure in [false, true] {
        let (mut one, mut reference) = bed_of(9, 10_000);
        reference[9100] -= DVec3::new(0.0, 0.0, 2e-3);
        one.velocity[9200] = DVec3::new(0.0, 0.0, -3.0);
        let mut many = one.clone();
        let uniform = uniform_free_body(&one).expect("alike free bodies");
        let step = (1.25e-6, 2.5e-6);
        let a = kick_drift_flat_tracked(
            &mut one,
            &reference,
            step,
            true,
            uniform,
            (G, measure),
            None,
        );
        let b = kick_drift_flat_tracked(
            &mut many,
            &reference,
            step,
            true,
            uniform,
            (G, measure),
            Some(&pool),
        );
        assert_eq!(a.max_disp2, b.max_disp2);
        assert_eq!(a.max_disp2.is_some(), measure);
        assert_eq!((a.finite, a.kicked_finite), (b.finite, b.kicked_finite));
        assert_eq!(a.reach.to_bits(), b.reach.to_bits());
        // 3 m/s over 2.5 µs: the reach is at least 7.5 µm.
        assert!(a.reach >= 7.4e-6, "reach {}", a.reach);
        assert_eq!(one.position, many.position);
        assert_eq!(one.velocity, many.velocity);
        assert_eq!(one.omega, many.omega);
        assert_eq!(one.force, many.force, "the weights");
    }
}

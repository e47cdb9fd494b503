//! Results do not depend on the number of worker threads: forces are evaluated in parallel
//! chunks but each body receives them in a fixed order (docs/physics.md §6.2; forces/parallel.rs).

use crate::common;

use common::{bits_by_tag, Gas};
use dem::{Simulation, SimulationConfig};

/// 1000 Table-1 spheres on a cubic lattice 3.1 mm apart with random velocities up to 0.5 m/s,
/// falling into a closed box under gravity, with friction, rolling friction and e = 0.2.
/// Each interior sphere has six lattice neighbours inside the 3.3 mm list cutoff (d + skin), so
/// the candidate list holds ≈ 2700 pairs: six 512-pair parallel chunks, and the 1000 bodies
/// make seven ranges of the parallel accumulation and wall pass (at least 128 bodies each)
/// and three of the kick and drift (at least 256), so the two threads share every pass.
pub fn pile(threads: usize) -> Gas {
    let mut config = SimulationConfig::new(2.5e-6);
    config.threads = threads;
    common::pile(config)
}

/// Runs `one` and `two` 20 × 100 steps side by side, requiring the same bits after each
/// hundred; returns the most particle–particle contacts `one` had at those looks.
fn run_side_by_side(one: &mut Simulation, two: &mut Simulation) -> usize {
    let mut contacts = 0;
    for _ in 0..20 {
        one.run(100).expect("serial run");
        two.run(100).expect("parallel run");
        contacts = contacts.max(one.contacts().particle_particle);
        // Exact equality: the engine promises bit-identical sums at any thread count.
        assert!(
            bits_by_tag(one) == bits_by_tag(two),
            "runs diverged by t = {} s",
            one.time()
        );
    }
    contacts
}

#[test]
fn same_run_on_one_and_two_threads_is_bit_identical() {
    let mut one = pile(1).build();
    let mut two = pile(2).build();
    let contacts = run_side_by_side(&mut one, &mut two);
    assert!(
        contacts > 100,
        "the pile must collide for the comparison to mean anything ({contacts} contacts)"
    );
}

#[test]
fn thread_count_can_change_mid_run_without_changing_the_result() {
    let mut reference = pile(1).build();
    let mut switched = pile(1).build();
    reference.run(1000).expect("serial run");
    switched.run(500).expect("serial part");
    switched.set_threads(2).expect("a two-thread pool starts");
    switched.run(500).expect("parallel part");
    // Exact equality, as above.
    assert!(bits_by_tag(&reference) == bits_by_tag(&switched));
}

#[test]
fn run_with_fused_kicks_matches_single_steps_bit_for_bit() {
    // `run(n)` does each step's second half kick in the next step's first pass; the
    // additions are the same, so the state must be exactly that of n calls to `step`.
    let mut fused = pile(1).build();
    let mut single = pile(1).build();
    for _ in 0..10 {
        fused.run(97).expect("fused run");
        for _ in 0..97 {
            single.step().expect("single steps");
        }
        assert!(
            bits_by_tag(&fused) == bits_by_tag(&single),
            "diverged by t = {} s",
            fused.time()
        );
    }
    assert!(
        fused.contacts().particle_particle > 100,
        "the pile must collide"
    );
}

#[test]
fn timing_the_phases_changes_no_bit_and_accounts_for_every_step() {
    let mut plain = pile(1).build();
    let mut timed = pile(1).build();
    timed.time_phases(true);
    let start = std::time::Instant::now();
    for _ in 0..5 {
        plain.run(100).expect("untimed run");
        timed.run(100).expect("timed run");
    }
    let elapsed = start.elapsed().as_secs_f64();
    // Exact equality: timing only reads the clock.
    assert!(bits_by_tag(&plain) == bits_by_tag(&timed));
    let t = timed.phase_times().expect("timing is on");
    assert_eq!(t.steps, 500);
    assert_eq!(plain.phase_times(), None);
    // The phases lie inside the timed steps, which lie inside `elapsed` (which also holds the
    // untimed run), and every phase does work: the pile collides (forces), moves (integrate)
    // and is listed at least once (neighbour).
    assert!(t.total() <= elapsed, "{t:?} against {elapsed} s");
    assert!(
        t.integrate > 0.0 && t.neighbour > 0.0 && t.forces > 0.0,
        "{t:?}"
    );
    // Switching off forgets the totals; on again starts from zero.
    timed.time_phases(false);
    assert_eq!(timed.phase_times(), None);
    timed.time_phases(true);
    assert_eq!(timed.phase_times().map(|t| t.steps), Some(0));
}

#[test]
fn large_one_thread_runs_that_move_bodies_inside_the_evaluation_keep_every_bit() {
    // Past 2^15 bodies, a one-thread `run` does each step's kicks and drift inside the
    // previous step's evaluation, chunk by chunk of 16 384 bodies (forces/chunked.rs). The
    // pile's 40 000 spheres (three chunks) must end exactly where single steps (which never
    // fuse), two threads (which do not either) and a watched run (which does not fuse across
    // a look) take them, across list rebuilds.
    let big = |threads| Gas {
        count: 40_000,
        ..pile(threads)
    };
    let mut fused = big(1).build();
    let mut single = big(1).build();
    let mut two = big(2).build();
    // Looks every 40 steps end three of the fused stretches early (`run_watched`).
    let mut watched = big(1).build();
    fused.run(150).expect("fused run");
    watched
        .run_watched(150, 40, |_| Ok::<(), dem::DemError>(()))
        .expect("watched run");
    for _ in 0..150 {
        single.step().expect("single steps");
    }
    two.run(150).expect("parallel run");
    // Exact equality, as above.
    let bits = bits_by_tag(&fused);
    assert!(bits == bits_by_tag(&single), "fused against single steps");
    assert!(bits == bits_by_tag(&two), "fused against two threads");
    assert!(bits == bits_by_tag(&watched), "fused against a watched run");
    assert_eq!(fused.contacts(), single.contacts());
    // The comparison must cover collisions and a rebuild after the first list.
    assert!(
        fused.contacts().particle_particle > 1000,
        "{:?}",
        fused.contacts()
    );
    assert!(fused.rebuilds() >= 2, "{} list builds", fused.rebuilds());
}

/// A bidisperse bed with diameters 3 and 9 mm (ratio 3, where the candidate search goes by
/// size class) in a closed box 4 × 9.3 mm wide: blocks of 3 × 3 × 3 lattice sites 3.1 mm
/// apart, half of them (at random) holding one large sphere at their centre and the rest
/// 27 small ones, 896 spheres in all, with random velocities up to 0.5 m/s, falling under
/// gravity.
fn bidisperse_pile(threads: usize) -> dem::Simulation {
    use dem::{DVec3, Interaction, Material, ParticleInit, Simulation, Wall, WallMaterial};
    use rand::{Rng, SeedableRng};
    let mut config = SimulationConfig::new(2.5e-6);
    config.threads = threads;
    let mut sim = Simulation::new(config).expect("valid configuration");
    let material = Material::fan2023();
    let id = sim
        .add_material(material, Interaction::fan2023())
        .expect("valid material");
    let (site, blocks) = (3.1e-3, 4usize);
    let edge = blocks as f64 * 3.0 * site;
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        for (point, normal) in [(DVec3::ZERO, axis), (edge * axis, -axis)] {
            let wall = Wall::plane(
                point,
                normal,
                WallMaterial::Elastic(material),
                Interaction::fan2023(),
            )
            .expect("valid plane");
            sim.add_wall(wall).expect("valid wall");
        }
    }
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(17);
    let velocity = |rng: &mut rand_xoshiro::Xoshiro256PlusPlus| loop {
        let v = DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 2.0 - DVec3::ONE;
        if v.length_squared() <= 1.0 {
            break v * 0.5;
        }
    };
    let mut large = vec![false; blocks.pow(3)];
    large[..blocks.pow(3) / 2].fill(true);
    for k in (1..large.len()).rev() {
        large.swap(k, rng.gen_range(0..=k));
    }
    for (b, &large) in large.iter().enumerate() {
        let corner = DVec3::new(
            (b % blocks) as f64,
            ((b / blocks) % blocks) as f64,
            (b / (blocks * blocks)) as f64,
        ) * 3.0
            * site;
        let spheres: Vec<(DVec3, f64)> = if large {
            vec![(corner + DVec3::splat(1.5 * site), 4.5e-3)]
        } else {
            (0..27)
                .map(|s| {
                    let cell = DVec3::new((s % 3) as f64, ((s / 3) % 3) as f64, (s / 9) as f64);
                    (corner + (cell + DVec3::splat(0.5)) * site, 1.5e-3)
                })
                .collect()
        };
        for (at, radius) in spheres {
            let mut init = ParticleInit::at_rest(at, radius, id);
            init.velocity = velocity(&mut rng);
            sim.add_particle(init).expect("valid particle");
        }
    }
    sim
}

#[test]
fn a_bidisperse_bed_on_one_and_two_threads_is_bit_identical() {
    let mut one = bidisperse_pile(1);
    let mut two = bidisperse_pile(2);
    assert_eq!(one.particles().len(), 32 + 32 * 27);
    let contacts = run_side_by_side(&mut one, &mut two);
    assert!(
        contacts > 100 && one.rebuilds() > 1,
        "the bed must collide and rebuild its lists for the comparison to mean anything \
         ({contacts} contacts, {} builds)",
        one.rebuilds()
    );
}

//! Tests of the force evaluation: the batched kernels against the general laws, the
//! filters against their definitions, and the fixtures other force tests share.

use rand::{Rng, SeedableRng};

use super::bond_rows::BondTables;
use super::filter::{live_history, note_live, plane_touches};
use super::*;
use crate::contact::geometry::plane_distance;
use crate::contact::ContactHistory;
use crate::history::{HistoryArrays, LIVE};
use crate::material::{Interaction, Material, WallMaterial};
use crate::neighbour::{build_lists, CellGrid, PairSearch};
use crate::particles::{MaterialId, ParticleInit};

/// Keeps every contact, in order, for tests that sum them their own way.
impl PairSink for Vec<(u32, u32, ContactForce)> {
    fn contact(&mut self, i: usize, j: usize, cf: &ContactForce) {
        self.push((i as u32, j as u32, *cf));
    }
}

/// A jumble of spheres in a box of planes with one tilted polygon, moving and spinning,
/// with random tangential histories: every branch of both kernels is reached.
pub(super) fn jumble(materials: usize, polydisperse: bool) -> (ParticleSet, Vec<Option<Wall>>) {
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(5);
    let mut set = ParticleSet::default();
    let mut v = |s: f64| {
        DVec3::new(
            rng.gen::<f64>() - 0.5,
            rng.gen::<f64>() - 0.5,
            rng.gen::<f64>() - 0.5,
        ) * s
    };
    for k in 0..600 {
        let r = if polydisperse {
            1.5e-3 * (1.0 + 0.3 * (k % 7) as f64 / 7.0)
        } else {
            1.5e-3
        };
        let mut init = ParticleInit::at_rest(
            DVec3::splat(0.0125) + v(0.025),
            r,
            MaterialId((k % materials) as u16),
        );
        init.velocity = v(2.0);
        init.angular_velocity = v(400.0);
        set.push(&init, 2500.0 * (1.0 + (k % materials) as f64));
    }
    let m = WallMaterial::Elastic(Material::fan2023());
    let i = Interaction::fan2023();
    let mut walls: Vec<Option<Wall>> = vec![
        Some(Wall::plane(DVec3::ZERO, DVec3::Z, m, i).unwrap()),
        Some(
            Wall::plane(
                DVec3::new(0.025, 0.0, 0.0),
                -DVec3::X,
                WallMaterial::Rigid,
                i,
            )
            .unwrap(),
        ),
        None,
        Some(
            Wall::polygon(
                vec![
                    DVec3::new(0.0, 0.0, 0.02),
                    DVec3::new(0.02, 0.0, 0.01),
                    DVec3::new(0.02, 0.02, 0.01),
                    DVec3::new(0.0, 0.02, 0.02),
                ],
                m,
                Interaction { friction: 0.3, ..i },
            )
            .unwrap(),
        ),
    ];
    walls[0].as_mut().unwrap().velocity = DVec3::new(0.1, 0.0, 0.0);
    (set, walls)
}

#[test]
fn a_batch_finds_the_same_worst_overlap_as_one_contact_at_a_time() {
    // `see_batch` skips the walk when the bits' maximum says nothing beats the worst so
    // far; it must never skip a batch that holds a larger fraction. Random batches of
    // fractions, some negative, zero, NaN or tiny, against `see` on every contact: the
    // same fraction and index, exactly.
    use rand::{Rng, SeedableRng};
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(5);
    let mut batch = Batch::default();
    let (mut batched, mut single) = (WorstOverlap::default(), WorstOverlap::default());
    for b in 0..2000 {
        batch.len = rng.gen_range(0..=BATCH);
        for f in &mut batch.overlap_fraction[..batch.len] {
            *f = match rng.gen_range(0..8) {
                0 => -rng.gen::<f64>(),
                1 => 0.0,
                2 => f64::NAN,
                3 => 1e-300 * rng.gen::<f64>(),
                // Growing slowly, so later batches still beat the worst now and then.
                _ => 0.05 * rng.gen::<f64>() * (1.0 + b as f64 / 500.0),
            };
        }
        let base = BATCH * b;
        batched.see_batch(&batch, base..);
        for (m, &f) in batch.overlap_fraction[..batch.len].iter().enumerate() {
            single.see(f, base + m);
        }
        assert_eq!(
            batched.fraction.to_bits(),
            single.fraction.to_bits(),
            "batch {b}"
        );
        assert_eq!(batched.index, single.index, "batch {b}");
    }
    assert!(
        single.fraction > 0.05,
        "the worst grew past the first batches'"
    );
}

#[test]
fn split_plane_filter_matches_the_per_candidate_test() {
    // The three passes of the equal-sphere plane filter against the one-candidate-at-a-
    // time definition: the same touching list, histories kept bit for bit or forgotten,
    // for a contiguous run (the slab faces' stream) and for a run with gaps (the
    // gathered path), with a NaN position counted as touching. Exact equality: both
    // evaluate the same expression on the same numbers.
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(3);
    let r = 1.5e-3;
    let mut pos: Vec<DVec3> = (0..200)
        .map(|_| DVec3::new(rng.gen(), rng.gen::<f64>() * 4e-3, rng.gen()))
        .collect();
    pos[17] = DVec3::new(0.5, f64::NAN, 0.5);
    let (normal, offset) = (DVec3::new(0.0, 1.0, 0.0), 0.0);
    let contiguous: Vec<u32> = (10..150).collect();
    let gapped: Vec<u32> = (0..200).filter(|k| k % 3 != 1).collect();
    for pi in [contiguous, gapped] {
        let old: Vec<DVec3> = (0..pi.len())
            .map(|k| DVec3::splat(k as f64 + 1.0))
            .collect();
        let expect_touch: Vec<bool> = pi
            .iter()
            .map(|&i| !(plane_distance(pos[i as usize], normal, offset) >= r))
            .collect();
        // Every third contact had already opened (not live) before this filter.
        let before: Vec<u8> = (0..pi.len()).map(|k| u8::from(k % 3 != 0)).collect();
        let (mut touch, mut hits, mut history) = (
            vec![9u8; pi.len()],
            vec![0u32; pi.len()],
            HistoryArrays::from(
                old.iter()
                    .map(|&t| ContactHistory {
                        tangential: t,
                        rolling: DVec3::ZERO,
                        bonded: false,
                    })
                    .collect::<Vec<_>>(),
            ),
        );
        history.live.copy_from_slice(&before);
        plane_touches(&pos, &pi, (normal, offset, r), &mut touch);
        note_live(&touch, &mut history.live);
        let count = compact::from_bytes(&touch, &mut hits);
        let expect_hits: Vec<u32> = (0..pi.len() as u32)
            .filter(|&k| expect_touch[k as usize])
            .collect();
        assert!(count > 10 && count < pi.len(), "both outcomes occur");
        assert_eq!(&hits[..count], &expect_hits[..]);
        let nan = pi
            .iter()
            .position(|&i| i == 17)
            .expect("both runs hold particle 17");
        assert!(
            hits[..count].contains(&(nan as u32)),
            "a NaN distance counts as touching"
        );
        for (k, o) in old.iter().enumerate() {
            // Touching: live, and the gather sees ξ only if it was live before.
            // Separated: the history reads as zero (§3.1).
            let was = before[k] == LIVE;
            let kept = if expect_touch[k] && was {
                *o
            } else {
                DVec3::ZERO
            };
            let flags = history.live[k];
            let seen = if expect_touch[k] {
                live_history(flags, history.tangential[k])
            } else {
                history.get(k).tangential
            };
            assert_eq!(flags & LIVE == LIVE, expect_touch[k]);
            assert_eq!(
                seen.to_array().map(f64::to_bits),
                kept.to_array().map(f64::to_bits)
            );
        }
    }
}

/// Everything an evaluation leaves behind, as bits.
pub(super) fn bits(
    buffers: &ForceBuffers,
    pairs: &PairList,
    walls: &WallPairList,
    eval: &Evaluation,
) -> Vec<u64> {
    let histories = pairs.history.iter().chain(walls.history.iter());
    let vectors = buffers
        .force
        .iter()
        .copied()
        .chain(buffers.torque.iter().copied())
        .chain(histories.flat_map(|h| [h.tangential, h.rolling]));
    let mut out: Vec<u64> = vectors
        .flat_map(|v| v.to_array().map(f64::to_bits))
        .collect();
    out.extend([
        eval.count.particle_particle as u64,
        eval.count.particle_wall as u64,
        eval.worst_pair.index as u64,
        eval.worst_pair.fraction.to_bits(),
        eval.worst_wall.index as u64,
        eval.worst_wall.fraction.to_bits(),
    ]);
    out
}

/// The jumble with everything an evaluation needs: coefficients of its materials and
/// walls, and gravity.
pub(super) struct Jumble {
    pub set: ParticleSet,
    pub walls: Vec<Option<Wall>>,
    pub pair_coeffs: Vec<PairCoefficients>,
    pub wall_coeffs: Vec<PairCoefficients>,
    pub materials: usize,
    pub poly: bool,
    /// Gravitational acceleration [m/s²].
    pub gravity: DVec3,
}

impl Jumble {
    pub fn new(materials: usize, poly: bool) -> Self {
        let (set, walls) = jumble(materials, poly);
        let mats: Vec<Material> = (0..materials)
            .map(|k| Material {
                density: 2500.0 * (1.0 + k as f64),
                ..Material::fan2023()
            })
            .collect();
        let i = Interaction::fan2023();
        let mut pair_coeffs = Vec::new();
        for a in &mats {
            for b in &mats {
                pair_coeffs.push(PairCoefficients::new(a, Some(b), &i));
            }
        }
        let mut wall_coeffs = Vec::new();
        for w in &walls {
            for a in &mats {
                wall_coeffs.push(match w {
                    Some(w) => PairCoefficients::with_wall(a, &w.material, &w.interaction),
                    None => PairCoefficients::new(a, None, &i),
                });
            }
        }
        Self {
            set,
            walls,
            pair_coeffs,
            wall_coeffs,
            materials,
            poly,
            gravity: DVec3::new(0.0, -9.81, 0.0),
        }
    }

    /// Candidate lists with random tangential histories (and rolling ones, for the
    /// laws that keep them).
    pub fn lists(&self) -> (PairList, WallPairList) {
        let skin = 3e-4;
        let grid = CellGrid::build(&self.set.position, 2.0 * 1.5e-3 * 1.3 + skin);
        let (mut pairs, mut wall_pairs) = (PairList::default(), WallPairList::default());
        build_lists(
            PairSearch::Cells(&grid),
            &self.set,
            &self.walls,
            skin,
            &PairList::default(),
            &mut WallPairList::default(),
            crate::neighbour::Carry::Same,
            (&mut pairs, &mut wall_pairs),
            &mut crate::neighbour::ListScratch::default(),
        );
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(9);
        let (t, r, _) = pairs.history.split_mut();
        let (wt, wr, _) = wall_pairs.history.split_mut();
        for h in t.iter_mut().chain(wt.iter_mut()) {
            *h = DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 2e-6;
        }
        for h in r.iter_mut().chain(wr.iter_mut()) {
            *h = DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 1e-9;
        }
        (pairs, wall_pairs)
    }
}

/// The kernel input of `jumble` under `laws`, with no bonding constants: a test whose
/// coefficients bond sets `bond_tables` to theirs ([`BondTables::of`]).
pub(super) fn jumble_input<'a>(jumble: &'a Jumble, laws: &'a ContactLaws) -> KernelInput<'a> {
    static NO_BONDS: BondTables = BondTables {
        pair: Vec::new(),
        wall: Vec::new(),
    };
    KernelInput {
        particles: &jumble.set,
        laws,
        pair_coeffs: &jumble.pair_coeffs,
        materials: jumble.materials,
        walls: &jumble.walls,
        wall_coeffs: &jumble.wall_coeffs,
        bond_tables: &NO_BONDS,
        uniform_body: (!jumble.poly).then(|| (jumble.set.radius[0], jumble.set.mass[0])),
        dt: 2.5e-6,
        quanta: Default::default(),
        pair_bonds: false,
        wall_bonds: false,
        area_cohesion: false,
        reach: 0.0,
    }
}

/// The scalar path's pair contacts summed onto `n` bodies: F and M_i on i, −F and M_j
/// on j.
fn summed(n: usize, contacts: Vec<(u32, u32, ContactForce)>) -> (Vec<DVec3>, Vec<DVec3>) {
    let (mut force, mut torque) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
    for (a, b, cf) in contacts {
        let (a, b) = (a as usize, b as usize);
        force[a] += cf.force;
        force[b] -= cf.force;
        torque[a] += cf.torque_i;
        torque[b] += cf.torque_j;
    }
    (force, torque)
}

/// The batched path on one thread over `pairs` and `wall_pairs`, from zero forces: its sums
/// and what it found.
fn batched_forces(
    input: &KernelInput,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
) -> (ForceBuffers, Evaluation) {
    let mut buffers = ForceBuffers::default();
    start(input.particles, DVec3::ZERO, &mut buffers);
    let eval = evaluate(input, pairs, wall_pairs, &mut buffers, None, &mut []);
    (buffers, eval)
}

/// The scalar path under `laws` over `pairs` and then `wall_pairs`, in list order: each
/// body's force and torque, and the worst pair overlap it saw.
fn scalar_forces(
    input: &KernelInput,
    laws: ContactLaws,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
) -> (Vec<DVec3>, Vec<DVec3>, WorstOverlap) {
    let ids = (&pairs.i.clone()[..], &pairs.j.clone()[..]);
    let mut contacts = Vec::new();
    let worst = pair_loop_with(
        input,
        laws,
        ids,
        0,
        pairs.history.split_mut(),
        &mut contacts,
    );
    let (mut force, mut torque) = summed(input.particles.len(), contacts);
    let wids = (
        &wall_pairs.particle.clone()[..],
        &wall_pairs.wall.clone()[..],
    );
    let mut loads = vec![Default::default(); input.walls.len()];
    wall_loop(
        input,
        wids,
        wall_pairs.history.split_mut(),
        &mut loads,
        |a, cf| {
            force[a] += cf.force;
            torque[a] += cf.torque_i;
        },
    );
    (force, torque, worst)
}

/// The batched path's sums in `buffers` against the scalar path's: the same formulas
/// with a few operations regrouped, so agreement to 1e-12 of each body's own force or
/// torque.
fn assert_close(buffers: &ForceBuffers, force: &[DVec3], torque: &[DVec3]) {
    for k in 0..force.len() {
        let f = force[k].length().max(1e-30);
        let t = torque[k].length().max(1e-30);
        assert!(
            (buffers.force[k] - force[k]).length() <= 1e-12 * f,
            "force {k}: {} against {}",
            buffers.force[k],
            force[k]
        );
        assert!(
            (buffers.torque[k] - torque[k]).length() <= 1e-12 * t,
            "torque {k}"
        );
    }
}

#[test]
fn bodies_beyond_the_prefetch_size_get_the_scalar_laws_forces() {
    // Copies of the jumble, far apart, hold more bodies than `PREFETCH_BODIES`, so the
    // pair filter and gather ask for lines ahead (hints, which must change nothing).
    // Forces must agree with the scalar laws as in
    // `batched_kernels_match_the_scalar_contact_laws` (to 1e-12, the same formulas with
    // a few operations regrouped), and two threads must give every bit of one.
    let jumble = Jumble::new(1, false);
    let one = &jumble.set;
    let copies = PREFETCH_BODIES / one.len() + 2;
    let mut set = ParticleSet::default();
    for c in 0..copies {
        for k in 0..one.len() {
            let mut init = ParticleInit::at_rest(
                one.position[k] + DVec3::X * (0.05 * c as f64),
                one.radius[k],
                MaterialId(0),
            );
            init.velocity = one.velocity[k];
            init.angular_velocity = one.omega[k];
            set.push(&init, 2500.0);
        }
    }
    assert!(set.len() > PREFETCH_BODIES);
    let big = Jumble {
        set,
        walls: Vec::new(),
        wall_coeffs: Vec::new(),
        ..Jumble::new(1, false)
    };
    let (mut pairs, mut wall_pairs) = big.lists();
    let laws = ContactLaws::default();
    let input = jumble_input(&big, &laws);
    let (mut p2, mut w2) = (pairs.clone(), wall_pairs.clone());
    let (buffers, eval) = batched_forces(&input, &mut pairs, &mut wall_pairs);
    assert!(eval.count.particle_particle > copies * 100);

    let (force, torque, _) = scalar_forces(&input, laws, &mut p2, &mut w2);
    assert_close(&buffers, &force, &torque);

    let pool = crate::team::Team::new(2).unwrap();
    let (mut p3, mut w3) = big.lists();
    let mut two = ForceBuffers::default();
    start(&big.set, DVec3::ZERO, &mut two);
    evaluate(&input, &mut p3, &mut w3, &mut two, Some(&pool), &mut []);
    let bits = |v: &[DVec3]| {
        v.iter()
            .map(|x| x.to_array().map(f64::to_bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&two.force), bits(&buffers.force));
    assert_eq!(bits(&two.torque), bits(&buffers.torque));
}

#[test]
fn batched_kernels_match_the_scalar_contact_laws() {
    // The batched path (the paper's laws) against the general scalar path over the same
    // lists: with one material and one size (the shared-coefficient fills), and with two
    // materials and seven sizes (the per-contact gathers). Same formulas with a few
    // operations regrouped: agreement to 1e-12 of each body's largest force or torque.
    for (materials, poly) in [(1, false), (2, true)] {
        let jumble = Jumble::new(materials, poly);
        let (mut pairs, mut wall_pairs) = jumble.lists();
        let laws = ContactLaws::default();
        let input = jumble_input(&jumble, &laws);
        let (mut p2, mut w2) = (pairs.clone(), wall_pairs.clone());
        let (buffers, eval) = batched_forces(&input, &mut pairs, &mut wall_pairs);
        assert!(eval.count.particle_particle > 100 && eval.count.particle_wall > 10);
        assert!(
            eval.count.particle_particle < p2.len(),
            "some candidates must be apart"
        );

        let (force, torque, worst) = scalar_forces(&input, laws, &mut p2, &mut w2);
        assert_eq!(eval.worst_pair.index, worst.index);
        assert_close(&buffers, &force, &torque);
        for (a, b) in pairs
            .history
            .iter()
            .zip(p2.history.iter())
            .chain(wall_pairs.history.iter().zip(w2.history.iter()))
        {
            assert!(
                (a.tangential - b.tangential).length() <= 1e-12 * b.tangential.length(),
                "history"
            );
        }
    }
}

#[test]
fn the_simplified_jkr_added_to_batches_matches_the_scalar_contact_laws() {
    // The batched kernel's dry forces with the attraction subtracted (`area_cohesion`)
    // against the one-contact pipeline, which subtracts it inside the normal force: the
    // same numbers regrouped, to 1e-12 of each body's largest force or torque. k_c = 1e6
    // J/m³ makes the attraction a good share of each contact's force, on the pairs of the
    // first material and on every wall of it; the second material's pairs stay dry.
    use crate::contact::Cohesion;
    for (materials, poly) in [(1, false), (2, true)] {
        let mut jumble = Jumble::new(materials, poly);
        let sticky = Cohesion::SimplifiedJkr {
            energy_density: 1e6,
        };
        jumble.pair_coeffs[0].cohesion = sticky;
        for w in 0..jumble.walls.len() {
            jumble.wall_coeffs[w * materials].cohesion = sticky;
        }
        let (mut pairs, mut wall_pairs) = jumble.lists();
        let laws = ContactLaws::default();
        let mut input = jumble_input(&jumble, &laws);
        input.area_cohesion = true;
        assert!(input.batched());
        let (mut p2, mut w2) = (pairs.clone(), wall_pairs.clone());
        let (buffers, _) = batched_forces(&input, &mut pairs, &mut wall_pairs);
        let (force, torque, _) = scalar_forces(&input, laws, &mut p2, &mut w2);
        assert_close(&buffers, &force, &torque);
        // And the attraction is there: the dry batch differs by far more than round-off.
        let (mut p3, mut w3) = jumble.lists();
        input.area_cohesion = false;
        let (dry, _) = batched_forces(&input, &mut p3, &mut w3);
        let moved = dry
            .force
            .iter()
            .zip(&buffers.force)
            .map(|(a, b)| (*a - *b).length())
            .fold(0.0, f64::max);
        assert!(moved > 1e-3, "largest change {moved} N");
    }
}

#[test]
fn bonded_pairs_and_walls_in_batches_match_the_scalar_contact_laws() {
    // JKR and liquid bridges through the batched kernel's bonded lanes, for pairs and for
    // the walls (planes and polygons), against the one-contact pipeline, on equal spheres of
    // one material and on unequal spheres of two (where only the second material's pairs are
    // wet, and the mixed pairs and the second material's wall contacts dry). Every candidate
    // starts bonded, so the lists hold bonds across gaps: some within the laws' reach (a JKR
    // bond in tension, a bridge alone) and some beyond it (broken); dry pairs flagged bonded
    // (as a changed material table leaves them) are apart. Forces and torques agree to 1e-12
    // of each body's own (the same formulas, a few operations regrouped), and every
    // candidate's history and bond after the step to 1e-12 of ξ.
    use crate::contact::Cohesion;
    use crate::history::{BONDED, LIVE};
    // w = 100 J/m² makes the JKR reach about 12 µm here, so that gaps of the jumble fall
    // on both sides of it; V = 10⁻¹² m³ a bridge's about 0.1 mm.
    let glue = Cohesion::Jkr {
        work_of_adhesion: 100.0,
    };
    let water = Cohesion::LiquidBridge {
        volume: 1e-12,
        surface_tension: 0.072,
        contact_angle: 0.35,
    };
    for (materials, poly, law) in [(1, false, glue), (1, false, water), (2, true, glue)] {
        let mut jumble = Jumble::new(materials, poly);
        jumble.pair_coeffs[0].cohesion = law;
        if materials == 2 {
            jumble.pair_coeffs[3].cohesion = water;
        }
        // The walls bond with the first material by the same law, the second stays dry.
        for w in 0..jumble.walls.len() {
            jumble.wall_coeffs[w * materials].cohesion = law;
        }
        let (mut pairs, mut wall_pairs) = jumble.lists();
        pairs.history.live.fill(LIVE | BONDED);
        wall_pairs.history.live.fill(LIVE | BONDED);
        let laws = ContactLaws::default();
        let tables = BondTables::of(&jumble.pair_coeffs, &jumble.wall_coeffs);
        let mut input = jumble_input(&jumble, &laws);
        input.bond_tables = &tables;
        input.pair_bonds = true;
        input.wall_bonds = true;
        assert!(input.batched_pairs() && input.batched());
        let (mut p2, mut w2) = (pairs.clone(), wall_pairs.clone());
        let (buffers, _) = batched_forces(&input, &mut pairs, &mut wall_pairs);
        let (force, torque, _) = scalar_forces(&input, laws, &mut p2, &mut w2);
        assert_close(&buffers, &force, &torque);
        let (mut gaps_held, mut gaps_broken) = (0, 0);
        for k in 0..pairs.history.len() {
            let (a, b) = (pairs.history.get(k), p2.history.get(k));
            assert_eq!(a.bonded, b.bonded, "bond of candidate {k}");
            let scale = b.tangential.length().max(1e-30);
            assert!(
                (a.tangential - b.tangential).length() <= 1e-12 * scale,
                "ξ of {k}"
            );
            let (i, j) = (pairs.i[k] as usize, pairs.j[k] as usize);
            let p = &jumble.set;
            let gap = (p.position[i] - p.position[j]).length() - p.radius[i] - p.radius[j];
            if gap > 0.0 {
                if b.bonded {
                    gaps_held += 1;
                } else {
                    gaps_broken += 1;
                }
            }
        }
        assert!(
            gaps_held > 0 && gaps_broken > 0,
            "bonds held across gaps: {gaps_held}, broken: {gaps_broken}"
        );
        let mut wall_bonds = 0;
        for k in 0..wall_pairs.history.len() {
            let (a, b) = (wall_pairs.history.get(k), w2.history.get(k));
            assert_eq!(a.bonded, b.bonded, "bond of wall candidate {k}");
            let scale = b.tangential.length().max(1e-30);
            assert!(
                (a.tangential - b.tangential).length() <= 1e-12 * scale,
                "wall ξ of {k}"
            );
            wall_bonds += usize::from(b.bonded);
        }
        assert!(wall_bonds > 0, "no wall contact bonded");
    }
}

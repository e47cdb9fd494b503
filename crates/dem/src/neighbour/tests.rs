//! Tests of the neighbour search: the cell list against a brute-force search, and history
//! carried over rebuilds by index, through moved indices and in either wall-list order.

use super::*;
use rand::{Rng, SeedableRng};

#[test]
fn cell_list_finds_exactly_the_pairs_of_a_brute_force_search() {
    // Exact set equality: any missed or extra pair is a bug.
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
    let mut set = ParticleSet::default();
    for _ in 0..400 {
        let p = DVec3::new(rng.gen::<f64>(), rng.gen::<f64>() * 0.1, rng.gen::<f64>());
        let init = crate::particles::ParticleInit::at_rest(
            p,
            0.01 + 0.01 * rng.gen::<f64>(),
            crate::particles::MaterialId(0),
        );
        set.push(&init, 1000.0);
    }
    let skin = 0.005;
    let grid = CellGrid::build(&set.position, 0.04 + skin);
    let (mut pairs, mut walls) = (PairList::default(), WallPairList::default());
    build_lists(
        PairSearch::Cells(&grid),
        &set,
        &[],
        skin,
        &PairList::default(),
        &mut WallPairList::default(),
        Carry::Same,
        (&mut pairs, &mut walls),
        &mut ListScratch::default(),
    );
    let mut brute = Vec::new();
    for i in 0..set.len() {
        for j in i + 1..set.len() {
            let cut = set.radius[i] + set.radius[j] + skin;
            if set.position[i].distance_squared(set.position[j]) < cut * cut {
                brute.push((i as u32, j as u32));
            }
        }
    }
    let found: Vec<(u32, u32)> = pairs
        .i
        .iter()
        .copied()
        .zip(pairs.j.iter().copied())
        .collect();
    assert_eq!(found, brute);
}

/// Bodies at `bodies` (position [m], radius [m]).
fn particle_set(bodies: &[(DVec3, f64)]) -> ParticleSet {
    let mut set = ParticleSet::default();
    for &(p, r) in bodies {
        let init = crate::particles::ParticleInit::at_rest(p, r, crate::particles::MaterialId(0));
        set.push(&init, 1000.0);
    }
    set
}

/// Every pair (i, j), i < j, closer than R_i + R_j + skin, by testing all pairs with the
/// expression the searches use.
fn brute_force_pairs(set: &ParticleSet, skin: f64) -> Vec<(u32, u32)> {
    let mut brute = Vec::new();
    for i in 0..set.len() {
        for j in i + 1..set.len() {
            let cut = set.radius[i] + set.radius[j] + skin;
            if set.position[i].distance_squared(set.position[j]) < cut * cut {
                brute.push((i as u32, j as u32));
            }
        }
    }
    brute
}

/// The pair list `build_lists` writes from `search`, as (i, j) in list order.
fn listed_pairs(set: &ParticleSet, skin: f64, search: PairSearch<'_>) -> Vec<(u32, u32)> {
    let (mut pairs, mut walls) = (PairList::default(), WallPairList::default());
    build_lists(
        search,
        set,
        &[],
        skin,
        &PairList::default(),
        &mut WallPairList::default(),
        Carry::Same,
        (&mut pairs, &mut walls),
        &mut ListScratch::default(),
    );
    pairs
        .i
        .iter()
        .copied()
        .zip(pairs.j.iter().copied())
        .collect()
}

/// The pair lists of the single grid and of the size classes, checked equal to the brute
/// force's in content and order; returns how many pairs, and whether the simulation would
/// search these radii by size class.
fn check_both_searches(set: &ParticleSet, skin: f64) -> (usize, bool) {
    let r_max = set.radius.iter().copied().fold(0.0, f64::max);
    let brute = brute_force_pairs(set, skin);
    let grid = CellGrid::build(&set.position, (2.0 * r_max + skin).max(f64::MIN_POSITIVE));
    // Exact equality, element by element: the order is part of the bits of a run.
    assert_eq!(listed_pairs(set, skin, PairSearch::Cells(&grid)), brute);
    let mut classes = SizeClasses::default();
    classes.rebuild(&set.position, &set.radius, skin);
    assert_eq!(
        listed_pairs(set, skin, PairSearch::Classes(&classes)),
        brute
    );
    (brute.len(), SizeClasses::pays_for(&set.radius))
}

/// `count` bodies uniformly in a box of `extent` [m], radii drawn by `radius`.
fn random_bed(
    seed: u64,
    count: usize,
    extent: DVec3,
    mut radius: impl FnMut(&mut rand_xoshiro::Xoshiro256PlusPlus) -> f64,
) -> ParticleSet {
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(seed);
    let bodies: Vec<(DVec3, f64)> = (0..count)
        .map(|_| {
            let u = DVec3::new(rng.gen(), rng.gen(), rng.gen());
            (u * extent, radius(&mut rng))
        })
        .collect();
    particle_set(&bodies)
}

#[test]
fn size_classes_find_exactly_the_pairs_of_a_brute_force_search_for_two_sizes() {
    // 1000 spheres: small ones of radius 1 mm and large ones 2, 3, 4 and 10 times as large,
    // one large in eight, overlapping freely in a box: every pair the brute force finds and
    // no other, in its order; a simulation searches the last three by size class.
    for (k, ratio) in [2.0, 3.0, 4.0, 10.0].into_iter().enumerate() {
        let r = 1e-3;
        let set = random_bed(
            11 + k as u64,
            1000,
            DVec3::splat(0.03 + 0.004 * ratio),
            |rng| {
                if rng.gen::<f64>() < 0.125 {
                    ratio * r
                } else {
                    r
                }
            },
        );
        for skin in [0.0, 0.2 * r, 0.2 * ratio * r] {
            let (pairs, by_class) = check_both_searches(&set, skin);
            assert_eq!(by_class, ratio > 2.0, "ratio {ratio}");
            // Enough pairs that a search missing a stencil direction would be caught.
            assert!(
                pairs > 300,
                "ratio {ratio}, skin {skin}: only {pairs} pairs"
            );
        }
    }
}

#[test]
fn size_classes_find_exactly_the_pairs_of_a_brute_force_search_for_continuous_sizes() {
    // Continuous distributions: uniform radii over 1:4, log-uniform over 1:10, and a
    // mixture of a narrow and a wide population; each against the brute force.
    let r = 1e-3;
    let uniform = |rng: &mut rand_xoshiro::Xoshiro256PlusPlus| r * (1.0 + 3.0 * rng.gen::<f64>());
    let log_uniform = |rng: &mut rand_xoshiro::Xoshiro256PlusPlus| r * 10f64.powf(rng.gen::<f64>());
    let mixture = |rng: &mut rand_xoshiro::Xoshiro256PlusPlus| {
        if rng.gen::<f64>() < 0.8 {
            r * (1.0 + 0.05 * rng.gen::<f64>())
        } else {
            r * (2.5 + 4.0 * rng.gen::<f64>())
        }
    };
    let sets = [
        random_bed(21, 800, DVec3::splat(0.04), uniform),
        random_bed(22, 800, DVec3::new(0.06, 0.01, 0.06), log_uniform),
        random_bed(23, 800, DVec3::splat(0.04), mixture),
    ];
    for set in &sets {
        let (pairs, by_class) = check_both_searches(set, 0.2 * r);
        assert!(
            by_class && pairs > 500,
            "{pairs} pairs, by class: {by_class}"
        );
    }
}

#[test]
fn pairs_at_exactly_the_cutoff_are_left_out_and_pairs_one_ulp_inside_are_found() {
    // Small spheres of radius 0.5 m and large ones of 2 m (ratio 4), skin 0.25 m: cutoffs
    // 1.25 (small–small), 2.75 (small–large) and 4.25 (large–large), all exact in binary.
    // The small spheres sit on a lattice 1.25 apart, exactly at their cutoff (the test is
    // strict: no pair), the grid's cells about as wide, so that the bodies lie on or near
    // cell boundaries; a row of four more lies one unit in the last place closer than 1.25
    // to the lattice's first row (pairs). Large spheres: one exactly at 2.75 from a small
    // one, one a unit in the last place inside it, one exactly 4.25 from a large one.
    let (rs, rl, skin) = (0.5, 2.0, 0.25);
    // The next float towards zero.
    let inward = |x: f64| f64::from_bits(x.to_bits() - 1);
    let mut bodies = Vec::new();
    for k in 0..64 {
        let (x, y, z) = ((k % 4) as f64, ((k / 4) % 4) as f64, (k / 16) as f64);
        bodies.push((DVec3::new(x, y, z) * 1.25, rs));
    }
    for k in 0..4 {
        bodies.push((DVec3::new(k as f64 * 1.25, inward(-1.25), 0.0), rs));
    }
    bodies.push((DVec3::new(-2.75, 0.0, 0.0), rl));
    bodies.push((DVec3::new(0.0, 0.0, inward(-2.75)), rl));
    bodies.push((DVec3::new(-2.75, 0.0, -4.25), rl));
    let set = particle_set(&bodies);
    let brute = brute_force_pairs(&set, skin);
    let (_, by_class) = check_both_searches(&set, skin);
    assert!(by_class);
    let has = |a: u32, b: u32| brute.contains(&(a.min(b), a.max(b)));
    // One ulp inside: pairs.
    assert!(has(64, 0) && has(67, 3) && has(69, 0), "{brute:?}");
    // Exactly at the cutoff: no pairs.
    assert!(!has(0, 1) && !has(64, 65), "small–small at the cutoff");
    assert!(
        !has(68, 0) && !has(68, 70),
        "small–large and large–large at the cutoff"
    );
}

#[test]
fn empty_sets_single_bodies_and_lone_large_bodies() {
    // No bodies and one body: no pairs, and a single grid in a simulation. Two bodies of different
    // classes, apart and then in reach, in either index order: none, then exactly one.
    let skin = 0.1;
    assert_eq!(check_both_searches(&particle_set(&[]), skin), (0, false));
    let one = particle_set(&[(DVec3::ZERO, 1.0)]);
    assert_eq!(check_both_searches(&one, skin), (0, false));
    for (a, b) in [(1.0, 5.0), (5.0, 1.0)] {
        let apart = particle_set(&[(DVec3::ZERO, a), (DVec3::new(6.2, 0.0, 0.0), b)]);
        assert_eq!(check_both_searches(&apart, skin), (0, true));
        let close = particle_set(&[(DVec3::ZERO, a), (DVec3::new(6.0, 0.0, 0.0), b)]);
        assert_eq!(check_both_searches(&close, skin), (1, true));
    }
}

#[test]
fn large_bodies_outside_the_small_bodies_box_find_them() {
    // Large spheres above, below and beside a block of small ones, each within reach of
    // the block's edge: their cell coordinates in the small class's grid lie outside it.
    let r = 1.0;
    let mut bodies = Vec::new();
    for k in 0..125 {
        let (x, y, z) = ((k % 5) as f64, ((k / 5) % 5) as f64, (k / 25) as f64);
        bodies.push((DVec3::new(x, y, z) * 2.1 * r, r));
    }
    let edge = 4.0 * 2.1 * r;
    for at in [
        DVec3::new(0.5 * edge, 0.5 * edge, edge + 5.0 * r),
        DVec3::new(0.5 * edge, 0.5 * edge, -5.0 * r),
        DVec3::new(edge + 4.5 * r, 0.0, 0.0),
        DVec3::new(-4.5 * r, 0.0, edge),
    ] {
        bodies.push((at, 4.0 * r));
    }
    let set = particle_set(&bodies);
    let (pairs, by_class) = check_both_searches(&set, 0.3 * r);
    assert!(by_class);
    // Each large sphere reaches at least one small one (5 r < 4 r + r + skin).
    let brute = brute_force_pairs(&set, 0.3 * r);
    for large in 125..129u32 {
        assert!(
            brute.iter().any(|&(_, j)| j == large),
            "large sphere {large}"
        );
    }
    assert!(pairs > 4 * 125 / 2);
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

    #[test]
    fn any_mixture_is_searched_exactly(
        seed in 0u64..1 << 32,
        count in 0usize..300,
        ratio in 1.0f64..12.0,
        large_share in 0.0f64..1.0,
        skin_share in 0.0f64..0.5,
        flat in proptest::bool::ANY,
    ) {
        // Two populations, small ones of radius 1 with a 10 % spread and large ones up to
        // `ratio` times as large, in a box or a slab; the brute force decides.
        let extent = if flat { DVec3::new(40.0, 2.5, 40.0) } else { DVec3::splat(15.0) };
        let set = random_bed(seed, count, extent, |rng| {
            if rng.gen::<f64>() < large_share {
                1.0 + (ratio - 1.0) * rng.gen::<f64>()
            } else {
                1.0 + 0.1 * rng.gen::<f64>()
            }
        });
        check_both_searches(&set, skin_share * 2.0);
    }
}

#[test]
fn a_rebuild_carries_each_pairs_history_by_index_and_starts_new_pairs_empty() {
    // Exact: a carried history is the old one bit for bit, as `get` reads it (zero where
    // it was not live), and a pair the old list lacked starts from zero. The reference is
    // a map from (i, j) to the old history; the particles then move by up to a tenth of
    // their radius, so that pairs both persist and appear.
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(9);
    let mut set = ParticleSet::default();
    for _ in 0..300 {
        let p = DVec3::new(rng.gen::<f64>(), rng.gen::<f64>() * 0.1, rng.gen::<f64>()) * 0.2;
        let init =
            crate::particles::ParticleInit::at_rest(p, 0.01, crate::particles::MaterialId(0));
        set.push(&init, 1000.0);
    }
    let skin = 0.002;
    let build = |set: &ParticleSet, old: &PairList| {
        let grid = CellGrid::build(&set.position, 0.02 + skin);
        let (mut p, mut w) = (PairList::default(), WallPairList::default());
        build_lists(
            PairSearch::Cells(&grid),
            set,
            &[],
            skin,
            old,
            &mut WallPairList::default(),
            Carry::Same,
            (&mut p, &mut w),
            &mut ListScratch::default(),
        );
        p
    };
    let mut first = build(&set, &PairList::default());
    for k in 0..first.len() {
        let h = &mut first.history;
        h.tangential[k] = DVec3::new(k as f64 + 1.0, 0.5, -0.25);
        h.rolling[k] = DVec3::new(0.0, k as f64 + 2.0, 0.0);
        if k % 3 == 0 {
            h.live[k] = 0;
        }
    }
    let old: std::collections::HashMap<(u32, u32), ContactHistory> = (0..first.len())
        .map(|k| ((first.i[k], first.j[k]), first.history.get(k)))
        .collect();
    for x in &mut set.position {
        *x += DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 0.002 - 0.001;
    }
    let again = build(&set, &first);
    let (mut carried, mut fresh) = (0, 0);
    for k in 0..again.len() {
        let key = (again.i[k], again.j[k]);
        let want = old.get(&key).copied().unwrap_or_default();
        assert_eq!(again.history.get(k), want, "pair {key:?}");
        assert_eq!(again.history.live[k], crate::history::LIVE);
        match old.get(&key) {
            Some(h) if !h.is_empty() => carried += 1,
            Some(_) => {}
            None => fresh += 1,
        }
    }
    assert!(carried > 10 && fresh > 10, "carried {carried}, new {fresh}");
}

#[test]
fn wall_candidates_are_wall_major_and_carry_history_from_either_order() {
    // Particles along a box of four planes: each particle is a candidate of several
    // walls. The list must come out sorted by (wall, particle), and a rebuild must carry
    // every history exactly, whether the old list is wall-major or particle-major (the
    // order of lists in checkpoints written before the change) and sorted on restore.
    use crate::material::{Interaction, Material, WallMaterial};
    let mut set = ParticleSet::default();
    for k in 0..50 {
        let x = DVec3::new(0.001 + 0.0005 * (k % 10) as f64, 0.0017, 0.0005 * k as f64);
        let init =
            crate::particles::ParticleInit::at_rest(x, 0.0015, crate::particles::MaterialId(0));
        set.push(&init, 1000.0);
    }
    let m = WallMaterial::Elastic(Material::fan2023());
    let i = Interaction::fan2023();
    let walls: Vec<Option<Wall>> = vec![
        Some(Wall::plane(DVec3::ZERO, DVec3::X, m, i).unwrap()),
        None,
        Some(Wall::plane(DVec3::ZERO, DVec3::Y, m, i).unwrap()),
        Some(Wall::plane(DVec3::new(0.0, 0.0034, 0.0), -DVec3::Y, m, i).unwrap()),
    ];
    let skin = 3e-4;
    let grid = CellGrid::build(&set.position, 0.003 + skin);
    let build = |old: &WallPairList| {
        let (mut p, mut w) = (PairList::default(), WallPairList::default());
        build_lists(
            PairSearch::Cells(&grid),
            &set,
            &walls,
            skin,
            &PairList::default(),
            &mut old.clone(),
            Carry::Same,
            (&mut p, &mut w),
            &mut ListScratch::default(),
        );
        w
    };
    let mut first = build(&WallPairList::default());
    assert!(first.is_wall_major());
    let walls_seen: std::collections::BTreeSet<u32> = first.wall.iter().copied().collect();
    assert_eq!(walls_seen.len(), 3, "every present wall has candidates");
    for (k, t) in first.history.tangential.iter_mut().enumerate() {
        *t = DVec3::new(k as f64 + 1.0, 0.0, 0.0);
    }
    let particle_major = {
        let mut order: Vec<usize> = (0..first.particle.len()).collect();
        order.sort_by_key(|&k| (first.particle[k], first.wall[k]));
        first.permuted(&order)
    };
    assert!(!particle_major.is_wall_major());
    let sorted = particle_major.into_wall_major();
    for old in [&first, &sorted] {
        let again = build(old);
        assert_eq!(again.particle, first.particle);
        assert_eq!(again.wall, first.wall);
        assert_eq!(again.history, first.history, "history lost in the carry");
    }
}
#[test]
fn histories_follow_their_bodies_when_indices_move() {
    // After a re-sort and a removal (new body k was body origin[k]), each new pair's and
    // wall candidate's history must be the one its two bodies had, keyed here by the
    // bodies' tags in a map: negated when the pair's order of bodies turned round, zero
    // (+0.0) when absent, not live, or zero with a negative sign. Compared bit for bit,
    // so that a lost sign of zero fails too. The reference is an independent mechanism,
    // a map by tag, and it checks every entry.
    use crate::material::{Interaction, Material, WallMaterial};
    use std::collections::HashMap;
    let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(30);
    let mut set = ParticleSet::default();
    for _ in 0..400 {
        let p = DVec3::new(
            rng.gen::<f64>(),
            0.011 + 0.002 * rng.gen::<f64>(),
            rng.gen::<f64>(),
        ) * DVec3::new(0.2, 1.0, 0.2);
        let init =
            crate::particles::ParticleInit::at_rest(p, 0.01, crate::particles::MaterialId(0));
        set.push(&init, 1000.0);
    }
    let m = WallMaterial::Elastic(Material::fan2023());
    let i = Interaction::fan2023();
    let walls: Vec<Option<Wall>> = vec![
        Some(Wall::plane(DVec3::ZERO, DVec3::Y, m, i).unwrap()),
        None,
        Some(Wall::plane(DVec3::new(0.0, 0.025, 0.0), -DVec3::Y, m, i).unwrap()),
        Some(Wall::plane(DVec3::ZERO, DVec3::X, m, i).unwrap()),
    ];
    let skin = 0.002;
    let build = |set: &ParticleSet, old: (&PairList, &WallPairList), carry: Carry<'_>| {
        let grid = CellGrid::build(&set.position, 0.02 + skin);
        let (mut p, mut w) = (PairList::default(), WallPairList::default());
        let mut scratch = ListScratch::default();
        let lists = (&mut p, &mut w);
        build_lists(
            PairSearch::Cells(&grid),
            set,
            &walls,
            skin,
            old.0,
            &mut old.1.clone(),
            carry,
            lists,
            &mut scratch,
        );
        (p, w)
    };
    let none = (&PairList::default(), &WallPairList::default());
    let (mut pairs, mut wall_pairs) = build(&set, none, Carry::Same);
    // Histories of every kind: ordinary, not live, zero with negative signs, zero.
    let mut fill = |h: &mut HistoryArrays| {
        for k in 0..h.len() {
            let v = DVec3::new(rng.gen(), rng.gen(), rng.gen()) - 0.5;
            (h.tangential[k], h.rolling[k]) = match k % 5 {
                0 => (DVec3::new(-0.0, 0.0, -0.0), DVec3::splat(-0.0)),
                1 => (DVec3::ZERO, DVec3::ZERO),
                _ => (v, v * 0.25),
            };
            h.live[k] = if k % 7 == 3 { 0 } else { crate::history::LIVE };
        }
    };
    fill(&mut pairs.history);
    fill(&mut wall_pairs.history);
    let tag = set.tag.clone();
    let old_pairs: HashMap<_, _> = (0..pairs.len())
        .map(|k| {
            (
                (tag[pairs.i[k] as usize], tag[pairs.j[k] as usize]),
                pairs.history.get(k),
            )
        })
        .collect();
    let old_walls: HashMap<_, _> = (0..wall_pairs.particle.len())
        .map(|k| {
            let key = (wall_pairs.wall[k], tag[wall_pairs.particle[k] as usize]);
            (key, wall_pairs.history.get(k))
        })
        .collect();

    // Remove one body in eight, shuffle the rest, and move them a little.
    let keep: Vec<bool> = (0..set.len()).map(|k| k % 8 != 5).collect();
    let kept: Vec<u32> = (0..set.len() as u32)
        .filter(|&k| keep[k as usize])
        .collect();
    set.retain_mask(&keep);
    let mut order: Vec<u32> = (0..set.len() as u32).collect();
    for k in (1..order.len()).rev() {
        order.swap(k, rng.gen_range(0..=k));
    }
    set.permute(&order);
    let origin: Vec<u32> = order.iter().map(|&k| kept[k as usize]).collect();
    for x in &mut set.position {
        *x += (DVec3::new(rng.gen(), 0.0, rng.gen()) - 0.5) * 0.002;
    }
    let (new_pairs, new_walls) = build(&set, (&pairs, &wall_pairs), Carry::Moved(&origin));

    let bits = |h: ContactHistory| {
        let v = |x: DVec3| x.to_array().map(f64::to_bits);
        (v(h.tangential), v(h.rolling))
    };
    let expect = |h: Option<&ContactHistory>, flip: bool| match h {
        Some(h) if !h.is_empty() => {
            if flip {
                negate(*h)
            } else {
                *h
            }
        }
        _ => ContactHistory::default(),
    };
    let (mut carried, mut flipped, mut fresh) = (0, 0, 0);
    let tag = &set.tag;
    for k in 0..new_pairs.len() {
        let (a, b) = (tag[new_pairs.i[k] as usize], tag[new_pairs.j[k] as usize]);
        let want = match (old_pairs.get(&(a, b)), old_pairs.get(&(b, a))) {
            (Some(h), _) => expect(Some(h), false),
            (None, Some(h)) => {
                flipped += usize::from(!h.is_empty());
                expect(Some(h), true)
            }
            (None, None) => {
                fresh += 1;
                ContactHistory::default()
            }
        };
        carried += usize::from(!want.is_empty());
        assert_eq!(bits(new_pairs.history.get(k)), bits(want), "pair {k}");
        assert_eq!(new_pairs.history.live[k], crate::history::LIVE);
    }
    let mut carried_walls = 0;
    for k in 0..new_walls.particle.len() {
        let key = (new_walls.wall[k], tag[new_walls.particle[k] as usize]);
        let want = expect(old_walls.get(&key), false);
        carried_walls += usize::from(!want.is_empty());
        assert_eq!(
            bits(new_walls.history.get(k)),
            bits(want),
            "wall candidate {k}"
        );
    }
    // The cases must all occur, or the test would pass on a carry that drops them.
    assert!(
        carried > 100 && flipped > 20 && fresh > 10,
        "{carried} {flipped} {fresh}"
    );
    assert!(carried_walls > 30, "{carried_walls}");
}

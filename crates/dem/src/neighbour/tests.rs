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
        &grid,
        &set,
        &[],
        skin,
        &PairList::default(),
        &WallPairList::default(),
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
            &grid,
            set,
            &[],
            skin,
            old,
            &WallPairList::default(),
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
            &grid,
            &set,
            &walls,
            skin,
            &PairList::default(),
            old,
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
            &grid,
            set,
            &walls,
            skin,
            old.0,
            old.1,
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

//! The surface pass's contacts under the paper's laws, resolved [`BATCH`] at a time by the
//! wall kernel (`Batch::resolve_walls`) instead of one by one.
//!
//! A curved or meshed wall's contact costs the scalar laws about as much as fifteen
//! batched pair contacts: the chain of square roots and divisions of one contact cannot
//! overlap the next's. Here the contacts of a stretch are found in list order (each with
//! the history it continues, `surfaces::continued`), gathered into a batch, resolved
//! together, and handed out in the order they were found: each particle, each wall load
//! and each element load receives the same additions in the same order as on the
//! one-at-a-time path, whose forces the kernel matches to a few ulps (`forces::kernel`).

use glam::DVec3;

use super::kernel::{Batch, BATCH};
use super::loads::add_load;
use super::pairs::batch_force;
use super::surfaces::{continued, remember, touching, Stretch, StretchSinks, SurfaceScratch};
use super::{KernelInput, WorstOverlap};
use crate::contact::cohesion::{LAW_DRY, OUTCOME_APART};
use crate::history::{SurfaceContact, SurfaceSlot};

/// A contact gathered into the batch and not yet handed out: its particle, where its
/// history goes (candidate within the stretch, contact within the candidate's slot), its
/// element (triangle or band) and its normal.
#[derive(Debug, Clone, Copy)]
pub(super) struct Pending {
    particle: u32,
    candidate: u32,
    contact: u32,
    element: u32,
    normal: DVec3,
}

/// `surfaces::resolve_stretch` for the paper's laws (`ContactLaws::default()`).
pub(super) fn resolve_batched(
    input: &KernelInput,
    stretch: Stretch,
    sinks: &mut StretchSinks,
    scratch: &mut SurfaceScratch,
    worst: &mut WorstOverlap,
    book: &mut impl FnMut(u32, DVec3, DVec3),
) -> usize {
    let p = input.particles;
    let Stretch {
        wall,
        index: w,
        bands,
        ids,
        first,
        slots,
    } = stretch;
    let SurfaceScratch {
        mesh,
        contacts,
        previous,
        taken,
        pending,
        batch,
        broken,
    } = scratch;
    pending.clear();
    broken.clear();
    let bonds = input.wall_bonds;
    // With a bonding cohesion, the places within its reach: a bonded contact may act across
    // a gap (docs/physics.md §2.4, §2.6).
    let reach = if bonds { input.reach } else { 0.0 };
    let mut count = 0;
    for (candidate, &i) in ids.iter().enumerate() {
        let i = i as usize;
        let (x, r) = (p.position[i], p.radius[i]);
        let slot = &mut slots[candidate];
        touching(
            wall,
            (x, r + reach),
            bands,
            slot,
            (&mut *mesh, &mut *contacts),
        );
        if contacts.is_empty() {
            slot.contacts.clear();
            continue;
        }
        remember(&mut slot.contacts, previous, taken);
        // `slots[candidate]` is indexed anew below: a full batch hands out into `slots`.
        let pair = w * input.materials + p.material[i] as usize;
        let (c, bond) = (&input.wall_coeffs[pair], &input.bond_tables.wall[pair]);
        for contact in contacts.iter() {
            // `geometry::sphere_wall`: δ = R − distance; the kernel forms the lever arm.
            let overlap = r - contact.distance;
            let history = continued(contact.normal, previous, taken);
            if overlap <= 0.0 && !history.bonded {
                // Within the cohesion's reach but not bonded: no contact.
                continue;
            }
            worst.see(overlap / r, first + candidate);
            let m = pending.len();
            let dv = p.velocity[i] - wall.velocity_at(contact.point);
            let (wi, wj, xi) = (p.omega[i], wall.angular_velocity, history.tangential);
            for (a, (n, v, u, o, z)) in [
                (contact.normal.x, dv.x, wi.x, wj.x, xi.x),
                (contact.normal.y, dv.y, wi.y, wj.y, xi.y),
                (contact.normal.z, dv.z, wi.z, wj.z, xi.z),
            ]
            .into_iter()
            .enumerate()
            {
                batch.d[a][m] = n;
                batch.dv[a][m] = v;
                batch.omega[0][a][m] = u;
                batch.omega[1][a][m] = o;
                batch.xi[a][m] = z;
            }
            batch.overlap[m] = overlap;
            batch.radius[0][m] = r;
            batch.mass[0][m] = p.mass[i];
            batch.coeff.set(m, c);
            if bonds {
                batch.bond.set(m, bond, c.e_star);
            }
            pending.push(Pending {
                particle: i as u32,
                candidate: candidate as u32,
                contact: slots[candidate].contacts.len() as u32,
                element: contact.triangle,
                normal: contact.normal,
            });
            // The history is the kernel's output; until then the slot keeps the input.
            slots[candidate].contacts.push(SurfaceContact {
                normal: contact.normal,
                history,
            });
            count += 1;
            if pending.len() == BATCH {
                hand_out(input, w, (batch, pending, broken), slots, sinks, book);
            }
        }
    }
    hand_out(input, w, (batch, pending, broken), slots, sinks, book);
    // A broken bond leaves its slot, last first so that the indices stay true.
    for &(candidate, contact) in broken.iter().rev() {
        slots[candidate as usize].contacts.remove(contact as usize);
    }
    count - broken.len()
}

/// Resolves the batch of `pending` (contacts with wall `w`) and hands each contact's force
/// out in order: to its particle, to the wall's load and to `book`; its new history goes to
/// its slot. With a bonding wall cohesion, a contact whose bond broke gets nothing and is
/// listed in `broken`.
fn hand_out(
    input: &KernelInput,
    w: usize,
    (batch, pending, broken): (&mut Batch, &mut Vec<Pending>, &mut Vec<(u32, u32)>),
    slots: &mut [SurfaceSlot],
    sinks: &mut StretchSinks,
    book: &mut impl FnMut(u32, DVec3, DVec3),
) {
    if pending.is_empty() {
        return;
    }
    batch.len = pending.len();
    let bonds = input.wall_bonds;
    if bonds {
        batch.resolve_bonded_walls(input.dt);
    } else {
        batch.resolve_walls(input.dt);
    }
    if input.area_cohesion {
        let material = &input.particles.material;
        let uniform = (input.materials == 1).then(|| &input.wall_coeffs[w]);
        super::area_cohesion::walls(
            batch,
            pending.len(),
            (uniform, |m| {
                let i = pending[m].particle as usize;
                &input.wall_coeffs[w * input.materials + material[i] as usize]
            }),
        );
    }
    for (m, q) in pending.iter().enumerate() {
        let history = &mut slots[q.candidate as usize].contacts[q.contact as usize].history;
        if bonds {
            if batch.bond.outcome[m] == OUTCOME_APART {
                broken.push((q.candidate, q.contact));
                continue;
            }
            history.bonded = batch.bond.law[m] != LAW_DRY;
        }
        let cf = batch_force(batch, m);
        let i = q.particle as usize;
        sinks.force[i - sinks.offset] += cf.force;
        sinks.torque[i - sinks.offset] += cf.torque_i;
        add_load(sinks.sum, sinks.quanta, input.particles.position[i], &cf);
        book(q.element, q.normal, cf.force);
        let xi = DVec3::new(batch.xi[0][m], batch.xi[1][m], batch.xi[2][m]);
        slots[q.candidate as usize].contacts[q.contact as usize]
            .history
            .tangential = xi;
    }
    pending.clear();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::bond_rows::BondTables;
    use crate::forces::loads::LoadSum;
    use crate::forces::surfaces::resolve_one_by_one;
    use crate::material::{Interaction, Material, PairCoefficients, WallMaterial};
    use crate::particles::{MaterialId, ParticleInit, ParticleSet};
    use crate::wall::{Wall, WallMotion};
    use rand::{Rng, SeedableRng};

    /// Sphere radius [m].
    const R: f64 = 1.5e-3;

    /// A meshed V-trough along x (faces z = |y|, folds along its floor line and between
    /// triangles) sliding at 0.1 m/s, and a cone frustum spinning at 20 rad/s: moving and
    /// turning surfaces, and spheres that touch two triangles at once.
    fn walls() -> Vec<Option<Wall>> {
        let (m, i) = (
            WallMaterial::Elastic(Material::fan2023()),
            Interaction::fan2023(),
        );
        let mut triangles = Vec::new();
        for k in 0..4 {
            let (x0, x1) = (0.005 * k as f64, 0.005 * (k + 1) as f64);
            for s in [-1.0, 1.0] {
                let (a, b) = (DVec3::new(x0, 0.0, 0.0), DVec3::new(x1, 0.0, 0.0));
                let (c, d) = (
                    DVec3::new(x0, 0.01 * s, 0.01),
                    DVec3::new(x1, 0.01 * s, 0.01),
                );
                triangles.push([a, b, d]);
                triangles.push([a, d, c]);
            }
        }
        let mut trough = Wall::mesh(&triangles, m, i).expect("valid mesh");
        let mut cone = Wall::frustum(
            DVec3::new(0.05, 0.0, 0.0),
            DVec3::Z,
            0.02,
            [0.005, 0.015],
            m,
            i,
        )
        .expect("valid frustum");
        let moving = |velocity, angular_velocity| WallMotion {
            velocity,
            angular_velocity,
            centre: DVec3::new(0.05, 0.0, 0.0),
            displaced: false,
        };
        trough
            .set_motion(moving(DVec3::new(0.1, 0.0, 0.0), DVec3::ZERO))
            .expect("valid motion");
        cone.set_motion(moving(DVec3::ZERO, DVec3::new(0.0, 0.0, 20.0)))
            .expect("valid motion");
        vec![Some(trough), Some(cone)]
    }

    /// 150 spheres of two materials near each wall, from 0.6 R to 1.1 R off its surface
    /// (most touch, some do not), with random velocities and spins; the candidates of
    /// each wall, in increasing order.
    fn spheres() -> (ParticleSet, [Vec<u32>; 2]) {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(11);
        let mut set = ParticleSet::default();
        let mut ids = [Vec::new(), Vec::new()];
        for k in 0..300 {
            let h = R * rng.gen_range(0.6..1.1);
            let centre = if k % 2 == 0 {
                // On the trough: face z = |y| on side s, normal (0, −s, 1)/√2.
                let (x, t) = (rng.gen_range(0.002..0.018), rng.gen_range(0.0..0.01));
                let s: f64 = if rng.gen::<bool>() { 1.0 } else { -1.0 };
                DVec3::new(x, s * t, t) + DVec3::new(0.0, -s, 1.0).normalize() * h
            } else {
                // Inside the cone: a point of its surface moved in along the radius.
                let (phi, u) = (
                    rng.gen_range(0.0..std::f64::consts::TAU),
                    rng.gen_range(0.002..0.018),
                );
                let rho = 0.005 + 0.01 * u / 0.02;
                let radial = DVec3::new(phi.cos(), phi.sin(), 0.0);
                DVec3::new(0.05, 0.0, u) + radial * (rho - h)
            };
            let material = (k / 2) % 2;
            let mut init = ParticleInit::at_rest(centre, R, MaterialId(material as u16));
            let mut v = |s: f64| {
                DVec3::new(
                    rng.gen::<f64>() - 0.5,
                    rng.gen::<f64>() - 0.5,
                    rng.gen::<f64>() - 0.5,
                ) * s
            };
            init.velocity = v(1.0);
            init.angular_velocity = v(300.0);
            set.push(&init, 2500.0 * (1.0 + material as f64));
            ids[k % 2].push(k as u32);
        }
        (set, ids)
    }

    /// What one pass over a stretch leaves: forces, torques, bookings (element, normal,
    /// force), the contact count and the worst overlap's index.
    type Outcome = (
        Vec<DVec3>,
        Vec<DVec3>,
        Vec<(u32, DVec3, DVec3)>,
        usize,
        usize,
    );

    fn pass(
        input: &KernelInput,
        w: usize,
        ids: &[u32],
        slots: &mut [SurfaceSlot],
        batched: bool,
    ) -> Outcome {
        let n = input.particles.len();
        let (mut force, mut torque) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
        let mut sum = LoadSum::default();
        let mut sinks = StretchSinks {
            force: &mut force,
            torque: &mut torque,
            offset: 0,
            sum: &mut sum,
            quanta: &input.quanta,
        };
        let stretch = Stretch {
            wall: input.walls[w].as_ref().expect("present"),
            index: w,
            bands: 4,
            ids,
            first: 0,
            slots,
        };
        let mut scratch = SurfaceScratch::default();
        let mut worst = WorstOverlap::default();
        let mut bookings = Vec::new();
        let mut book = |e, n, f| bookings.push((e, n, f));
        let count = if batched {
            resolve_batched(
                input,
                stretch,
                &mut sinks,
                &mut scratch,
                &mut worst,
                &mut book,
            )
        } else {
            resolve_one_by_one(
                input,
                stretch,
                &mut sinks,
                &mut scratch,
                &mut worst,
                &mut book,
            )
        };
        (force, torque, bookings, count, worst.index)
    }

    /// Agreement to 1e-12 of `b`'s magnitude: the same formulas with a few operations
    /// regrouped (`forces::kernel`).
    fn close(a: DVec3, b: DVec3, scale: f64) -> bool {
        (a - b).length() <= 1e-12 * scale
    }

    /// The batched pass's `a` against the one-by-one pass's `b`: each body's force and
    /// torque, and the element bookings in the same order with the same forces, [`close`].
    fn assert_same_sums(a: &Outcome, b: &Outcome) {
        for i in 0..b.0.len() {
            let scale = b.0[i].length().max(1e-300);
            assert!(close(a.0[i], b.0[i], scale), "force {i}");
            let scale = b.1[i].length().max(1e-300);
            assert!(close(a.1[i], b.1[i], scale), "torque {i}");
        }
        assert_eq!(a.2.len(), b.2.len());
        for (x, y) in a.2.iter().zip(&b.2) {
            assert_eq!((x.0, x.1), (y.0, y.1), "booking order");
            assert!(close(x.2, y.2, y.2.length()), "booked force");
        }
    }

    /// The kernel input of the spheres `set` and two materials with `walls`, their
    /// coefficients and the laws; with a bonding wall cohesion where `reach` [m] is not 0.
    fn surface_input<'a>(
        set: &'a ParticleSet,
        (walls, wall_coeffs, tables): (&'a [Option<Wall>], &'a [PairCoefficients], &'a BondTables),
        laws: &'a crate::contact::ContactLaws,
        reach: f64,
    ) -> KernelInput<'a> {
        KernelInput {
            particles: set,
            laws,
            bond_tables: tables,
            pair_coeffs: &[],
            materials: 2,
            walls,
            wall_coeffs,
            uniform_body: None,
            dt: 2.5e-6,
            quanta: Default::default(),
            pair_bonds: false,
            wall_bonds: reach > 0.0,
            area_cohesion: false,
            reach,
        }
    }

    /// The coefficients of the two materials (densities 2500 and 5000 kg/m³) with each wall.
    fn coefficients(walls: &[Option<Wall>]) -> Vec<PairCoefficients> {
        let materials: Vec<Material> = (0..2)
            .map(|k| Material {
                density: 2500.0 * (1.0 + k as f64),
                ..Material::fan2023()
            })
            .collect();
        walls
            .iter()
            .flatten()
            .flat_map(|w| {
                materials
                    .iter()
                    .map(|a| PairCoefficients::with_wall(a, &w.material, &w.interaction))
            })
            .collect()
    }

    #[test]
    fn bonded_surface_contacts_match_the_one_by_one_laws() {
        // The first material's contacts with the walls bond by JKR (w = 100 J/m², a reach
        // of about 15 µm here), the second's by liquid bridges (V = 10⁻¹² m³, about
        // 0.13 mm): mixed batches. Step 1 bonds the touching contacts; then every sphere
        // moves 0.1 R away from its wall, so that step 2 holds some bonds across gaps and
        // breaks others. The batches agree with `ContactLaws::resolve` as in
        // `batched_surface_contacts_match_the_one_by_one_laws` (1e-12 of each body's own
        // force or torque; the same counts, bookings, slots and bonds).
        use crate::contact::Cohesion;
        let (mut set, ids) = spheres();
        let walls = walls();
        let mut wall_coeffs = coefficients(&walls);
        let laws = [
            Cohesion::Jkr {
                work_of_adhesion: 100.0,
            },
            Cohesion::LiquidBridge {
                volume: 1e-12,
                surface_tension: 0.072,
                contact_angle: 0.35,
            },
        ];
        for (k, c) in wall_coeffs.iter_mut().enumerate() {
            c.cohesion = laws[k % 2];
        }
        let reach = wall_coeffs
            .iter()
            .map(|c| c.cohesion.reach(c.e_star, R))
            .fold(0.0, f64::max);
        let contact_laws = crate::contact::ContactLaws::default();
        let mut counts = Vec::new();
        for (w, ids) in ids.iter().enumerate() {
            let mut batched = vec![SurfaceSlot::default(); ids.len()];
            let mut scalar = batched.clone();
            for step in 0..2 {
                if step == 1 {
                    let wall = walls[w].as_ref().expect("present");
                    for &i in ids {
                        let x = set.position[i as usize];
                        let (cp, dist) = wall.closest_point(x);
                        set.position[i as usize] = x + (x - cp) / dist * (0.1 * R);
                    }
                }
                let tables = BondTables::of(&[], &wall_coeffs);
                let input =
                    surface_input(&set, (&walls, &wall_coeffs, &tables), &contact_laws, reach);
                let a = pass(&input, w, ids, &mut batched, true);
                let b = pass(&input, w, ids, &mut scalar, false);
                assert_eq!(a.3, b.3, "wall {w} step {step}: contacts");
                assert_eq!(a.4, b.4, "wall {w} step {step}: worst overlap");
                assert_same_sums(&a, &b);
                let mut gaps_held = 0;
                for ((x, y), &i) in batched.iter().zip(&scalar).zip(ids.iter()) {
                    assert_eq!(x.contacts.len(), y.contacts.len());
                    for (p, q) in x.contacts.iter().zip(&y.contacts) {
                        let t = q.history.tangential;
                        assert!(close(p.history.tangential, t, t.length()), "history");
                        assert_eq!(p.history.bonded, q.history.bonded, "bond");
                    }
                    let wall = walls[w].as_ref().expect("present");
                    let apart = wall.closest_point(set.position[i as usize]).1 > R;
                    gaps_held += usize::from(apart && !y.contacts.is_empty());
                }
                counts.push((a.3, gaps_held));
            }
        }
        // On each wall: bonds held across gaps in step 2, and fewer contacts than in step 1
        // (bonds broke, or never formed).
        for pair in counts.chunks(2) {
            let ((first, _), (second, held)) = (pair[0], pair[1]);
            assert!(held > 0 && second < first, "{counts:?}");
        }
    }

    #[test]
    fn batched_surface_contacts_match_the_one_by_one_laws() {
        // The batches against `ContactLaws::resolve` over the same contacts, for two steps
        // (the second continues the histories the first wrote back). Same formulas with a
        // few operations regrouped (`forces::kernel`): agreement to 1e-12 of each body's
        // largest force or torque; the counts, the worst contact and the order of the
        // element bookings are equal.
        let (set, ids) = spheres();
        let walls = walls();
        let wall_coeffs = coefficients(&walls);
        let laws = crate::contact::ContactLaws::default();
        let tables = BondTables::of(&[], &wall_coeffs);
        let input = surface_input(&set, (&walls, &wall_coeffs, &tables), &laws, 0.0);
        for (w, ids) in ids.iter().enumerate() {
            let mut batched = vec![SurfaceSlot::default(); ids.len()];
            let mut scalar = batched.clone();
            for step in 0..2 {
                let a = pass(&input, w, ids, &mut batched, true);
                let b = pass(&input, w, ids, &mut scalar, false);
                assert_eq!(a.3, b.3, "wall {w} step {step}: contacts");
                assert!(
                    a.3 > 2 * BATCH,
                    "wall {w}: several batches, {} contacts",
                    a.3
                );
                assert_eq!(a.4, b.4, "wall {w} step {step}: worst overlap");
                assert_same_sums(&a, &b);
                for (x, y) in batched.iter().zip(&scalar) {
                    assert_eq!(x.contacts.len(), y.contacts.len());
                    for (p, q) in x.contacts.iter().zip(&y.contacts) {
                        let t = q.history.tangential;
                        assert!(close(p.history.tangential, t, t.length()), "history");
                        assert!(t != DVec3::ZERO, "a touching contact slides or sticks");
                    }
                }
            }
            if w == 0 {
                assert!(
                    batched.iter().any(|s| s.contacts.len() >= 2),
                    "some sphere touches two triangles of the trough"
                );
            }
        }
    }
}

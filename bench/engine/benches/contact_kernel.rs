//! Criterion benchmark of the contact kernel: the scalar `ContactLaws::resolve` and the
//! structure-of-arrays batch the engine uses for the paper's laws, on Table-1 contacts
//! (sphere pairs, and sphere–wall contacts like those on the slab's faces).

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use dem::contact::cohesion::BondConstants;
use dem::contact::geometry::{sphere_sphere, Sphere};
use dem::contact::{BodyMotion, Cohesion, ContactHistory, ContactLaws};
use dem::internals::{Batch, BATCH};
use dem::material::{Interaction, Material, PairCoefficients};
use dem::DVec3;

/// Time step of the paper's base case [s].
const DT: f64 = 2.5e-6;

/// A Table-1 sphere–sphere contact number `k`: 1 % overlap, moving and spinning.
fn contact(k: usize) -> (DVec3, DVec3, DVec3, DVec3, DVec3) {
    let a = k as f64 * 0.37;
    let normal = DVec3::new(a.cos(), a.sin(), 0.3).normalize();
    let d = normal * (3.0e-3 - 1.5e-5);
    let dv = DVec3::new(0.1 * a.sin(), -0.2, 0.05);
    let (wi, wj) = (
        DVec3::new(3.0, -1.0, 2.0 * a.cos()),
        DVec3::new(-1.0, 0.5, 0.2),
    );
    // One contact in four slides, as about a fifth of the sphere pairs do in the paper's
    // discharge: at this overlap the Coulomb cap is reached at |ξ| = μ_s E* δ_n/(6 G*) ≈ 5.8 μm,
    // so 10 μm slides and 1 μm sticks.
    let stretch = if k.is_multiple_of(4) { 1e-5 } else { 1e-6 };
    let xi = DVec3::new(-normal.y, normal.x, 0.0) * stretch;
    (d, dv, wi, wj, xi)
}

/// A full batch of the contacts of [`contact`] between Table-1 spheres of radius `r` [m] and
/// mass `mass` [kg].
fn batch_of_table1_contacts(coeff: &PairCoefficients, r: f64, mass: f64) -> Batch {
    let mut batch = Batch::default();
    for k in 0..BATCH {
        let (d, dv, wi, wj, xi) = contact(k);
        batch.set_pair_motion(k, (d, dv), (wi, wj), xi);
        batch.radius[0][k] = r;
        batch.radius[1][k] = r;
        batch.mass[0][k] = mass;
        batch.mass[1][k] = mass;
    }
    batch.fill_coefficients(coeff);
    batch.len = BATCH;
    batch
}

fn kernels(c: &mut Criterion) {
    let m = Material::fan2023();
    let coeff = PairCoefficients::new(&m, Some(&m), &Interaction::fan2023());
    let (r, mass) = (
        1.5e-3,
        2500.0 * 4.0 / 3.0 * std::f64::consts::PI * 1.5e-3f64.powi(3),
    );
    let mut group = c.benchmark_group("contact_kernel");
    group.throughput(Throughput::Elements(BATCH as u64));

    group.bench_function("scalar_resolve_one_batch", |b| {
        let laws = ContactLaws::default();
        let sphere = Sphere {
            radius: r,
            mass,
            inertia: 0.4 * mass * r * r,
        };
        b.iter(|| {
            let mut sum = DVec3::ZERO;
            for k in 0..BATCH {
                let (d, dv, wi, wj, xi) = contact(k);
                let g = sphere_sphere(d, d.length_squared(), &sphere, &sphere);
                let mut h = ContactHistory {
                    tangential: xi,
                    ..ContactHistory::default()
                };
                let bi = BodyMotion {
                    velocity: dv,
                    omega: wi,
                };
                let bj = BodyMotion {
                    velocity: DVec3::ZERO,
                    omega: wj,
                };
                sum += laws
                    .resolve(black_box(&g), &bi, &bj, &coeff, &mut h, DT)
                    .force;
            }
            sum
        })
    });

    group.bench_function("batch_resolve_one_batch", |b| {
        let mut batch = batch_of_table1_contacts(&coeff, r, mass);
        let fresh = batch.xi;
        b.iter(|| {
            batch.xi = fresh;
            black_box(&mut batch).resolve_pairs(DT);
            batch.force[0][0]
        })
    });
    // The equal-sphere kernel the paper's beds use (R* and m* constants).
    let mut uniform = batch_of_table1_contacts(&coeff, r, mass);
    let fresh = uniform.xi;
    group.bench_function("batch_resolve_uniform_one_batch", |b| {
        b.iter(|| {
            uniform.xi = fresh;
            black_box(&mut uniform).resolve_pairs_uniform(DT, r, mass);
            uniform.force[0][0]
        })
    });
    // The wall kernel on the slab faces' contacts: normal ±y, a small overlap, the wall at
    // rest and not spinning (ω_j = 0), every coefficient shared.
    let mut walls = batch_of_table1_contacts(&coeff, r, mass);
    for k in 0..BATCH {
        let side = if k % 2 == 0 { 1.0 } else { -1.0 };
        walls.d[0][k] = 0.0;
        walls.d[1][k] = side;
        walls.d[2][k] = 0.0;
        walls.overlap[k] = 1e-7 * (1 + k % 5) as f64;
        for c in 0..3 {
            walls.omega[1][c][k] = 0.0;
        }
    }
    let fresh = walls.xi;
    group.bench_function("batch_resolve_walls_one_batch", |b| {
        b.iter(|| {
            walls.xi = fresh;
            black_box(&mut walls).resolve_walls(DT);
            walls.force[0][0]
        })
    });
    // A batch one contact short of full, as every wall run and every step's last pair
    // batch ends: its last `len mod 8` contacts must cost what the others do, not fall to a
    // scalar remainder loop (about 25 ns each against 7).
    let mut short = walls.clone();
    short.len = BATCH - 1;
    group.bench_function("batch_resolve_walls_short_batch", |b| {
        b.iter(|| {
            short.xi = fresh;
            black_box(&mut short).resolve_walls(DT);
            short.force[0][0]
        })
    });
    // The bonding laws in the equal-sphere kernel, every slot of one law: JKR at w = 0.1 J/m²
    // (Bo ≈ 1 for Table-1 spheres) and a liquid bridge of 1 nl of water at θ = 20°.
    for (name, law) in [
        (
            "batch_resolve_jkr_uniform_one_batch",
            Cohesion::Jkr {
                work_of_adhesion: 0.1,
            },
        ),
        (
            "batch_resolve_bridge_uniform_one_batch",
            Cohesion::LiquidBridge {
                volume: 1e-12,
                surface_tension: 0.072,
                contact_angle: 20f64.to_radians(),
            },
        ),
    ] {
        let bonded =
            PairCoefficients::new(&m, Some(&m), &Interaction::fan2023().with_cohesion(law));
        let mut batch = batch_of_table1_contacts(&bonded, r, mass);
        batch.bond.fill(&BondConstants::of(&bonded), bonded.e_star);
        let fresh = batch.xi;
        group.bench_function(name, |b| {
            b.iter(|| {
                batch.xi = fresh;
                black_box(&mut batch).resolve_bonded_pairs_uniform(DT, r, mass);
                batch.force[0][0]
            })
        });
    }
    group.finish();
}

criterion_group!(benches, kernels);
criterion_main!(benches);

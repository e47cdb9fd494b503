//! Criterion benchmark of the neighbour search: binning into the cell grid, and a full
//! rebuild of the Verlet lists with contact history carried by tag (what a particle removal
//! triggers), on a jittered dense packing of Table-1 spheres.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use dem::internals::CellGrid;
use dem::{DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig};

/// Table-1 diameter [m].
const D: f64 = 3.0e-3;

/// `side³` spheres on a lattice 0.995 d apart with a deterministic ±0.002 d jitter, no gravity,
/// after 20 steps so that the lists and histories exist.
fn packing(side: usize) -> Simulation {
    let mut config = SimulationConfig::new(2.5e-6);
    config.gravity = DVec3::ZERO;
    config.skin = 0.1 * D;
    let mut sim = Simulation::new(config).expect("valid configuration");
    let id = sim
        .add_material(Material::fan2023(), Interaction::fan2023())
        .expect("valid material");
    for k in 0..side * side * side {
        let (x, y, z) = (k % side, (k / side) % side, k / (side * side));
        let jitter = DVec3::new(
            (k as f64 * 0.7).sin(),
            (k as f64 * 1.3).sin(),
            (k as f64 * 2.1).sin(),
        ) * 0.002
            * D;
        let at = DVec3::new(x as f64, y as f64, z as f64) * 0.995 * D + jitter;
        sim.add_particle(ParticleInit::at_rest(at, 0.5 * D, id))
            .expect("valid particle");
    }
    sim.run(20).expect("the packing relaxes without error");
    sim
}

fn rebuild(c: &mut Criterion) {
    let mut group = c.benchmark_group("neighbour_rebuild");
    for side in [15usize, 30] {
        let sim = packing(side);
        let n = sim.particles().len();
        group.throughput(Throughput::Elements(n as u64));
        let positions = sim.particles().positions().to_vec();
        group.bench_function(format!("cell_grid_{n}"), |b| {
            b.iter(|| CellGrid::build(&positions, 1.1 * D))
        });
        let state = sim.state().clone();
        group.bench_function(format!("verlet_lists_with_history_{n}"), |b| {
            b.iter_batched(
                || Simulation::from_state(state.clone(), 1).expect("a saved state restores"),
                |mut sim| sim.remove_particles(|k, _| k == 0),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, rebuild);
criterion_main!(benches);

//! Turns a validated case into an engine simulation: materials, laws and walls.

use dem::{
    ContactLaws, DVec3, DemError, MaterialId, RollingLaw, Simulation, SimulationConfig,
    TangentialLaw,
};
use rand::Rng;

use crate::container::SlabWalls;
use crate::container::{build_container_walls, ContainerWalls};
use case::{Case, SizeDistribution};

/// EPSD viscous damping ratio η_r: Ai et al. (2011) suggest 0.3 (docs/physics.md §4.1).
const EPSD_DAMPING: f64 = 0.3;

/// Verlet skin as a fraction of the largest diameter. 0.1 d keeps candidate pairs close to
/// actual contacts while particles at 1–2 m/s cross half of it in about 60 steps.
const SKIN_DIAMETERS: f64 = 0.1;

fn engine_material(m: &case::MaterialSpec) -> dem::Material {
    dem::Material::from_shear_modulus(m.density, m.shear_modulus, m.poisson_ratio)
}

/// The engine's coefficients of a pair whose case values are `i`, for particles of
/// coarse-graining factor `kappa` (1 for the grains themselves): friction, rolling friction
/// and restitution are kept, and the cohesion is the parcels' (docs/physics.md §2.8).
fn engine_interaction(i: &case::InteractionSpec, kappa: f64) -> dem::Interaction {
    dem::Interaction {
        friction: i.friction,
        rolling_friction: i.rolling_friction,
        restitution: i.restitution,
        cohesion: i.cohesion.coarse_grained(kappa),
    }
}

/// The material table with every listed pair's cohesion the parcels' of factor `kappa`
/// (unlisted pairs mix from these, as the grains' would).
fn parcel_table(table: &dem::MaterialTable, kappa: f64) -> dem::MaterialTable {
    let mut parcels = table.clone();
    for pair in &mut parcels.pairs {
        pair.cohesion = pair.cohesion.coarse_grained(kappa);
    }
    parcels
}

/// The engine's contact laws for a case.
pub fn contact_laws(case: &Case) -> ContactLaws {
    ContactLaws {
        normal_clamp: case.contact.normal_clamp,
        tangential: match case.contact.tangential {
            case::TangentialLawSpec::MindlinNoSlip => TangentialLaw::MindlinNoSlip,
            case::TangentialLawSpec::MindlinDeresiewicz => TangentialLaw::MindlinDeresiewicz,
        },
        rolling: match case.contact.rolling {
            case::RollingLawSpec::ConstantTorque => RollingLaw::ConstantTorque { limiter: false },
            case::RollingLawSpec::Epsd => RollingLaw::Epsd {
                viscous_damping: EPSD_DAMPING,
            },
        },
    }
}

/// A simulation holding the container's walls (gate closed) and the particle material (of
/// the first component, for a mixture: [`case_simulation_by_component`] gives them all).
pub fn case_simulation(
    case: &Case,
    threads: usize,
) -> Result<(Simulation, ContainerWalls, MaterialId), DemError> {
    let (sim, walls, ids) = case_simulation_by_component(case, threads)?;
    Ok((sim, walls, ids[0]))
}

/// A simulation holding the container's walls (gate closed) and the particles' materials,
/// with the engine material of each component of `case.particles`, in order.
///
/// A case without a `[materials]` table has one particle material, shared by every
/// component, with the `[contact]` and `[wall]` coefficients. A case with one registers the
/// table's particle materials with every pair among them, and walls of a named material meet
/// each particle material with its pair's coefficients (docs/physics.md §1.2).
pub fn case_simulation_by_component(
    case: &Case,
    threads: usize,
) -> Result<(Simulation, ContainerWalls, Vec<MaterialId>), DemError> {
    let mut config = SimulationConfig::new(case.time_step);
    config.laws = contact_laws(case);
    config.gravity = DVec3::new(0.0, 0.0, -case.gravity);
    config.threads = threads;
    config.skin = SKIN_DIAMETERS * case.particles.max_diameter();
    config.max_rayleigh_fraction = case::MAX_RAYLEIGH_FRACTION;
    let mut sim = Simulation::new(config)?;
    let components = &case.particles.components;
    // Coarse-grained parcels scale the cohesion; κ = 1 multiplies by one, exactly.
    let kappa = case.particles.coarse_graining_factor();
    let Some(table) = &case.materials else {
        let material = engine_material(&components[0].material);
        let id = sim.add_material(material, engine_interaction(&case.contact.particle, kappa))?;
        let wall_material = match &case.wall.material {
            case::WallMaterialSpec::SameAsParticle => dem::WallMaterial::Elastic(material),
            case::WallMaterialSpec::Rigid => dem::WallMaterial::Rigid,
            case::WallMaterialSpec::Custom(m) => dem::WallMaterial::Elastic(engine_material(m)),
            case::WallMaterialSpec::Named(name) => return Err(no_table(name)),
        };
        let walls = build_container_walls(
            &mut sim,
            &case.geometry,
            wall_material,
            engine_interaction(&case.wall.interaction, kappa),
        )?;
        return Ok((sim, walls, vec![id; components.len()]));
    };
    // Each particle material once, in the order the components first name it.
    let mut names: Vec<&str> = Vec::new();
    for c in components {
        let name = c.material_name.as_deref().ok_or_else(|| {
            DemError::InvalidInput(format!(
                "component {} has no material of the case's [materials] table",
                c.name
            ))
        })?;
        if !names.contains(&name) {
            names.push(name);
        }
    }
    let table = &parcel_table(table, kappa);
    let ids = sim.add_material_table(table, &names)?;
    let component_ids = components
        .iter()
        .map(|c| {
            let name = c.material_name.as_deref().unwrap_or_default();
            ids.get(name).ok_or_else(|| no_table(name))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let walls = match &case.wall.material {
        case::WallMaterialSpec::Named(name) => {
            // Built with the first particle material's pair; then each particle material
            // gets its own pair on every wall.
            let walls = build_container_walls(
                &mut sim,
                &case.geometry,
                table.wall_material(name)?,
                table.interaction(names[0], name)?,
            )?;
            for wall in walls.all() {
                sim.set_wall_from_table(wall, table, &ids, name)?;
            }
            walls
        }
        other => {
            let material = match other {
                case::WallMaterialSpec::Custom(m) => dem::WallMaterial::Elastic(engine_material(m)),
                case::WallMaterialSpec::Rigid => dem::WallMaterial::Rigid,
                // Validation names the one particle material instead.
                _ => {
                    return Err(DemError::InvalidInput(
                        "wall.material = \"same\" with a [materials] table must name the \
                         particles' material"
                            .to_string(),
                    ))
                }
            };
            build_container_walls(
                &mut sim,
                &case.geometry,
                material,
                engine_interaction(&case.wall.interaction, kappa),
            )?
        }
    };
    Ok((sim, walls, component_ids))
}

/// The refusal of a material name that the case's table does not hold.
fn no_table(name: &str) -> DemError {
    DemError::InvalidInput(format!(
        "material \"{name}\" is not in the case's [materials] table"
    ))
}

/// A simulation holding the slab hopper's walls (gate closed) and the particle material;
/// refused for a case of another kind.
pub fn slab_simulation(
    case: &Case,
    threads: usize,
) -> Result<(Simulation, SlabWalls, MaterialId), DemError> {
    match case_simulation(case, threads)? {
        (sim, ContainerWalls::Slab(walls), id) => Ok((sim, walls, id)),
        _ => Err(not_a_slab(case)),
    }
}

/// The refusal of a slab-only operation on a case of another kind.
fn not_a_slab(case: &Case) -> DemError {
    DemError::InvalidInput(format!(
        "this needs the slab hopper (geometry.kind = \"slab\"), not a {} case",
        case.geometry.kind()
    ))
}

/// Draws one particle radius [m] from the case's size distribution.
pub fn sample_radius(size: &SizeDistribution, rng: &mut dyn rand::RngCore) -> f64 {
    let d = match size {
        SizeDistribution::Monodisperse { diameter } => *diameter,
        SizeDistribution::Uniform { min, max } => min + (max - min) * rng.gen::<f64>(),
        SizeDistribution::Normal {
            mean,
            std_dev,
            min,
            max,
        } => {
            // Box–Muller, truncated by rejection to [min, max].
            loop {
                let (u1, u2): (f64, f64) = (rng.gen::<f64>().max(f64::MIN_POSITIVE), rng.gen());
                let z = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
                let d = mean + std_dev * z;
                if d >= *min && d <= *max {
                    break d;
                }
            }
        }
        SizeDistribution::Discrete {
            diameters,
            fractions,
        } => {
            let u: f64 = rng.gen();
            let mut acc = 0.0;
            let mut pick = diameters[diameters.len() - 1];
            for (d, f) in diameters.iter().zip(fractions) {
                acc += f;
                if u < acc {
                    pick = *d;
                    break;
                }
            }
            pick
        }
    };
    0.5 * d
}

/// Places `count` particles on a jittered hexagonal lattice filling the hopper from the
/// bottom up, at rest: a dense start for benchmarks, not the paper's fill protocol.
pub fn lattice_bed(
    sim: &mut Simulation,
    case: &Case,
    material: MaterialId,
    count: usize,
    rng: &mut impl Rng,
) -> Result<usize, DemError> {
    let g = case.slab().ok_or_else(|| not_a_slab(case))?;
    let r = 0.5 * case.particles.max_diameter();
    let spacing = 2.0 * r * 1.01;
    let row = spacing * 3f64.sqrt() / 2.0;
    let mut placed = 0;
    let mut k = 0usize;
    let half = 0.5 * g.width;
    while placed < count {
        let z = r * 1.05 + row * k as f64;
        if z + r > g.height {
            break;
        }
        let shift = if k.is_multiple_of(2) {
            0.0
        } else {
            0.5 * spacing
        };
        let mut x = -half + r * 1.05 + shift;
        while x + r < half && placed < count {
            let jitter = 0.002 * r * (rng.gen::<f64>() - 0.5);
            if crate::fill::inside_slab(g, x, z, r, 1e-5) {
                sim.add_particle(dem::ParticleInit::at_rest(
                    DVec3::new(x + jitter, 0.5 * g.thickness, z),
                    r,
                    material,
                ))?;
                placed += 1;
            }
            x += spacing;
        }
        k += 1;
    }
    Ok(placed)
}

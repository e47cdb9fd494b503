//! The simulation: one owner of the whole state, advanced by velocity Verlet (docs/physics.md §6.2).

use std::ops::Range;
use std::sync::Arc;

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use crate::clump::{ClumpSet, ClumpShape};
use crate::contact::{normal::hertz_energy, ContactLaws};
use crate::error::DemError;
use crate::forces::bond_rows::BondTables;
use crate::forces::loads::{LoadQuanta, SurfaceLoads, WallLoad};
use crate::forces::{self, ContactCount, ForceBuffers, KernelInput, WorstOverlap};
use crate::integrator::{
    displacement_box_diagonal, kick, kick_drift, kick_drift_flat_tracked, kick_drift_range,
    largest_displacement, merge_drift, uniform_free_body, NOTHING_MOVED,
};
use crate::material::{harmonic, Interaction, Material, PairCoefficients, WallMaterial};
use crate::neighbour::{
    build_lists, Carry, CellGrid, ListScratch, PairList, PairSearch, SizeClasses, WallPairList,
};
use crate::particles::{MaterialId, ParticleInit, ParticleSet, ParticleTag};
use crate::reach::ReachBound;
use crate::region_force::RegionForce;
use crate::team::Team;
use crate::timescale::rayleigh_time;
use crate::timing::{Mark, PhaseTimes, StepClock};
use crate::wall::{Wall, WallId};
use crate::watch::Watched;

mod edit;
mod energy;
mod guards;
mod material_table;
mod rebuild;
mod run;
mod step;
mod walls;

pub use edit::RemovedParticle;
pub use energy::Energy;
use guards::*;
pub use material_table::MaterialIds;
use step::*;

/// Settings fixed for a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SimulationConfig {
    /// Time step Δt [s]. The paper's base case uses 2.5e-6 s = 0.097 t_R (docs/physics.md §6.1).
    pub time_step: f64,
    /// Gravitational acceleration [m/s²]; z is vertical, so (0, 0, −9.81) on Earth.
    pub gravity: DVec3,
    /// Contact sub-models.
    pub laws: ContactLaws,
    /// Verlet skin [m]; 0 picks 0.2 × the largest radius when the first list is built.
    pub skin: f64,
    /// Largest accepted Δt / t_R [-]. EDEM's guidance is 0.1–0.4; the paper stays below 0.1.
    pub max_rayleigh_fraction: f64,
    /// Largest accepted overlap as a fraction of the smaller radius [-]; beyond it the run stops.
    pub max_overlap_fraction: f64,
    /// Worker threads for force evaluation; 0 uses every core, 1 runs without a pool.
    pub threads: usize,
    /// Re-sort particles into cell order every this many list rebuilds (0: never).
    pub resort_every: u32,
}

impl SimulationConfig {
    /// Defaults around a time step `time_step` [s]: Earth gravity along −z, the paper's laws.
    pub fn new(time_step: f64) -> Self {
        Self {
            time_step,
            gravity: DVec3::new(0.0, 0.0, -9.81),
            laws: ContactLaws::default(),
            skin: 0.0,
            // 0.25 t_R leaves room for verification runs at coarser steps while refusing the
            // clearly unstable ones; production runs use 0.097.
            max_rayleigh_fraction: 0.25,
            // Hopper impacts at 3 m/s overlap by ≈ 3 % of the radius (docs/physics.md §1.1); 10 % means
            // something is wrong.
            max_overlap_fraction: 0.1,
            threads: 1,
            resort_every: 16,
        }
    }
}

/// Everything that defines the state of a run; serialisable for checkpoints, so that a
/// resumed run is bit-identical to an uninterrupted one.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SimulationState {
    config: SimulationConfig,
    materials: Vec<Material>,
    interactions: Vec<Option<Interaction>>,
    particles: ParticleSet,
    walls: Vec<Option<Wall>>,
    /// Per wall (parallel to `walls`), its interaction with each particle material, indexed
    /// by material id, where one was set; a material without one meets the wall with the
    /// wall's own interaction.
    wall_interactions: Vec<Vec<Option<Interaction>>>,
    pairs: PairList,
    wall_pairs: WallPairList,
    /// Positions at the last list build [m].
    reference: Vec<DVec3>,
    /// Largest wall displacement since the last build [m].
    wall_drift: f64,
    skin: f64,
    /// How far beyond contact [m] the cohesion of the lists' last build reached (the lists
    /// hold the pairs closer than R_i + R_j + skin + this); 0 without cohesion.
    #[serde(default)]
    list_reach: f64,
    time: f64,
    steps: u64,
    rebuilds: u64,
    needs_rebuild: bool,
    indices_changed: bool,
    contacts: ContactCount,
    /// The element loads of each wall (by wall index) summed over the current window.
    surface_loads: Vec<SurfaceLoads>,
    /// Each wall's load (by wall index) integrated over time since it was added: force
    /// [N s] and torque about the origin [N m s], summed step by step in step order.
    wall_impulses: Vec<WallLoad>,
    /// The quanta of the walls' fixed-point loads, as the last preparation set them from
    /// the particles of that moment; `None` before the first. Kept in the state so that a
    /// restored simulation sums its wall loads to the same bits as the one that saved it.
    load_quanta: Option<LoadQuanta>,
    /// The rigid clumps, whose members are among the particles (docs/physics.md §11.4).
    #[serde(default)]
    clumps: ClumpSet,
}

impl SimulationState {
    /// How far the walls have moved since the last list build [m], where there are walls:
    /// the wall branch of the list-build test (`Simulation::lists_may_miss`).
    fn walls_moved(&self) -> Option<f64> {
        self.walls
            .iter()
            .any(Option::is_some)
            .then_some(self.wall_drift)
    }
}

/// A DEM simulation of spheres and walls.
pub struct Simulation {
    state: SimulationState,
    pool: Option<Arc<Team>>,
    /// Cells sized by the largest sphere: the order of the re-sorts, and the candidate search
    /// for (near-)uniform radii.
    grid: CellGrid,
    /// The bodies by size class, for the candidate search of wide size distributions.
    size_classes: SizeClasses,
    buffers: ForceBuffers,
    pair_coeffs: Vec<PairCoefficients>,
    wall_coeffs: Vec<PairCoefficients>,
    /// The bonding constants of `pair_coeffs` and `wall_coeffs`, formed with them.
    bond_tables: BondTables,
    /// Whether any pair of materials, or any material and wall, bonds beyond contact (JKR, a
    /// liquid bridge; found with the coefficients): the lists then reach beyond contact.
    bonds: bool,
    /// Whether any pair of materials bonds: the batched kernel then resolves the pairs with
    /// the bonding laws (`forces::pairs`).
    pair_bonds: bool,
    /// Whether any material and wall bond: the wall contacts are then resolved one at a
    /// time (`forces::general`).
    wall_bonds: bool,
    /// Whether any pair has the simplified JKR's attraction, which the batched kernel adds.
    area_cohesion: bool,
    /// Radius [m] and mass [kg] shared by every particle, when they are all alike; found at
    /// each list rebuild (which every addition or removal of a particle forces).
    uniform_body: Option<(f64, f64)>,
    /// 1/m [1/kg] and 1/I [1/(kg m²)] shared by every particle when all are alike and free
    /// (`integrator::uniform_free_body`); found with `uniform_body`, and after a change of flags.
    uniform_free: Option<(f64, f64)>,
    prepared: bool,
    /// Time per phase since timing was switched on; `None` while off.
    phase_times: Option<PhaseTimes>,
    /// The lists before the last build, kept for their allocations: the next build writes
    /// into them, instead of growing fresh vectors to some 10^4 candidates at every build.
    spare_lists: (PairList, WallPairList),
    /// Bounds on the displacements since the last build, which spare the exact measures
    /// where they rule a build out ([`ReachBound`]); not part of the state: a restored
    /// simulation measures until its first build.
    reach_bound: ReachBound,
    /// The list builds' working arrays, kept for their memory ([`ListScratch`]).
    list_scratch: ListScratch,
    /// The quanta of the walls' fixed-point loads, set with the coefficients.
    load_quanta: LoadQuanta,
    /// Whether the next preparation sets new quanta: after an edit (which may have added
    /// particles farther out or lighter), not after a restore, which keeps the saved ones.
    new_quanta: bool,
    /// Each wall's load in the last step (by wall index); not part of the state: a restored
    /// simulation has zero loads until its first step.
    wall_loads: Vec<WallLoad>,
    /// The error that stopped a step after it had begun to move bodies: every later step is
    /// refused with [`DemError::AfterFailure`], since the state is no longer one instant's.
    /// Not part of the state: a simulation restored from a checkpoint starts without it.
    failure: Option<Box<DemError>>,
    /// The external force on the particles of a region, added at every step while set
    /// ([`Simulation::set_region_force`]). Not part of the state: a caller that checkpoints
    /// sets it again on the restored simulation.
    region_force: Option<RegionForce>,
}

fn make_pool(threads: usize) -> Result<Option<Arc<Team>>, DemError> {
    if threads == 1 {
        return Ok(None);
    }
    Team::new(threads)
        .map(|pool| Some(Arc::new(pool)))
        .map_err(|_| DemError::ThreadPool(threads))
}

impl Simulation {
    /// An empty simulation.
    pub fn new(config: SimulationConfig) -> Result<Self, DemError> {
        if !(config.time_step.is_finite() && config.time_step > 0.0) {
            return Err(DemError::InvalidInput(format!(
                "time step must be positive and finite, got {}",
                config.time_step
            )));
        }
        if !config.gravity.is_finite() {
            return Err(DemError::InvalidInput(format!(
                "gravity must be finite, got {}",
                config.gravity
            )));
        }
        // `!(x >= 0)` and `!(x > 0)` also refuse NaN, which every comparison would let pass.
        if !(config.skin >= 0.0 && config.skin.is_finite()) {
            return Err(DemError::InvalidInput(format!(
                "skin must be finite and ≥ 0 (0 picks 0.2 × the largest radius), got {}",
                config.skin
            )));
        }
        if !(config.max_overlap_fraction > 0.0) {
            return Err(DemError::InvalidInput(format!(
                "overlap limit (max_overlap_fraction) must be > 0, got {}",
                config.max_overlap_fraction
            )));
        }
        if !(config.max_rayleigh_fraction > 0.0) {
            // A NaN limit would switch the Rayleigh guard off without a word.
            return Err(DemError::InvalidInput(format!(
                "time-step limit (max_rayleigh_fraction) must be > 0, got {}",
                config.max_rayleigh_fraction
            )));
        }
        let state = SimulationState {
            config,
            materials: Vec::new(),
            interactions: Vec::new(),
            particles: ParticleSet::default(),
            walls: Vec::new(),
            wall_interactions: Vec::new(),
            pairs: PairList::default(),
            wall_pairs: WallPairList::default(),
            reference: Vec::new(),
            wall_drift: 0.0,
            skin: config.skin,
            list_reach: 0.0,
            time: 0.0,
            steps: 0,
            rebuilds: 0,
            needs_rebuild: true,
            indices_changed: false,
            contacts: ContactCount::default(),
            surface_loads: Vec::new(),
            wall_impulses: Vec::new(),
            load_quanta: None,
            clumps: ClumpSet::default(),
        };
        Self::from_state(state, config.threads)
    }

    /// Restores a saved state with `threads` worker threads (0 = every core).
    pub fn from_state(mut state: SimulationState, threads: usize) -> Result<Self, DemError> {
        // Checkpoints from before the wall-major candidate order hold particle-major lists.
        state.wall_pairs = std::mem::take(&mut state.wall_pairs).into_wall_major();
        let new_quanta = state.load_quanta.is_none();
        Ok(Self {
            pool: make_pool(threads)?,
            state,
            grid: CellGrid::default(),
            size_classes: SizeClasses::default(),
            buffers: ForceBuffers::default(),
            pair_coeffs: Vec::new(),
            wall_coeffs: Vec::new(),
            bond_tables: BondTables::default(),
            bonds: false,
            pair_bonds: false,
            wall_bonds: false,
            area_cohesion: false,
            uniform_body: None,
            uniform_free: None,
            prepared: false,
            phase_times: None,
            spare_lists: Default::default(),
            reach_bound: ReachBound::default(),
            list_scratch: ListScratch::default(),
            load_quanta: LoadQuanta::default(),
            new_quanta,
            wall_loads: Vec::new(),
            failure: None,
            region_force: None,
        })
    }

    /// Switches the per-phase timing of steps on (from zero) or off. It reads the clock and
    /// changes nothing else: trajectories are bit-identical either way.
    pub fn time_phases(&mut self, on: bool) {
        self.phase_times = on.then(PhaseTimes::default);
    }

    /// Wall-clock time per phase of the steps taken since [`Simulation::time_phases`]
    /// switched timing on; `None` while it is off.
    pub fn phase_times(&self) -> Option<PhaseTimes> {
        self.phase_times
    }

    /// Sets (or, with `None`, removes) the external force on the particles whose centres lie
    /// in a region (docs/physics.md §6.4): from the next force evaluation on, each step adds
    /// π r² τ to every free particle inside, at the positions the step evaluates its forces
    /// at (the next step's first half kick still uses the forces evaluated before). A force
    /// that is not finite, or a region that is empty, is refused and nothing changes.
    pub fn set_region_force(&mut self, force: Option<RegionForce>) -> Result<(), DemError> {
        if let Some(fault) = force.as_ref().and_then(RegionForce::fault) {
            return Err(DemError::InvalidInput(format!("region force: {fault}")));
        }
        self.region_force = force;
        Ok(())
    }

    /// The external force on a region's particles, where one is set.
    pub fn region_force(&self) -> Option<&RegionForce> {
        self.region_force.as_ref()
    }

    /// The complete state, for checkpoints.
    pub fn state(&self) -> &SimulationState {
        &self.state
    }

    /// Changes the number of worker threads (results do not depend on it).
    pub fn set_threads(&mut self, threads: usize) -> Result<(), DemError> {
        self.pool = make_pool(threads)?;
        self.state.config.threads = threads;
        Ok(())
    }

    /// A wall by handle.
    pub fn wall(&self, id: WallId) -> Option<&Wall> {
        self.state.walls.get(id.0 as usize).and_then(Option::as_ref)
    }

    /// The rigid clumps (read-only); their members are among the particles.
    pub fn clumps(&self) -> &ClumpSet {
        &self.state.clumps
    }

    /// The particles (read-only; probes observe, never mutate).
    pub fn particles(&self) -> &ParticleSet {
        &self.state.particles
    }

    /// The configuration.
    pub fn config(&self) -> &SimulationConfig {
        &self.state.config
    }

    /// Simulated time [s].
    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.state.steps
    }

    /// Neighbour-list builds so far.
    pub fn rebuilds(&self) -> u64 {
        self.state.rebuilds
    }

    /// Contacts that carried force in the last step.
    pub fn contacts(&self) -> ContactCount {
        self.state.contacts
    }

    /// Particle–particle candidates in the current neighbour list: the pairs closer than
    /// R_i + R_j + skin at the last build.
    pub fn candidate_pairs(&self) -> usize {
        self.state.pairs.len()
    }

    /// The smallest Rayleigh time of the particles present [s] (paper Eq. 9).
    pub fn rayleigh_time(&self) -> Option<f64> {
        let p = &self.state.particles;
        (0..p.len())
            .map(|k| rayleigh_time(&self.state.materials[p.material[k] as usize], p.radius[k]))
            .min_by(f64::total_cmp)
    }
}

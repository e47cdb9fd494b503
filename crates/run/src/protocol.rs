//! The run protocol of one hopper case: fill, settle, open the gate, discharge (issue 3,
//! docs/physics.md §5 and §10.8), as a resumable state machine. The heap test lifts its
//! cylinder instead of opening a gate, and waits for the heap to come to rest (§5.9).

use analysis::series::RateSeries;
use analysis::AnalysisError;
use dem::{DVec3, MaterialId, ParticleInit, Simulation, SimulationState, Watched};
use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::{Deserialize, Serialize};

use crate::{
    adopt_walls, case_simulation_by_component, insert_slab_batch, ContainerWalls, Draw, Packing,
    ParticleDraws,
};
use crate::{insert_silo_batch, FillRegion};
use case::{Case, Geometry, MeshOutlet};
use files::StopReason;
use measure::{
    bed_bulk, silo_bulk, BulkMeasurement, BulkProbe, ContainerOutline, CrossingProbe, FieldGrid,
    Kernel, OutletBins, OutletGeometry, OutletShape, RadialBins, RadialPackingProbe, Snapshot,
    StripConfig, StripProbe, VelocityFieldProbe,
};

use super::fields::FieldsRecorder;
use super::orientations::OrientationRecorder;
use super::remaining::RemainingRecorder;
use super::residence::OpeningRecord;
use super::unclog::{pulse_force, AtClog, UnclogRecord};
use super::wall_forces::WallForceRecorder;
use super::wall_pressure::WallPressureRecorder;
use super::RunError;

/// Height of the insertion band below the fill top [m]: tall enough for a few hundred
/// particles per batch at random-sequential-addition density, short enough to start low.
const INSERT_BAND: f64 = 0.08;
/// Simulated time between insertion attempts [s].
pub(crate) const INSERT_INTERVAL: f64 = 0.01;
/// Settling starts being checked this long after the last insertion [s] (the last batch
/// needs about √(2H/g) ≈ 0.3 s to land from the top of a 400 mm hopper).
pub(crate) const MIN_SETTLE_AFTER_FILL: f64 = 0.05;
/// Simulated time between settling checks and particle deletions [s].
pub(crate) const CHECK_INTERVAL: f64 = 0.0025;
/// Particles observed by the crossing probe lie within this many diameters of the outlet
/// line: between two observations (≤ 100 steps) a particle moves far less than that.
const CROSSING_BAND_DIAMETERS: f64 = 2.0;
/// Height of a silo wall's pressure zones, in mean diameters: fine enough for the Janssen
/// profile (decay lengths of tens of diameters), coarse enough that a zone holds many
/// contacts.
const PRESSURE_ZONE_DIAMETERS: f64 = 2.0;
/// Speed at which the side walls slip past the settled bed (`protocol.wall_slip`) [m/s]:
/// slow enough to be quasi-static (a sphere of the benchmark's M1 at this speed has 4e-10 J of
/// kinetic energy, below the default settling threshold of 1e-9 J, and the slip's 10⁴–10⁵
/// steps are hundreds of contact times), fast enough that a slip of a tenth of a diameter
/// costs under 0.1 s of simulated time.
pub(crate) const WALL_SLIP_SPEED: f64 = 0.003;
/// The discharge's pressure windows, in W(t) bins.
const PRESSURE_WINDOW_BINS: f64 = 10.0;

/// Phase of the protocol.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Phase {
    /// Inserting particles in batches.
    Fill {
        /// Particles inserted so far.
        inserted: usize,
        /// Simulated time of the last successful insertion [s].
        last_insert: f64,
    },
    /// Waiting for the kinetic energy to fall below the threshold.
    Settle {
        /// When the fill finished [s].
        since: f64,
    },
    /// Gate open; particles leave.
    Discharge {
        /// When the gate opened [s].
        opened: f64,
        /// Last time a particle crossed the outlet [s].
        last_crossing: f64,
    },
    /// Finished.
    Done {
        /// Why the discharge stopped.
        reason: StopReason,
        /// When the gate opened [s].
        opened: f64,
    },
    /// The settled bed's side walls rise by `protocol.wall_slip` relative to its bottom
    /// (docs/physics.md §7.7), at a constant speed, until the step `until_step`.
    Slip {
        /// The step at which the walls have risen by the whole slip and stop.
        until_step: u64,
    },
    /// Settling again after the slip, as in `Settle`; the gate opens when it is calm.
    Resettle {
        /// When the slip ended [s].
        since: f64,
    },
    /// The heap test's cylinder rises at `geometry.lift_speed` until its lower edge has
    /// cleared the material (docs/physics.md §5.9).
    Lift {
        /// When the lift started [s] (the heap test's opening).
        opened: f64,
    },
    /// The heap test's cylinder is gone; the heap flows until it comes to rest.
    Rest {
        /// When the lift started [s].
        opened: f64,
        /// When the cylinder was removed [s].
        since: f64,
    },
    /// A run that breaks its arches (`[protocol.unclog]`, docs/physics.md §5.11) pushes the
    /// grains over its clogged orifice up until the step `until_step`, then discharges
    /// again; its probes go on observing.
    Pulse {
        /// When the gate opened [s].
        opened: f64,
        /// The step at which the pulse ends.
        until_step: u64,
    },
}

impl Phase {
    /// When the container opened [s] (the gate removed, or the heap test's lift started), in
    /// the phases after it; `None` before it, and once done.
    pub fn opened(&self) -> Option<f64> {
        match *self {
            Self::Discharge { opened, .. }
            | Self::Pulse { opened, .. }
            | Self::Lift { opened }
            | Self::Rest { opened, .. } => Some(opened),
            Self::Fill { .. }
            | Self::Settle { .. }
            | Self::Slip { .. }
            | Self::Resettle { .. }
            | Self::Done { .. } => None,
        }
    }
}

/// Everything of a run that a checkpoint must hold to resume bit-identically: the engine's
/// state, then the protocol's record. A running case holds only the record beside its
/// live [`Simulation`] and serialises the two as a [`RunStateView`], so that no second copy
/// of the particles and contact histories is kept; both serialise to the same bytes.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunState {
    pub(crate) sim: SimulationState,
    pub(crate) record: RunRecord,
}

/// A run's state borrowed from a running case: serialises as [`RunState`] does, byte for
/// byte (postcard writes a struct as its fields in order).
#[derive(Debug, Clone, Copy, Serialize)]
pub(crate) struct RunStateView<'a> {
    pub(crate) sim: &'a SimulationState,
    pub(crate) record: &'a RunRecord,
}

impl RunStateView<'_> {
    /// An owned copy of the state.
    pub(crate) fn to_owned(self) -> RunState {
        RunState {
            sim: self.sim.clone(),
            record: self.record.clone(),
        }
    }
}

/// The protocol's part of a run's state: the walls' handles, the fill's draws, the phase, the
/// probes and the recorders.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunRecord {
    pub(crate) walls: ContainerWalls,
    /// The engine material of each component of `particles.components`.
    pub(crate) materials: Vec<MaterialId>,
    pub(crate) rng: Xoshiro256PlusPlus,
    /// The component of each particle, by tag, for a mixture (empty for one component): what
    /// `composition.csv` sorts the outlet crossings by.
    pub(crate) components: Vec<u8>,
    /// The drawn particle that the last batch could not place; the next batch places it
    /// first (see `ParticleDraws`).
    pub(crate) pending: Option<Draw>,
    pub(crate) phase: Phase,
    pub(crate) crossing: CrossingProbe,
    /// φ(x) on the outlet strip of a slab (`None` for a silo).
    pub(crate) strip: Option<StripProbe>,
    /// The coarse-grained x–z field of a slab (`None` for a silo).
    pub(crate) field: Option<VelocityFieldProbe>,
    /// φ(r) on the outlet slab of a circular orifice (`None` for a slot).
    pub(crate) radial: Option<RadialPackingProbe>,
    pub(crate) bulk: Option<BulkMeasurement>,
    pub(crate) settled_kinetic_energy: f64,
    pub(crate) settled: bool,
    pub(crate) next_frame: f64,
    pub(crate) next_check: f64,
    pub(crate) discharged_mass: f64,
    /// Mass of the fill when the gate opened [kg].
    pub(crate) fill_mass: f64,
    /// The loads on the walls, by window (`wall_forces.csv`).
    pub(crate) wall_forces: WallForceRecorder,
    /// The particles left in the container against time (`remaining.csv`).
    pub(crate) remaining: RemainingRecorder,
    /// The long axes of shaped grains in the bed and at the outlet (`orientations.csv`;
    /// `None` for spheres).
    pub(crate) orientation: Option<OrientationRecorder>,
    /// The grains of the bed at the opening, for their residence times (`residence.csv`);
    /// empty until a gate opens.
    pub(crate) opening: OpeningRecord,
    /// Wall pressure against height of a silo (`wall_pressure.csv`; `None` for a slab).
    pub(crate) pressure: Option<WallPressureRecorder>,
    /// Coarse-grained fields (`[output.fields]`; `None` without). Not in checkpoints, so
    /// that a run without fields writes the checkpoint bytes it always wrote: a resumed run
    /// starts its fields afresh at the resume.
    #[serde(skip)]
    pub(crate) fields: Option<FieldsRecorder>,
    /// The clogs of a run that breaks its arches (`[protocol.unclog]`; `None` without).
    /// Checkpoints carry it after the time spent (`run::checkpoint`), not in this
    /// serialisation, so that a run without it writes the checkpoint bytes it always wrote.
    #[serde(skip)]
    pub(crate) unclog: Option<UnclogRecord>,
}

impl RunState {
    /// The engine's state: particles, walls, contact histories, time and step count.
    pub fn simulation(&self) -> &SimulationState {
        &self.sim
    }

    /// The handles of the container's walls in [`RunState::simulation`].
    pub fn walls(&self) -> &ContainerWalls {
        &self.record.walls
    }

    /// The engine material of each component of `particles.components`, in order.
    pub fn component_materials(&self) -> &[MaterialId] {
        &self.record.materials
    }

    /// The component of each particle, by tag, for a mixture (an index into
    /// `particles.components`; `u8::MAX` for a tag never given one); empty for one component.
    pub fn particle_components(&self) -> &[u8] {
        &self.record.components
    }
}

impl RunRecord {
    /// Records that the particle tagged `tag` belongs to mixture component `component`.
    fn record_component(&mut self, tag: u64, component: u8) {
        let k = tag as usize;
        if self.components.len() <= k {
            self.components.resize(k + 1, u8::MAX);
        }
        self.components[k] = component;
    }
}

/// A case being run.
pub struct CaseRun {
    pub(crate) case: Case,
    pub(crate) sim: Simulation,
    pub(crate) state: RunRecord,
    /// Whether to keep the state at the end of the settling ([`CaseRun::keep_bed`]).
    keep_bed: bool,
    /// The state kept at the end of the settling, gate closed, until taken.
    bed: Option<Box<RunState>>,
    /// The walls a run from a bed rebuilt for its case ([`CaseRun::from_bed`]), by name.
    rebuilt: Vec<String>,
}

/// The wall-pressure recorder of a silo's walls in `sim` (its gate left out); `None` for a
/// slab.
fn pressure_recorder(
    case: &Case,
    walls: &ContainerWalls,
    sim: &mut Simulation,
) -> Result<Option<WallPressureRecorder>, RunError> {
    let ContainerWalls::Silo(_) = walls else {
        return Ok(None);
    };
    let recorded: Vec<(u8, dem::WallId)> = walls
        .named()
        .into_iter()
        .filter_map(|(name, id)| Some((name, id?)))
        .filter(|(_, id)| *id != walls.gate())
        .collect();
    Ok(Some(WallPressureRecorder::new(
        sim,
        &recorded,
        PRESSURE_ZONE_DIAMETERS * case.particles.mean_diameter(),
        PRESSURE_WINDOW_BINS * case.measure.rate_bin_width,
    )?))
}

/// The outlet geometry of a case for the probes.
pub fn outlet_geometry(case: &Case) -> OutletGeometry {
    let particle_diameter = case.particles.mean_diameter();
    match &case.geometry {
        Geometry::Slab(g) => OutletGeometry {
            outlet_height: 0.0,
            centre: g.outlet_centre(),
            half_width: g.outlet_radius(),
            particle_diameter,
            shape: OutletShape::Slot,
        },
        Geometry::Cylinder(g) => OutletGeometry {
            outlet_height: 0.0,
            centre: g.outlet_offset,
            half_width: g.outlet_radius(),
            particle_diameter,
            shape: OutletShape::Circle { centre_y: 0.0 },
        },
        Geometry::Cuboid(g) | Geometry::DrawDown(case::DrawDownGeometry { container: g }) => {
            OutletGeometry {
                outlet_height: 0.0,
                centre: g.outlet_offset,
                half_width: g.outlet_radius(),
                particle_diameter,
                shape: match g.outlet {
                    case::CuboidOutlet::Slot => OutletShape::Slot,
                    case::CuboidOutlet::Square => OutletShape::Rectangle {
                        centre_y: 0.0,
                        half_depth: g.outlet_radius(),
                    },
                },
            }
        }
        // The heap has no outlet; its crossing probe, never shown a frame, is given the
        // plate's disc, past whose edge the grains leave.
        Geometry::Heap(g) => OutletGeometry {
            outlet_height: 0.0,
            centre: 0.0,
            half_width: g.plate_radius,
            particle_diameter,
            shape: OutletShape::Circle { centre_y: 0.0 },
        },
        Geometry::Mesh(g) => match g.outlet {
            MeshOutlet::Disc { centre, radius, .. } => OutletGeometry {
                outlet_height: 0.0,
                centre: centre[0],
                half_width: radius,
                particle_diameter,
                shape: OutletShape::Circle {
                    centre_y: centre[1],
                },
            },
            MeshOutlet::Rectangle { centre, size } => OutletGeometry {
                outlet_height: 0.0,
                centre: centre[0],
                half_width: 0.5 * size[0],
                particle_diameter,
                shape: OutletShape::Rectangle {
                    centre_y: centre[1],
                    half_depth: 0.5 * size[1],
                },
            },
        },
    }
}

/// The insertion band of the fill, (bottom, top) above the outlet plane [m]: `INSERT_BAND`
/// below the fill top (or the container's top, if lower), not below `protocol.fill_bottom`.
pub(crate) fn fill_band(case: &Case) -> (f64, f64) {
    let top = case.protocol.fill_top.min(case.geometry.height());
    ((top - INSERT_BAND).max(case.protocol.fill_bottom), top)
}

/// The region a 3D container's fill is poured into (all kinds but the slab).
fn fill_region(geometry: &Geometry) -> &dyn FillRegion {
    match geometry {
        Geometry::Cylinder(g) => g,
        Geometry::Cuboid(g) => g,
        Geometry::DrawDown(g) => &g.container,
        Geometry::Heap(g) => g,
        Geometry::Mesh(g) => g,
        Geometry::Slab(_) => unreachable!("the slab fills through `insert_slab_batch`"),
    }
}

/// The extent in y of a slot or rectangular orifice of a 3D container [m] (its x-profiles'
/// strips are that deep): a box's slot spans the depth; `None` for the slab (whose profiles
/// are per unit of its thickness) and for circular orifices.
pub fn outlet_depth(case: &Case) -> Option<f64> {
    match &case.geometry {
        Geometry::Cuboid(g) => Some(g.outlet_depth()),
        Geometry::DrawDown(g) => Some(g.container.outlet_depth()),
        Geometry::Mesh(g) => match g.outlet {
            MeshOutlet::Rectangle { size, .. } => Some(size[1]),
            MeshOutlet::Disc { .. } => None,
        },
        Geometry::Slab(_) | Geometry::Cylinder(_) | Geometry::Heap(_) => None,
    }
}

impl CaseRun {
    /// A fresh run: walls built, gate closed, no particles yet.
    pub fn new(case: &Case, threads: usize) -> Result<Self, RunError> {
        let (mut sim, walls, materials) = case_simulation_by_component(case, threads)?;
        let outlet = outlet_geometry(case);
        let (strip, field) = match &case.geometry {
            Geometry::Slab(g) => {
                let bins = OutletBins::with_width(&outlet, case.measure.x_bin_width)?;
                let mut strip = StripConfig::new(outlet, bins);
                strip.strip_height = case.measure.strip_height;
                let d = outlet.particle_diameter;
                let grid = FieldGrid::new(
                    -0.5 * g.width,
                    0.5 * g.width,
                    -3.0 * d,
                    (2.0 * g.width).min(g.height),
                    d,
                )?;
                (
                    Some(StripProbe::new(strip)?),
                    Some(VelocityFieldProbe::new(
                        grid,
                        Kernel::Box,
                        case.measure.rate_bin_width,
                    )?),
                )
            }
            Geometry::Cylinder(_)
            | Geometry::Cuboid(_)
            | Geometry::Mesh(_)
            | Geometry::Heap(_)
            | Geometry::DrawDown(_) => (None, None),
        };
        let radial = match outlet.shape {
            // The heap's disc is no orifice: nothing flows through it.
            OutletShape::Circle { .. } if case.geometry.heap().is_some() => None,
            OutletShape::Circle { centre_y } => Some(RadialPackingProbe::new(
                RadialBins::with_width(
                    [outlet.centre, centre_y],
                    outlet.half_width,
                    case.measure.x_bin_width,
                )?,
                outlet.outlet_height,
                case.measure.strip_height,
            )?),
            OutletShape::Slot | OutletShape::Rectangle { .. } => None,
        };
        let pressure = pressure_recorder(case, &walls, &mut sim)?;
        let wall_forces =
            WallForceRecorder::new(&sim, &walls, case.measure.rate_bin_width, case.time_step);
        let state = RunRecord {
            walls,
            materials,
            rng: Xoshiro256PlusPlus::seed_from_u64(case.seed),
            components: Vec::new(),
            pending: None,
            phase: Phase::Fill {
                inserted: 0,
                last_insert: 0.0,
            },
            crossing: CrossingProbe::new(outlet)?,
            strip,
            field,
            radial,
            bulk: None,
            settled_kinetic_energy: f64::NAN,
            settled: false,
            next_frame: 0.0,
            next_check: 0.0,
            discharged_mass: 0.0,
            fill_mass: 0.0,
            wall_forces,
            remaining: RemainingRecorder::new(case.measure.rate_bin_width),
            orientation: case
                .particles
                .has_shapes()
                .then(OrientationRecorder::default),
            opening: OpeningRecord::default(),
            pressure,
            fields: FieldsRecorder::new(case)?,
            unclog: case.protocol.unclog.map(|_| UnclogRecord::default()),
        };
        Ok(Self {
            case: case.clone(),
            sim,
            state,
            keep_bed: false,
            bed: None,
            rebuilt: Vec::new(),
        })
    }

    /// Resumes from a checkpointed state.
    pub fn resume(case: &Case, state: RunState, threads: usize) -> Result<Self, RunError> {
        let RunState {
            sim,
            record: mut state,
        } = state;
        let sim = Simulation::from_state(sim, threads)?;
        if state.fields.is_none() {
            state.fields = FieldsRecorder::new(case)?;
        }
        if state.unclog.is_none() {
            state.unclog = case.protocol.unclog.map(|_| UnclogRecord::default());
        }
        let mut run = Self {
            case: case.clone(),
            sim,
            state,
            keep_bed: false,
            bed: None,
            rebuilt: Vec::new(),
        };
        // The pulse's force is no part of the engine's state: a run stopped during a pulse
        // sets it again.
        if let Phase::Pulse { .. } = run.state.phase {
            run.set_pulse(true)?;
        }
        Ok(run)
    }

    /// A run of `case` from a bed: the state `bed` that a run kept at the end of its
    /// settling ([`CaseRun::take_bed`]), its gate opened at once. `case` may differ from the
    /// bed's case only where `run::check_bed` allows (the caller checks).
    ///
    /// The engine state is the bed's, bit for bit: positions, velocities, spins, forces, the
    /// neighbour lists and every contact history, the time and the step count. The walls
    /// become `case`'s, handle by handle ([`adopt_walls`]): equal walls stay with their
    /// contacts' histories; a wall that differs (the bottom plates or flat bottom and the
    /// gate, for another outlet) is replaced, and its contacts start without history. The
    /// probes, the wall-load windows and N(t) are `case`'s, started at the bed's time, and the
    /// settled bulk fraction is measured again in `case`'s container. With the bed's own
    /// case nothing changes, and the discharge is the saving run's, bit for bit.
    pub fn from_bed(case: &Case, bed: RunState, threads: usize) -> Result<Self, RunError> {
        let mut run = Self::new(case, 1)?;
        let RunState { sim, record: bed } = bed;
        let mut sim = Simulation::from_state(sim, threads)?;
        let changed = adopt_walls(&mut sim, &run.sim)?;
        run.rebuilt = changed
            .iter()
            .map(|&id| {
                run.state
                    .walls
                    .name_of(id)
                    .or_else(|| bed.walls.name_of(id))
                    .unwrap_or_else(|| "unnamed".to_string())
            })
            .collect();
        run.sim = sim;
        // Zones and bands on the walls the run now holds; the settled bed's pressure window
        // belongs to the run that saved the bed.
        run.state.pressure = pressure_recorder(case, &run.state.walls, &mut run.sim)?;
        let state = &mut run.state;
        state.materials = bed.materials;
        state.components = bed.components;
        state.pending = bed.pending;
        state.rng = bed.rng;
        state.settled = bed.settled;
        state.settled_kinetic_energy = bed.settled_kinetic_energy;
        state.fill_mass = bed.fill_mass;
        state.wall_forces = WallForceRecorder::new(
            &run.sim,
            &state.walls,
            case.measure.rate_bin_width,
            case.time_step,
        );
        run.state.bulk = run.measure_bulk().ok();
        run.open_gate()?;
        Ok(run)
    }

    /// A run of `case` from a checked packing: its particles placed at rest, in file order,
    /// in the container with its gate closed; the run then settles (the first check after
    /// `MIN_SETTLE_AFTER_FILL`, as after a fill) and goes on as usual.
    pub fn from_packing(case: &Case, packing: &Packing, threads: usize) -> Result<Self, RunError> {
        let mut run = Self::new(case, threads)?;
        // A mixture's particles each get their component's material, and the run records
        // their components by tag, as the fill does.
        let components = packing.components();
        run.sim.reserve_particles(packing.particles().len());
        for (k, p) in packing.particles().iter().enumerate() {
            let component = components.get(k).copied();
            let material = run.state.materials[component.map_or(0, usize::from)];
            let tag = run
                .sim
                .add_particle(ParticleInit::at_rest(p.position, p.radius, material))?;
            if let Some(component) = component {
                run.state.record_component(tag, component);
            }
        }
        let t = run.sim.time();
        run.state.next_check = t + MIN_SETTLE_AFTER_FILL;
        run.state.phase = Phase::Settle { since: t };
        Ok(run)
    }

    /// The walls that a run from a bed rebuilt for its case, by name (`gate`,
    /// `plate_left`, `bottom`, …); empty when the bed's walls were all kept.
    pub fn rebuilt_walls(&self) -> &[String] {
        &self.rebuilt
    }

    /// Keeps the run's state at the end of the settling, before the gate opens, for
    /// [`CaseRun::take_bed`].
    pub fn keep_bed(&mut self) {
        self.keep_bed = true;
    }

    /// The state kept at the end of the settling (gate closed), once, after the chunk in
    /// which the gate opened; `None` before, after it was taken, or without
    /// [`CaseRun::keep_bed`].
    pub fn take_bed(&mut self) -> Option<RunState> {
        self.bed.take().map(|b| *b)
    }

    /// The state to checkpoint, borrowed from the engine and the protocol.
    pub(crate) fn checkpoint(&self) -> RunStateView<'_> {
        RunStateView {
            sim: self.sim.state(),
            record: &self.state,
        }
    }

    /// The simulation (read-only).
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    /// Switches the engine's per-phase timing on (from zero) or off
    /// ([`Simulation::time_phases`]); the run is bit-identical either way.
    pub fn time_phases(&mut self, on: bool) {
        self.sim.time_phases(on);
    }

    /// The component of each particle inserted so far, by tag (an index into
    /// `particles.components`); empty for a case of one component.
    pub fn particle_components(&self) -> &[u8] {
        &self.state.components
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        self.state.phase
    }

    /// Advances by one protocol chunk (at most `CHECK_INTERVAL` of simulated time).
    ///
    /// On a thread pool the whole chunk runs inside it ([`Simulation::pool_handle`]): the
    /// discharge measures the outlet every few steps, and each of those short runs would
    /// otherwise hand its steps over to the pool and back.
    pub fn advance(&mut self) -> Result<(), RunError> {
        let pool = self.sim.pool_handle();
        match pool {
            Some(pool) => pool.install(|| self.advance_here()),
            None => self.advance_here(),
        }
    }

    /// [`CaseRun::advance`] on the calling thread.
    fn advance_here(&mut self) -> Result<(), RunError> {
        let dt = self.case.time_step;
        let chunk = (CHECK_INTERVAL / dt).round().max(1.0) as u64;
        match self.state.phase {
            Phase::Fill {
                inserted,
                last_insert,
            } => self.fill(inserted, last_insert, chunk),
            Phase::Settle { since } => self.settle(since, chunk, false),
            Phase::Slip { until_step } => self.slip(until_step, chunk),
            Phase::Resettle { since } => self.settle(since, chunk, true),
            Phase::Discharge {
                opened,
                last_crossing,
            } => self.discharge(opened, last_crossing, chunk),
            Phase::Pulse { opened, until_step } => self.pulse(opened, until_step, chunk),
            Phase::Lift { opened } => self.lift(opened, chunk),
            Phase::Rest { opened, since } => self.rest(opened, since, chunk),
            Phase::Done { .. } => Ok(()),
        }
    }

    fn fill(&mut self, inserted: usize, last_insert: f64, chunk: u64) -> Result<(), RunError> {
        let total = self.case.particles.count;
        // Room for the whole fill at once (nothing once it is there).
        self.sim.reserve_particles(total.saturating_sub(inserted));
        let t = self.sim.time();
        let mut inserted = inserted;
        let mut last = last_insert;
        if t >= self.state.next_check {
            self.state.next_check = t + INSERT_INTERVAL;
            let n = self.insert_batch(total - inserted)?;
            if n > 0 {
                inserted += n;
                last = t;
            } else if t - last > 1.0 {
                return Err(RunError::CannotFill { inserted, total });
            }
        }
        self.run_recording_loads(chunk)?;
        self.state.phase = if inserted >= total {
            self.state.next_check = self.sim.time() + MIN_SETTLE_AFTER_FILL;
            Phase::Settle {
                since: self.sim.time(),
            }
        } else {
            Phase::Fill {
                inserted,
                last_insert: last,
            }
        };
        Ok(())
    }

    /// Inserts one batch of up to `want` particles into the insertion band by random
    /// sequential addition, as the fill does every `INSERT_INTERVAL`; returns how many it
    /// placed. The cost estimate inserts the first batch the same way to learn how many
    /// particles the band holds.
    pub(crate) fn insert_batch(&mut self, want: usize) -> Result<usize, RunError> {
        let band = fill_band(&self.case);
        let draws = ParticleDraws::new(&self.case.particles, &self.state.materials);
        let v0 = DVec3::new(0.0, 0.0, -self.case.protocol.fill_speed);
        let attempts = 20 * want + 1000;
        let state = &mut self.state;
        let placed = match &self.case.geometry {
            Geometry::Slab(g) => insert_slab_batch(
                &mut self.sim,
                g,
                &mut state.rng,
                want,
                &draws,
                &mut state.pending,
                band,
                v0,
                attempts,
            )?,
            Geometry::Cylinder(_)
            | Geometry::Cuboid(_)
            | Geometry::Mesh(_)
            | Geometry::Heap(_)
            | Geometry::DrawDown(_) => insert_silo_batch(
                &mut self.sim,
                fill_region(&self.case.geometry),
                &mut state.rng,
                want,
                &draws,
                &mut state.pending,
                band,
                v0,
                attempts,
            )?,
        };
        if draws.is_mixture() {
            for &(tag, component) in &placed {
                // A clump's members have the tags after its first's.
                let members = self.case.particles.components[component as usize]
                    .shape
                    .as_ref()
                    .map_or(1, |s| s.members() as u64);
                for member in tag..tag + members {
                    state.record_component(member, component);
                }
            }
        }
        Ok(placed.len())
    }

    fn mean_kinetic_energy(&self) -> f64 {
        let e = self.sim.energy();
        // Per grain: a clump's energy is its body's, counted once.
        (e.translational + e.rotational) / self.sim.watched().body_count().max(1) as f64
    }

    /// Takes `chunk` steps and reads the walls' loads after them (`wall_forces`).
    fn run_recording_loads(&mut self, chunk: u64) -> Result<(), RunError> {
        self.sim.run(chunk)?;
        let step = self.sim.steps();
        self.state.wall_forces.observe(&self.sim.watched(), step);
        Ok(())
    }

    /// Settling checks until the bed is calm, then the opening; `slipped` says whether the
    /// walls have slipped past the bed already. A calm bed that is still to slip
    /// (`protocol.wall_slip` > 0) starts the slip instead of the opening.
    fn settle(&mut self, since: f64, chunk: u64, slipped: bool) -> Result<(), RunError> {
        self.run_recording_loads(chunk)?;
        let t = self.sim.time();
        if t < self.state.next_check {
            return Ok(());
        }
        if let Some(p) = &mut self.state.pressure {
            p.observe_settling(&mut self.sim);
        }
        let ke = self.mean_kinetic_energy();
        let calm = ke < self.case.protocol.settle_kinetic_energy;
        if calm || t - since > self.case.protocol.max_settle_time {
            if !slipped && self.case.protocol.wall_slip > 0.0 {
                return self.start_slip();
            }
            self.state.settled = calm;
            self.state.settled_kinetic_energy = ke;
            self.state.bulk = self.measure_bulk().ok();
            // Grains, a clump's mass once (for spheres the particles' masses in order).
            self.state.fill_mass = self.sim.watched().bodies(|_| true).masses.iter().sum();
            if self.keep_bed {
                // The bed: everything a run from it needs to discharge as this one will.
                self.bed = Some(Box::new(self.checkpoint().to_owned()));
            }
            match &self.case.geometry {
                Geometry::Heap(g) => self.start_lift(g.lift_speed)?,
                _ => self.open_gate()?,
            }
        }
        Ok(())
    }

    /// The side walls that slip past the settled bed: a silo's cylinder, a box's four sides
    /// (the bottom, a cone or plates and the gate stay, so the bed keeps resting on them).
    fn slipping_walls(&self) -> Vec<dem::WallId> {
        match &self.state.walls {
            ContainerWalls::Silo(w) => vec![w.cylinder],
            ContainerWalls::Box(w) => w.sides.to_vec(),
            // The case's checks refuse a slip for these kinds.
            ContainerWalls::Slab(_) | ContainerWalls::Mesh(_) | ContainerWalls::Heap(_) => {
                Vec::new()
            }
        }
    }

    /// Starts raising the side walls by `protocol.wall_slip` at `WALL_SLIP_SPEED`, in a whole
    /// number of steps (the speed adjusted to it, so that the walls stop exactly at the slip).
    fn start_slip(&mut self) -> Result<(), RunError> {
        let dt = self.case.time_step;
        let slip = self.case.protocol.wall_slip;
        let steps = (slip / (WALL_SLIP_SPEED * dt)).ceil().max(1.0) as u64;
        let speed = slip / (steps as f64 * dt);
        for id in self.slipping_walls() {
            self.sim.set_wall_motion(
                id,
                dem::WallMotion {
                    velocity: DVec3::new(0.0, 0.0, speed),
                    displaced: true,
                    ..Default::default()
                },
            )?;
        }
        self.state.phase = Phase::Slip {
            until_step: self.sim.steps() + steps,
        };
        Ok(())
    }

    /// Raises the side walls until `until_step`, then stops them and settles again.
    fn slip(&mut self, until_step: u64, chunk: u64) -> Result<(), RunError> {
        let left = until_step.saturating_sub(self.sim.steps());
        self.run_recording_loads(chunk.min(left).max(1))?;
        if self.sim.steps() >= until_step {
            for id in self.slipping_walls() {
                self.sim.set_wall_motion(id, dem::WallMotion::default())?;
            }
            // The loads booked while the walls moved belong to no window of the settled bed.
            // The cylinder's bands moved up with it by the slip (at most half a diameter);
            // its zones keep the heights they were given at the start.
            if let Some(p) = &mut self.state.pressure {
                p.observe_settling(&mut self.sim);
            }
            let t = self.sim.time();
            self.state.next_check = t + MIN_SETTLE_AFTER_FILL;
            self.state.phase = Phase::Resettle { since: t };
        }
        Ok(())
    }

    /// Removes the gate at the current time and starts the discharge.
    fn open_gate(&mut self) -> Result<(), RunError> {
        let t = self.sim.time();
        if let Some(fields) = &mut self.state.fields {
            // The bed at rest, its gate still under it.
            fields.observe_settled(&self.sim.watched())?;
        }
        if let Some(o) = &mut self.state.orientation {
            o.record_bed(&self.sim.watched());
        }
        self.state.opening.record(&self.sim.watched());
        self.sim.remove_wall(self.state.walls.gate())?;
        self.state.remaining.open(t);
        if let Some(p) = &mut self.state.pressure {
            p.open(&mut self.sim, t);
        }
        // The gate's last window ends with it; the next ones lie on the W(t) bins.
        self.state.wall_forces.close(self.sim.steps());
        self.state.next_frame = t;
        self.state.next_check = t;
        self.state.phase = Phase::Discharge {
            opened: t,
            last_crossing: t,
        };
        Ok(())
    }

    /// Starts lifting the heap test's cylinder at `speed` [m/s]: the test's opening.
    fn start_lift(&mut self, speed: f64) -> Result<(), RunError> {
        let t = self.sim.time();
        self.sim.set_wall_motion(
            self.state.walls.gate(),
            dem::WallMotion {
                velocity: DVec3::new(0.0, 0.0, speed),
                displaced: true,
                ..Default::default()
            },
        )?;
        self.state.remaining.open(t);
        // The settled fill's last window of wall loads ends with the lift's start.
        self.state.wall_forces.close(self.sim.steps());
        self.state.next_frame = t;
        self.state.next_check = t;
        self.state.phase = Phase::Lift { opened: t };
        Ok(())
    }

    /// Takes `chunk` steps of the heap test, records N(t) on the plate and removes the grains
    /// that fell past its edge (as those below an outlet, `protocol.deletion_depth` below it).
    fn heap_chunk(&mut self, chunk: u64) -> Result<(), RunError> {
        self.run_recording_loads(chunk)?;
        self.state.remaining.observe(&self.sim.watched());
        let depth = self.case.protocol.deletion_depth;
        let removed = self.sim.remove_bodies(|x| x.z < -depth);
        self.state.discharged_mass += removed.iter().map(|r| r.mass).sum::<f64>();
        Ok(())
    }

    /// Lifts the cylinder until its lower edge, risen by v (t − t₀), is above every grain
    /// within a diameter of its wall; then removes it and lets the heap come to rest.
    fn lift(&mut self, opened: f64, chunk: u64) -> Result<(), RunError> {
        self.heap_chunk(chunk)?;
        let Geometry::Heap(test) = &self.case.geometry else {
            unreachable!("only the heap test lifts")
        };
        let t = self.sim.time();
        let edge = test.lift_speed * (t - opened);
        let p = self.sim.particles();
        let reach = test.cylinder_radius + self.case.particles.max_diameter();
        let clear = (0..p.len()).all(|k| {
            let x = p.positions()[k];
            x.x.hypot(x.y) > reach || x.z + p.radii()[k] < edge
        });
        if clear {
            self.sim.remove_wall(self.state.walls.gate())?;
            self.state.next_check = t + MIN_SETTLE_AFTER_FILL;
            self.state.phase = Phase::Rest { opened, since: t };
        } else if t - opened > self.case.protocol.time_limit {
            self.state.phase = Phase::Done {
                reason: StopReason::TimeLimit,
                opened,
            };
        }
        Ok(())
    }

    /// Lets the heap flow until its mean kinetic energy per particle falls below
    /// `protocol.settle_kinetic_energy` (checked from `MIN_SETTLE_AFTER_FILL` after the
    /// cylinder's removal), or the time limit.
    fn rest(&mut self, opened: f64, since: f64, chunk: u64) -> Result<(), RunError> {
        self.heap_chunk(chunk)?;
        let t = self.sim.time();
        let calm = t >= self.state.next_check
            && self.mean_kinetic_energy() < self.case.protocol.settle_kinetic_energy;
        let reason = if calm || self.sim.particles().is_empty() {
            Some(StopReason::AtRest)
        } else if t - opened > self.case.protocol.time_limit {
            Some(StopReason::TimeLimit)
        } else {
            None
        };
        self.state.phase = match reason {
            Some(reason) => Phase::Done { reason, opened },
            None => Phase::Rest { opened, since },
        };
        Ok(())
    }

    fn measure_bulk(&self) -> Result<BulkMeasurement, RunError> {
        // Grains: a clump as the sphere of its volume at its centre of mass (its members
        // overlap, so their volumes would count the overlaps twice).
        let bodies = self.sim.watched().bodies(|_| true);
        let p = &bodies;
        let centres = || -> Vec<[f64; 3]> { p.positions.iter().map(|x| x.to_array()).collect() };
        let d = self.case.particles.mean_diameter();
        let g = match &self.case.geometry {
            Geometry::Slab(g) => g,
            Geometry::Cylinder(silo) => {
                return Ok(silo_bulk(&centres(), &p.radii, silo.radius, d, |h| {
                    silo.volume_below(h)
                })?);
            }
            Geometry::Heap(test) => {
                return Ok(silo_bulk(
                    &centres(),
                    &p.radii,
                    test.cylinder_radius,
                    d,
                    |h| test.volume_below(h),
                )?);
            }
            Geometry::Cuboid(silo)
            | Geometry::DrawDown(case::DrawDownGeometry { container: silo }) => {
                // Columns over the floor plan less a diameter along every wall, as for the
                // cylinder (docs/physics.md §7.6).
                let (hw, hb) = (0.5 * silo.width - d, 0.5 * silo.depth - d);
                return Ok(bed_bulk(
                    &centres(),
                    &p.radii,
                    |x, y| x.abs() < hw && y.abs() < hb,
                    d,
                    |h| silo.volume_below(h),
                )?);
            }
            // STL walls have no known inside volume: no bulk fraction (NaN in the summary).
            Geometry::Mesh(_) => {
                return Err(RunError::NotMeasured(
                    "the bulk fraction of STL walls, whose inside volume is not known",
                ))
            }
        };
        let outlet = outlet_geometry(&self.case);
        let outline = ContainerOutline::hopper(g.width, &outlet, g.hopper_angle(), g.height)?;
        let (x0, x1) = outline.x_range();
        let probe = BulkProbe::new(
            outline,
            g.thickness,
            (x0, x1),
            0.0,
            outlet.particle_diameter,
        )?;
        let frame = OwnedSnapshot::of(&self.sim.watched(), |_| true);
        Ok(probe.measure(&frame.view(self.sim.time(), self.case.particles.density()))?)
    }

    fn discharge(&mut self, opened: f64, last_crossing: f64, chunk: u64) -> Result<(), RunError> {
        let last_crossing = self.discharge_chunk(last_crossing, chunk)?;
        let t = self.sim.time();
        let target = self.case.protocol.stop_fraction * self.state.fill_mass;
        let unclogging = self.case.protocol.unclog.is_some();
        let reason = if self.sim.particles().is_empty() {
            Some(StopReason::Empty)
        } else if self.case.protocol.stop_fraction < 1.0
            && !unclogging
            && self.state.discharged_mass >= target
            && self.steady_window_complete(opened)
        {
            Some(StopReason::Fraction)
        } else if t - last_crossing > self.case.protocol.clog_timeout {
            let landing = self
                .state
                .unclog
                .as_ref()
                .map_or(f64::NEG_INFINITY, |r| r.landing);
            match self.orifice_blocked() {
                true if unclogging => self.at_clog(opened)?,
                true => Some(StopReason::Clogged),
                // Grains a pulse lifted are still in the air: wait for them.
                false if t < landing => None,
                false => Some(StopReason::Drained),
            }
        } else if t - opened > self.case.protocol.time_limit {
            Some(StopReason::TimeLimit)
        } else {
            None
        };
        match reason {
            Some(reason) => self.state.phase = Phase::Done { reason, opened },
            // A pulse started at the clog sets its own phase.
            None if matches!(self.state.phase, Phase::Pulse { .. }) => {}
            None => {
                self.state.phase = Phase::Discharge {
                    opened,
                    last_crossing,
                }
            }
        }
        Ok(())
    }

    /// At a clog of a run that breaks its arches: records it with its arch, and starts a
    /// pulse (returning `None`) or says why the run stops.
    fn at_clog(&mut self, opened: f64) -> Result<Option<StopReason>, RunError> {
        let Some(spec) = self.case.protocol.unclog else {
            return Ok(Some(StopReason::Clogged));
        };
        let outlet = outlet_geometry(&self.case);
        let frame = OwnedSnapshot::of(&self.sim.watched(), |_| true);
        let arch = measure::find_arch(
            &frame.view(self.sim.time(), self.case.particles.density()),
            &outlet,
        );
        let crossings = self.state.crossing.record().events.len();
        let t = self.sim.time();
        let record = self.state.unclog.get_or_insert_with(UnclogRecord::default);
        match record.declare(&spec, t, crossings, arch.as_ref()) {
            AtClog::Stop(reason) => Ok(Some(reason)),
            AtClog::Pulse => {
                let steps = (spec.duration / self.case.time_step).round().max(1.0) as u64;
                self.set_pulse(true)?;
                self.state.phase = Phase::Pulse {
                    opened,
                    until_step: self.sim.steps() + steps,
                };
                Ok(None)
            }
        }
    }

    /// The force ratio of the pulse now given ([`UnclogRecord::current_ratio`]) [-].
    fn pulse_ratio(&self) -> f64 {
        match (&self.case.protocol.unclog, &self.state.unclog) {
            (Some(spec), Some(record)) => record.current_ratio(spec),
            (Some(spec), None) => spec.force_ratio,
            (None, _) => 0.0,
        }
    }

    /// Sets the pulse's force on the grains over the orifice (`on`) or removes it.
    fn set_pulse(&mut self, on: bool) -> Result<(), RunError> {
        let ratio = self.pulse_ratio();
        let force = match (on, &self.case.protocol.unclog) {
            (true, Some(spec)) => Some(pulse_force(
                &self.case,
                spec,
                ratio,
                &outlet_geometry(&self.case),
            )),
            _ => None,
        };
        self.sim.set_region_force(force)?;
        Ok(())
    }

    /// A chunk of the pulse (at most up to its last step), observed as the discharge is;
    /// at its end the force is removed and the discharge goes on, the clog timeout counted
    /// from there. A clear opening means drained only once the grains the pulse lifted are
    /// back ([`UnclogRecord::landing`]).
    fn pulse(&mut self, opened: f64, until_step: u64, chunk: u64) -> Result<(), RunError> {
        let left = until_step.saturating_sub(self.sim.steps()).max(1);
        self.discharge_chunk(f64::NEG_INFINITY, chunk.min(left))?;
        let t = self.sim.time();
        if self.sim.particles().is_empty() {
            self.set_pulse(false)?;
            self.state.phase = Phase::Done {
                reason: StopReason::Empty,
                opened,
            };
        } else if self.sim.steps() >= until_step {
            let flight = match &self.case.protocol.unclog {
                Some(spec) => 2.0 * (self.pulse_ratio() - 1.0) * spec.duration,
                None => 0.0,
            };
            if let Some(record) = self.state.unclog.as_mut() {
                record.landing = t + flight;
            }
            self.set_pulse(false)?;
            self.state.phase = Phase::Discharge {
                opened,
                last_crossing: t,
            };
        }
        Ok(())
    }

    /// Takes `chunk` steps of the discharge, observing the outlet and the probes, and
    /// deletes the particles well below the outlet; returns the time of the last crossing
    /// (`last_crossing` if none came).
    fn discharge_chunk(&mut self, last_crossing: f64, chunk: u64) -> Result<f64, RunError> {
        let every = self.case.measure.crossing_check_interval.max(1) as u64;
        let d = outlet_geometry(&self.case).particle_diameter;
        let density = self.case.particles.density();
        // A mixture's probes see each particle's own mass (its material's density).
        let masses = self.case.particles.is_mixture();
        let band = CROSSING_BAND_DIAMETERS * d;
        let mut last_crossing = last_crossing;
        let (case, state, sim) = (&self.case, &mut self.state, &mut self.sim);
        // The outlet is looked at every `every` steps and after the chunk's last; the engine
        // leaves each look's second half kick to the next step's pass, and the view gives
        // full-step velocities. The walls' loads are read at the same looks.
        let first = sim.steps();
        let mut taken = 0u64;
        sim.run_watched(chunk, every, |seen: &Watched<'_>| -> Result<(), RunError> {
            taken = (taken + every).min(chunk);
            state.wall_forces.observe(seen, first + taken);
            let t = seen.time();
            let frame = OwnedSnapshot::of_with_masses(seen, |x| x.z.abs() < band, masses);
            let found = state.crossing.observe(&frame.view(t, density))?;
            if found > 0 {
                last_crossing = t;
                if let Some(o) = &mut state.orientation {
                    let events = &state.crossing.record().events;
                    o.record_crossings(&events[events.len() - found..], seen);
                }
            }
            state.remaining.observe(seen);
            if let Some(fields) = &mut state.fields {
                fields.observe(seen)?;
            }
            if t >= state.next_frame {
                state.next_frame += case.measure.frame_interval;
                if let Some(probe) = &mut state.strip {
                    let strip = OwnedSnapshot::of_with_masses(seen, |x| x.z.abs() < d, masses);
                    probe.observe(&strip.view(t, density))?;
                }
                if let Some(probe) = &mut state.field {
                    let all = OwnedSnapshot::of_with_masses(seen, |_| true, masses);
                    probe.observe(&all.view(t, density))?;
                }
                if let Some(probe) = &mut state.radial {
                    // Spheres reaching into the slab |z| ≤ h/2 have |z| < h/2 + r_max.
                    let reach = 0.5 * case.measure.strip_height + case.particles.max_diameter();
                    let slab = OwnedSnapshot::of_with_masses(seen, |x| x.z.abs() < reach, masses);
                    probe.observe(&slab.view(t, density))?;
                }
            }
            Ok(())
        })?;
        if let Some(p) = &mut self.state.pressure {
            p.observe_discharge(&mut self.sim);
        }
        // Delete particles well below the outlet (docs/physics.md §5: about 5 d).
        let depth = self.case.protocol.deletion_depth;
        let removed = self.sim.remove_bodies(|x| x.z < -depth);
        self.state.discharged_mass += removed.iter().map(|r| r.mass).sum::<f64>();
        Ok(last_crossing)
    }
}

impl CaseRun {
    /// The discharge rate W(t) from the outlet crossings so far: whole bins of
    /// `measure.rate_bin_width` from the gate's opening at `opened` [s]. `finish` measures on
    /// this series, and the stop rule below reads it, so the two agree to the last bit.
    pub(crate) fn discharge_series(&self, opened: f64) -> Result<RateSeries, AnalysisError> {
        let record = self.state.crossing.record();
        let end = self.sim.time() - opened;
        let times: Vec<f64> = record.events.iter().map(|e| e.time - opened).collect();
        let masses: Vec<f64> = record.events.iter().map(|e| e.mass).collect();
        let bin = self.case.measure.rate_bin_width;
        RateSeries::from_events(&times, &masses, 0.0, end.max(bin), bin)
    }

    /// Whether the steady window is complete: the crossings counted in whole bins exceed
    /// `measure.steady_end_fraction` of the fill. Then `find_steady_window` takes the fill as
    /// its reference and finds some bin edge past the window's end mass, so the window, and
    /// everything measured over it, are those of any longer run. The mass deleted below the
    /// outlet (what `protocol.stop_fraction` counts) lags the crossings by the fall, but at
    /// a large outlet a bin of crossings can still be open when it reaches the same
    /// fraction: a run stopped then would measure a window cut short.
    fn steady_window_complete(&self, opened: f64) -> bool {
        let Ok(series) = self.discharge_series(opened) else {
            return false;
        };
        // The same products as `find_steady_window`'s reference test and end mass.
        let end_mass = self.case.measure.steady_end_fraction * self.state.fill_mass;
        let (_, cumulative) = series.cumulative_mass();
        series.total_mass() >= end_mass && cumulative.last().is_some_and(|&m| m > end_mass)
    }

    /// Whether some particle sits over the orifice, within D + d above it: a stopped flow
    /// with such a particle is an arch (a clog); without one, only the stagnant zones beside
    /// the orifice are left. A particle resting on a plate has its centre over the plate, so
    /// centres more than r/2 inside the opening must be held up by neighbours.
    fn orifice_blocked(&self) -> bool {
        let o = outlet_geometry(&self.case);
        let p = self.sim.watched().bodies(|_| true);
        (0..p.len()).any(|k| {
            let x = p.positions[k];
            let r = p.radii[k];
            let inside = |reach: f64| reach < o.half_width - 0.5 * r;
            let over = match o.shape {
                OutletShape::Slot => inside((x.x - o.centre).abs()),
                OutletShape::Circle { centre_y } => inside((x.x - o.centre).hypot(x.y - centre_y)),
                // Inside both spans: the x span as for a slot, the y span likewise.
                OutletShape::Rectangle {
                    centre_y,
                    half_depth,
                } => {
                    inside((x.x - o.centre).abs()) && (x.y - centre_y).abs() < half_depth - 0.5 * r
                }
            };
            over && x.z > 0.0 && x.z < 2.0 * o.half_width + o.particle_diameter
        })
    }
}

/// Particle data copied out of the engine for the probes (they take plain arrays).
pub struct OwnedSnapshot {
    ids: Vec<u64>,
    positions: Vec<[f64; 3]>,
    velocities: Vec<[f64; 3]>,
    radii: Vec<f64>,
    /// Each particle's mass [kg], when the probes need it (a mixture of materials).
    masses: Option<Vec<f64>>,
}

impl OwnedSnapshot {
    /// The particles whose position satisfies `keep`.
    pub fn of(p: &Watched<'_>, keep: impl Fn(DVec3) -> bool) -> Self {
        Self::of_with_masses(p, keep, false)
    }

    /// The particles whose position satisfies `keep`, with each one's mass from the engine
    /// when `masses` (particles of several materials, whose masses no one density gives).
    ///
    /// Where there are clumps, the probes see grains ([`Watched::bodies`]): each clump once,
    /// at its centre of mass, with its velocity, its whole mass and the radius of the sphere
    /// of its volume, so that a grain crosses the outlet, is counted and weighed once
    /// whatever its shape (docs/physics.md §11.8).
    pub fn of_with_masses(p: &Watched<'_>, keep: impl Fn(DVec3) -> bool, masses: bool) -> Self {
        if !p.clumps().is_empty() {
            let b = p.bodies(keep);
            return OwnedSnapshot {
                ids: b.tags,
                positions: b.positions.iter().map(|x| x.to_array()).collect(),
                velocities: b.velocities.iter().map(|x| x.to_array()).collect(),
                radii: b.radii,
                masses: Some(b.masses),
            };
        }
        let mut f = OwnedSnapshot {
            ids: Vec::new(),
            positions: Vec::new(),
            velocities: Vec::new(),
            radii: Vec::new(),
            masses: masses.then(Vec::new),
        };
        for k in 0..p.len() {
            let x = p.positions()[k];
            if keep(x) {
                if let Some(masses) = &mut f.masses {
                    masses.push(p.masses()[k]);
                }
                f.ids.push(p.tags()[k]);
                f.positions.push(x.to_array());
                f.velocities.push(p.velocity(k).to_array());
                f.radii.push(p.radii()[k]);
            }
        }
        f
    }

    /// A probe view at time `time` [s] for particle density `density` [kg/m³] (used where
    /// the frame holds no masses of its own).
    pub fn view(&self, time: f64, density: f64) -> Snapshot<'_> {
        Snapshot {
            time,
            ids: &self.ids,
            positions: &self.positions,
            velocities: &self.velocities,
            radii: &self.radii,
            density,
            masses: self.masses.as_deref(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_borrowed_state_serialises_as_the_owned_one_and_reads_back_to_it() {
        // A running case keeps no copy of the engine's state: its checkpoints serialise a
        // view of the live simulation and the record. Those bytes must be the ones of the
        // owned `RunState` that a resume reads, or resumed runs would not continue bit for
        // bit. Mid-fill, particles and contacts present.
        let text = include_str!("../tests/data/tiny.toml");
        let case = case::parse_case(text, "tiny.toml", &[]).expect("the tiny case is valid");
        let mut run = CaseRun::new(&case, 1).expect("builds");
        while run.simulation().particles().len() < 100 {
            run.advance().expect("fills");
        }
        let viewed = postcard::to_allocvec(&run.checkpoint()).expect("serialises");
        let owned = run.checkpoint().to_owned();
        assert_eq!(postcard::to_allocvec(&owned).expect("serialises"), viewed);
        let read: RunState = postcard::from_bytes(&viewed).expect("reads back");
        assert_eq!(postcard::to_allocvec(&read).expect("serialises"), viewed);
        let resumed = Simulation::from_state(read.sim, 1).expect("resumes");
        assert_eq!(
            resumed.particles().len(),
            run.simulation().particles().len()
        );
    }
}

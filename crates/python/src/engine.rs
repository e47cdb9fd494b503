//! `Simulation`: the engine of a case, stepped from Python, its state read as numpy arrays.
//!
//! The simulation starts as a run does, for every container kind (slab, cylinder, box,
//! mesh): `run::case_simulation_by_component`, the function a run builds its
//! engine with, gives the container's walls with the gate closed and the material of each
//! mixture component, but no particles; the caller adds them. A simulation may also start
//! from a bed a run saved (`from_bed`), its settled state as the run kept it. Arrays are
//! read-only copies (numpy arrays over bytes), so no Python object ever points into the
//! engine's storage while it steps.

use std::collections::HashSet;
use std::path::PathBuf;

use dem::clump::ClumpShape;
use dem::{
    DQuat, DVec3, DemError, Interaction, MaterialId, ParticleInit, Wall, WallId, WallMaterial,
};
use pyo3::exceptions::{PyKeyError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use run::read_bed;
use run::{case_simulation, case_simulation_by_component, ContainerWalls};

use crate::case::Case;
use crate::errors::{case_error, RunError};
use crate::run::{checked_threads, panic_text};

/// Steps taken between two looks at signals (Ctrl-C) during `step(n)`: each `run` ends
/// with every kick done, exactly as single steps do, so the split changes no bit.
const STEPS_PER_SLICE: u64 = 2000;

/// Most steps one `step(n)` call accepts; a larger count is almost surely a mistake (at the
/// paper's Δt it is 2500 s of simulated time).
const MAX_STEPS: i64 = 1_000_000_000;

/// How the container's walls meet the particles, which walls added from Python copy: the
/// wall material, the wall's own interaction and the one with each particle material that
/// differs from it (a case with a `[materials]` table sets one per pair).
#[derive(Clone)]
struct WallTemplate {
    material: WallMaterial,
    interaction: Interaction,
    per_material: Vec<(MaterialId, Interaction)>,
}

/// The DEM engine of a case, stepped from Python. `Simulation.from_case(case)` builds the
/// container of any kind (slab, cylinder, box, mesh; mixtures included) as a run does, gate
/// closed and no particles yet; `Simulation.from_bed(path)` starts from a bed a run saved.
/// Particles are added and read as numpy arrays (read-only copies), and `walls` names the
/// container's walls (docs/python.md, "The engine").
#[pyclass(module = "hopperflow._native", name = "Simulation")]
pub struct Simulation {
    sim: dem::Simulation,
    walls: ContainerWalls,
    /// The engine material of each component of `particles.components`, in order.
    materials: Vec<MaterialId>,
    /// The component of each particle, by tag, for a mixture (empty for one component), as
    /// a run records them.
    components: Vec<u8>,
    wall_template: WallTemplate,
    case: case::Case,
}

fn engine_error(e: &DemError) -> PyErr {
    RunError::new_err(format!("simulation: {e}"))
}

fn vec3(name: &str, v: [f64; 3]) -> PyResult<DVec3> {
    let v = DVec3::from_array(v);
    if !v.is_finite() {
        return Err(PyValueError::new_err(format!(
            "{name} = [{}, {}, {}]: every component must be finite",
            v.x, v.y, v.z
        )));
    }
    Ok(v)
}

/// A read-only numpy array of `data` (native-endian `dtype`), shaped (len / cols, cols), or
/// 1-D when `cols` is 0.
fn array<'py>(
    py: Python<'py>,
    bytes: Vec<u8>,
    dtype: &str,
    cols: usize,
) -> PyResult<Bound<'py, PyAny>> {
    let numpy = py.import("numpy")?;
    let data = PyBytes::new(py, &bytes);
    let flat = numpy.getattr("frombuffer")?.call1((data, dtype))?;
    if cols == 0 {
        Ok(flat)
    } else {
        flat.call_method1("reshape", ((-1i64, cols as i64),))
    }
}

/// Refuses an argument `name` of `len` `items` beside `n` positions: one `each` per particle.
fn one_each(name: &str, items: &str, len: usize, n: usize, each: &str) -> PyResult<()> {
    if len == n {
        return Ok(());
    }
    Err(PyValueError::new_err(format!(
        "{name} has {len} {items} but positions has {n}: one {each} per particle"
    )))
}

fn f64_bytes(values: impl Iterator<Item = f64>) -> Vec<u8> {
    values.flat_map(f64::to_ne_bytes).collect()
}

fn vec3_bytes(values: &[DVec3]) -> Vec<u8> {
    f64_bytes(values.iter().flat_map(|v| v.to_array()))
}

/// The template of the walls of `walls` in `sim`, read from the first of them present (the
/// gate, closed, is present in a fresh container and in a bed); the case's `[wall]`
/// coefficients on a rigid wall if none is.
fn wall_template(
    sim: &dem::Simulation,
    walls: &ContainerWalls,
    materials: &[MaterialId],
    case: &case::Case,
) -> WallTemplate {
    let present = walls
        .all()
        .into_iter()
        .find_map(|id| sim.wall(id).map(|w| (id, w)));
    let Some((id, wall)) = present else {
        let i = &case.wall.interaction;
        return WallTemplate {
            material: WallMaterial::Rigid,
            interaction: Interaction {
                friction: i.friction,
                rolling_friction: i.rolling_friction,
                restitution: i.restitution,
                cohesion: i.cohesion,
            },
            per_material: Vec::new(),
        };
    };
    let mut per_material: Vec<(MaterialId, Interaction)> = Vec::new();
    for &m in materials {
        let pair = sim
            .wall_interaction(id, m)
            .filter(|i| *i != wall.interaction);
        if let Some(i) = pair.filter(|_| per_material.iter().all(|(k, _)| *k != m)) {
            per_material.push((m, i));
        }
    }
    WallTemplate {
        material: wall.material,
        interaction: wall.interaction,
        per_material,
    }
}

impl Simulation {
    fn build(case: &case::Case, threads: usize) -> PyResult<Self> {
        let (sim, walls, materials) =
            case_simulation_by_component(case, threads).map_err(|e| engine_error(&e))?;
        Ok(Self::assemble(sim, walls, materials, Vec::new(), case))
    }

    fn assemble(
        sim: dem::Simulation,
        walls: ContainerWalls,
        materials: Vec<MaterialId>,
        components: Vec<u8>,
        case: &case::Case,
    ) -> Self {
        let wall_template = wall_template(&sim, &walls, &materials, case);
        Self {
            sim,
            walls,
            materials,
            components,
            wall_template,
            case: case.clone(),
        }
    }

    /// The component index `component`, checked against the case's components.
    fn component(&self, component: i64) -> PyResult<u8> {
        let n = self.materials.len();
        match usize::try_from(component) {
            Ok(k) if k < n => Ok(k as u8),
            _ => Err(PyValueError::new_err(format!(
                "component = {component}: must be an integer in 0..{n} (an index into \
                 `component_names`: {})",
                self.component_names().join(", ")
            ))),
        }
    }

    fn component_names(&self) -> Vec<String> {
        self.case
            .particles
            .components
            .iter()
            .map(|c| c.name.clone())
            .collect()
    }

    fn init(
        &self,
        position: [f64; 3],
        radius: f64,
        velocity: Option<[f64; 3]>,
        angular_velocity: Option<[f64; 3]>,
        component: u8,
    ) -> PyResult<ParticleInit> {
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "radius = {radius}: must be positive and finite [m]"
            )));
        }
        let material = self.materials[usize::from(component)];
        let mut init = ParticleInit::at_rest(vec3("position", position)?, radius, material);
        if let Some(v) = velocity {
            init.velocity = vec3("velocity", v)?;
        }
        if let Some(w) = angular_velocity {
            init.angular_velocity = vec3("angular_velocity", w)?;
        }
        Ok(init)
    }

    /// Adds a checked particle of mixture component `component`; returns its id.
    fn add(&mut self, init: ParticleInit, component: u8) -> PyResult<u64> {
        let tag = self.sim.add_particle(init).map_err(|e| engine_error(&e))?;
        // Recorded as a run records them: only a mixture's particles, by tag.
        if self.materials.len() > 1 {
            let k = tag as usize;
            if self.components.len() <= k {
                self.components.resize(k + 1, u8::MAX);
            }
            self.components[k] = component;
        }
        Ok(tag)
    }

    /// Adds `wall` with the container walls' material and interactions; returns its id.
    fn add_wall(&mut self, wall: Wall) -> PyResult<u32> {
        let id = self.sim.add_wall(wall).map_err(|e| engine_error(&e))?;
        for &(m, interaction) in &self.wall_template.per_material {
            self.sim
                .set_wall_interaction(id, m, interaction)
                .map_err(|e| engine_error(&e))?;
        }
        Ok(id.0)
    }

    /// Takes `n` steps with the GIL released, looking for Ctrl-C between slices.
    fn advance(&mut self, py: Python<'_>, n: u64) -> PyResult<()> {
        let mut left = n;
        while left > 0 {
            let m = left.min(STEPS_PER_SLICE);
            let sim = &mut self.sim;
            let outcome =
                py.detach(|| std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| sim.run(m))));
            match outcome {
                Ok(Ok(())) => {}
                Ok(Err(e)) => return Err(engine_error(&e)),
                Err(payload) => {
                    return Err(PyRuntimeError::new_err(format!(
                        "internal error in the engine: {}",
                        panic_text(payload.as_ref())
                    )))
                }
            }
            left -= m;
            py.check_signals()?;
        }
        Ok(())
    }

    fn wall_id(&self, id: i64) -> PyResult<WallId> {
        let valid = u32::try_from(id)
            .ok()
            .map(WallId)
            .filter(|w| self.sim.wall(*w).is_some());
        valid.ok_or_else(|| {
            PyKeyError::new_err(format!(
                "wall {id}: no such wall (removed, or never added); `walls` lists the container's"
            ))
        })
    }
}

#[pymethods]
impl Simulation {
    /// The engine of `case`, of any kind (slab, cylinder, box, mesh), as a run builds it:
    /// the container's walls (gate closed) and the material of each mixture component, no
    /// particles yet.
    #[staticmethod]
    #[pyo3(signature = (case, threads = 1))]
    fn from_case(case: PyRef<'_, Case>, threads: i64) -> PyResult<Self> {
        let threads = checked_threads(threads)?;
        Self::build(&case.case, threads)
    }

    /// The settled bed a run saved in folder `path` (`save_bed=`, `--save-bed`): its case,
    /// the engine's state at the end of the settling (gate closed) and each particle's
    /// component, bit for bit as the run kept them.
    #[staticmethod]
    #[pyo3(signature = (path, threads = 1))]
    fn from_bed(py: Python<'_>, path: PathBuf, threads: i64) -> PyResult<Self> {
        let threads = checked_threads(threads)?;
        let bed = read_bed(&path).map_err(|e| PyValueError::new_err(e.to_string()))?;
        let name = format!("{} (its case)", bed.path().display());
        let case = case::parse_case(bed.case_text(), &name, &[]).map_err(|e| case_error(py, &e))?;
        let state = bed.state();
        let sim = dem::Simulation::from_state(state.simulation().clone(), threads)
            .map_err(|e| engine_error(&e))?;
        Ok(Self::assemble(
            sim,
            state.walls().clone(),
            state.component_materials().to_vec(),
            state.particle_components().to_vec(),
            &case,
        ))
    }

    /// Takes `n` steps of Δt (the case's `time_step`). Ctrl-C stops between slices of
    /// steps, leaving the simulation at a whole step.
    #[pyo3(signature = (n = 1))]
    fn step(&mut self, py: Python<'_>, n: i64) -> PyResult<()> {
        if !(0..=MAX_STEPS).contains(&n) {
            return Err(PyValueError::new_err(format!(
                "n = {n}: must be an integer in 0..={MAX_STEPS} (steps to take)"
            )));
        }
        self.advance(py, n as u64)
    }

    /// Adds one particle, of the material of mixture component `component` (an index into
    /// `component_names`; 0, the case's one material, for a case of one component); returns
    /// its id.
    #[pyo3(signature = (position, radius, velocity = None, angular_velocity = None, component = 0))]
    fn add_particle(
        &mut self,
        position: [f64; 3],
        radius: f64,
        velocity: Option<[f64; 3]>,
        angular_velocity: Option<[f64; 3]>,
        component: i64,
    ) -> PyResult<u64> {
        let component = self.component(component)?;
        let init = self.init(position, radius, velocity, angular_velocity, component)?;
        self.add(init, component)
    }

    /// Adds particles at `positions` (N×3) with `radii` (N), optional `velocities` (N×3)
    /// and optional mixture `components` (N indices into `component_names`; all 0 when
    /// left out); returns their ids. Nothing is added when any of them is refused.
    #[pyo3(signature = (positions, radii, velocities = None, components = None))]
    fn add_particles(
        &mut self,
        positions: Vec<[f64; 3]>,
        radii: Vec<f64>,
        velocities: Option<Vec<[f64; 3]>>,
        components: Option<Vec<i64>>,
    ) -> PyResult<Vec<u64>> {
        let n = positions.len();
        one_each("radii", "entries", radii.len(), n, "radius")?;
        if let Some(v) = &velocities {
            one_each("velocities", "rows", v.len(), n, "velocity")?;
        }
        if let Some(c) = &components {
            one_each("components", "entries", c.len(), n, "component")?;
        }
        let inits = positions
            .iter()
            .zip(&radii)
            .enumerate()
            .map(|(k, (p, r))| {
                let v = velocities.as_ref().map(|v| v[k]);
                let component = components.as_ref().map_or(0, |c| c[k]);
                self.component(component)
                    .and_then(|c| Ok((self.init(*p, *r, v, None, c)?, c)))
                    .map_err(|e| PyValueError::new_err(format!("particle {k}: {e}")))
            })
            .collect::<PyResult<Vec<_>>>()?;
        inits
            .into_iter()
            .map(|(init, component)| self.add(init, component))
            .collect()
    }

    /// Removes the particles with these ids; returns how many were removed (ids that are
    /// not present are ignored: a particle may have left already).
    fn remove_particles(&mut self, ids: Vec<u64>) -> usize {
        let ids: HashSet<u64> = ids.into_iter().collect();
        self.sim
            .remove_particles(|k, p| ids.contains(&p.tags()[k]))
            .len()
    }

    /// Removes every grain whose centre is below height `z` [m] (a clump by its centre of
    /// mass, whole); returns their ids (a clump's is its first member's).
    fn remove_below(&mut self, z: f64) -> PyResult<Vec<u64>> {
        if z.is_nan() {
            return Err(PyValueError::new_err("z = nan: must be a number [m]"));
        }
        Ok(self
            .sim
            .remove_bodies(|x| x.z < z)
            .iter()
            .map(|r| r.tag)
            .collect())
    }

    /// Adds a rigid clump (docs/physics.md §11) of mixture component `component`'s material:
    /// `members` are its spheres as (x, y, z, r) rows [m] in the clump's own frame; the body
    /// is turned by the unit quaternion `orientation` (x, y, z, w; default none) and its
    /// centre of mass put at `position` [m], moving at `velocity` [m/s] and spinning at
    /// `angular_velocity` [rad/s]. Returns the clump's id, its first member's (members have
    /// the ids after it).
    #[pyo3(signature = (members, position, orientation = None, velocity = None, angular_velocity = None, component = 0))]
    fn add_clump(
        &mut self,
        members: Vec<[f64; 4]>,
        position: [f64; 3],
        orientation: Option<[f64; 4]>,
        velocity: Option<[f64; 3]>,
        angular_velocity: Option<[f64; 3]>,
        component: i64,
    ) -> PyResult<u64> {
        let component = self.component(component)?;
        let shape = ClumpShape::new(
            members
                .iter()
                .map(|m| (DVec3::new(m[0], m[1], m[2]), m[3]))
                .collect(),
        )
        .map_err(|e| PyValueError::new_err(format!("members: {e}")))?;
        let q = match orientation {
            Some([x, y, z, w]) => {
                let q = DQuat::from_xyzw(x, y, z, w);
                if !(q.is_finite() && (q.length() - 1.0).abs() < 1e-6) {
                    return Err(PyValueError::new_err(format!(
                        "orientation = [{x}, {y}, {z}, {w}]: must be a unit quaternion \
                         (x, y, z, w), |q| = 1 to 1e-6"
                    )));
                }
                q
            }
            None => DQuat::IDENTITY,
        };
        let x = vec3("position", position)?;
        let v = vec3("velocity", velocity.unwrap_or([0.0; 3]))?;
        let w = vec3("angular_velocity", angular_velocity.unwrap_or([0.0; 3]))?;
        let material = self.materials[usize::from(component)];
        let c = self
            .sim
            .add_clump(&shape, material, (x, q), (v, w))
            .map_err(|e| engine_error(&e))?;
        let first = self.sim.clumps().first_tags()[c];
        if self.materials.len() > 1 {
            let last = (first + members.len() as u64) as usize;
            if self.components.len() < last {
                self.components.resize(last, u8::MAX);
            }
            self.components[first as usize..last].fill(component);
        }
        Ok(first)
    }

    /// The rigid clumps, as a dict of read-only arrays, M rows: `ids` (each clump's first
    /// member's id), `positions` (centres of mass, M×3 [m]), `velocities` (M×3 [m/s]),
    /// `angular_velocities` (M×3 [rad/s]), `orientations` (unit quaternions x, y, z, w, M×4,
    /// from the principal frame to the world), `axes` (the long axis, the principal axis of
    /// least inertia, M×3, unit), `masses` (M [kg]) and `members` (M, spheres each).
    #[getter]
    fn clumps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = self.sim.clumps();
        let out = PyDict::new(py);
        let ids: Vec<u8> = c
            .first_tags()
            .iter()
            .flat_map(|t| t.to_ne_bytes())
            .collect();
        out.set_item("ids", array(py, ids, "uint64", 0)?)?;
        out.set_item(
            "positions",
            array(py, vec3_bytes(c.positions()), "float64", 3)?,
        )?;
        out.set_item(
            "velocities",
            array(py, vec3_bytes(c.velocities()), "float64", 3)?,
        )?;
        let omegas: Vec<DVec3> = (0..c.len()).map(|k| c.angular_velocity(k)).collect();
        out.set_item(
            "angular_velocities",
            array(py, vec3_bytes(&omegas), "float64", 3)?,
        )?;
        let quats = f64_bytes(c.orientations().iter().flat_map(|q| q.to_array()));
        out.set_item("orientations", array(py, quats, "float64", 4)?)?;
        let axes: Vec<DVec3> = c.orientations().iter().map(|q| *q * DVec3::X).collect();
        out.set_item("axes", array(py, vec3_bytes(&axes), "float64", 3)?)?;
        let masses = f64_bytes((0..c.len()).map(|k| c.body(k).mass));
        out.set_item("masses", array(py, masses, "float64", 0)?)?;
        let members: Vec<u8> = (0..c.len())
            .flat_map(|k| (c.body(k).members.len() as u64).to_ne_bytes())
            .collect();
        out.set_item("members", array(py, members, "uint64", 0)?)?;
        Ok(out)
    }

    /// Each particle's clump, N: an index into the rows of `clumps`, or −1 for a free
    /// sphere.
    #[getter]
    fn clump_indices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let bytes = self
            .sim
            .particles()
            .clump_indices()
            .iter()
            .flat_map(|&c| {
                match c {
                    dem::NO_CLUMP => -1i64,
                    c => i64::from(c),
                }
                .to_ne_bytes()
            })
            .collect();
        array(py, bytes, "int64", 0)
    }

    /// Adds an infinite plane wall of the container walls' material; returns its id.
    fn add_plane(&mut self, point: [f64; 3], normal: [f64; 3]) -> PyResult<u32> {
        let WallTemplate {
            material,
            interaction,
            ..
        } = self.wall_template;
        let wall = Wall::plane(
            vec3("point", point)?,
            vec3("normal", normal)?,
            material,
            interaction,
        )
        .map_err(|e| PyValueError::new_err(format!("plane: {e}")))?;
        self.add_wall(wall)
    }

    /// Adds a convex planar polygon wall (vertices in order) of the container walls'
    /// material; returns its id.
    fn add_polygon(&mut self, vertices: Vec<[f64; 3]>) -> PyResult<u32> {
        let WallTemplate {
            material,
            interaction,
            ..
        } = self.wall_template;
        let vertices = vertices
            .into_iter()
            .map(|v| vec3("vertex", v))
            .collect::<PyResult<Vec<_>>>()?;
        let wall = Wall::polygon(vertices, material, interaction)
            .map_err(|e| PyValueError::new_err(format!("polygon: {e}")))?;
        self.add_wall(wall)
    }

    /// Removes a wall (the gate, say).
    fn remove_wall(&mut self, id: i64) -> PyResult<()> {
        let id = self.wall_id(id)?;
        self.sim.remove_wall(id).map_err(|e| engine_error(&e))?;
        Ok(())
    }

    /// Opens the outlet: removes the gate.
    fn open_gate(&mut self) -> PyResult<()> {
        self.remove_wall(i64::from(self.walls.gate().0))
    }

    /// Moves a wall rigidly by `offset` [m].
    fn translate_wall(&mut self, id: i64, offset: [f64; 3]) -> PyResult<()> {
        let id = self.wall_id(id)?;
        let offset = vec3("offset", offset)?;
        self.sim
            .translate_wall(id, offset)
            .map_err(|e| engine_error(&e))
    }

    /// Sets the velocity a wall shows to the contact law [m/s] (it does not move it).
    fn set_wall_velocity(&mut self, id: i64, velocity: [f64; 3]) -> PyResult<()> {
        let id = self.wall_id(id)?;
        let velocity = vec3("velocity", velocity)?;
        self.sim
            .set_wall_velocity(id, velocity)
            .map_err(|e| engine_error(&e))
    }

    /// The load the particles exerted on wall `id` in the last step: the force [N] and the
    /// torque about the origin [N m], each a read-only float64 array of 3. Zero before the
    /// first step, and always for a wall that does not sum its load (a slab's front and
    /// back faces).
    fn wall_load<'py>(
        &self,
        py: Python<'py>,
        id: i64,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let id = self.wall_id(id)?;
        let load = self.sim.wall_load(id).map_err(|e| engine_error(&e))?;
        Ok((
            array(py, vec3_bytes(&[load.force]), "float64", 0)?,
            array(py, vec3_bytes(&[load.torque]), "float64", 0)?,
        ))
    }

    /// The container's walls by name, the names of `wall_forces.csv`, while present (walls
    /// added from Python are not among them): a slab's left, right, front, back,
    /// plate_left and plate_right (where the outlet leaves room for them); a cylinder's
    /// cylinder and hopper (a cone) or bottom (flat); a box's left, right, front, back,
    /// its plates (plate_left, plate_right, plate_front, plate_back) or bottom; a mesh's
    /// STL walls by their names; and every kind's gate until it is removed.
    #[getter]
    fn walls<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for id in self.walls.all() {
            if self.sim.wall(id).is_none() {
                continue;
            }
            if let Some(name) = self.walls.name_of(id) {
                d.set_item(name, id.0)?;
            }
        }
        Ok(d)
    }

    /// The container's kind: "slab", "cylinder", "box" or "mesh".
    #[getter]
    fn kind(&self) -> &'static str {
        self.case.geometry.kind()
    }

    /// The names of the case's particle components, in order (one name for a case of one
    /// component): what the indices of `components` and of `add_particle(component=)` mean.
    #[getter(component_names)]
    fn get_component_names(&self) -> Vec<String> {
        self.component_names()
    }

    /// Simulated time [s].
    #[getter]
    fn time(&self) -> f64 {
        self.sim.time()
    }

    /// Steps taken.
    #[getter]
    fn steps(&self) -> u64 {
        self.sim.steps()
    }

    /// The time step Δt [s].
    #[getter]
    fn time_step(&self) -> f64 {
        self.case.time_step
    }

    fn __len__(&self) -> usize {
        self.sim.particles().len()
    }

    /// Centre positions, N×3 [m].
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(
            py,
            vec3_bytes(self.sim.particles().positions()),
            "float64",
            3,
        )
    }

    /// Centre velocities at the full step, N×3 [m/s].
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(
            py,
            vec3_bytes(self.sim.particles().velocities()),
            "float64",
            3,
        )
    }

    /// Angular velocities, N×3 [rad/s].
    #[getter]
    fn angular_velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(
            py,
            vec3_bytes(self.sim.particles().angular_velocities()),
            "float64",
            3,
        )
    }

    /// Total force on each particle at the last step, N×3 [N].
    #[getter]
    fn forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(py, vec3_bytes(self.sim.particles().forces()), "float64", 3)
    }

    /// Radii, N [m].
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(
            py,
            f64_bytes(self.sim.particles().radii().iter().copied()),
            "float64",
            0,
        )
    }

    /// Masses, N [kg].
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        array(
            py,
            f64_bytes(self.sim.particles().masses().iter().copied()),
            "float64",
            0,
        )
    }

    /// Particle ids (stable while a particle lives; never reused), N.
    #[getter]
    fn ids<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let bytes = self
            .sim
            .particles()
            .tags()
            .iter()
            .flat_map(|t| t.to_ne_bytes())
            .collect();
        array(py, bytes, "uint64", 0)
    }

    /// Each particle's mixture component, N: an index into `component_names` (all 0 for a
    /// case of one component).
    #[getter]
    fn components<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        // Only a mixture records components, for every particle it adds; the others are 0.
        let component = |tag: &u64| self.components.get(*tag as usize).copied();
        let tags = self.sim.particles().tags();
        array(
            py,
            tags.iter().map(|t| component(t).unwrap_or(0)).collect(),
            "uint8",
            0,
        )
    }

    /// Material index of each particle, N.
    #[getter]
    fn materials<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let bytes = self
            .sim
            .particles()
            .materials()
            .iter()
            .flat_map(|m| m.to_ne_bytes())
            .collect();
        array(py, bytes, "uint16", 0)
    }

    /// Kinetic, rotational, gravitational and elastic energy [J].
    fn energy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let e = self.sim.energy();
        let d = PyDict::new(py);
        d.set_item("translational", e.translational)?;
        d.set_item("rotational", e.rotational)?;
        d.set_item("gravitational", e.gravitational)?;
        d.set_item("elastic", e.elastic)?;
        d.set_item("total", e.total())?;
        Ok(d)
    }

    /// Contacts at the last step: particle-particle and particle-wall.
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = self.sim.contacts();
        let d = PyDict::new(py);
        d.set_item("particle_particle", c.particle_particle)?;
        d.set_item("particle_wall", c.particle_wall)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        format!(
            "Simulation(t={} s, steps={}, particles={})",
            self.sim.time(),
            self.sim.steps(),
            self.sim.particles().len()
        )
    }
}

/// The reference for the bit-identity test of `Simulation`: the same set-up stepped by the
/// engine in one uninterrupted `run`, without the Python class in between. Returns the
/// positions, velocities and angular velocities as read-only N×3 arrays. A test hook, so
/// its Python name is private (`hopperflow._testing` gives it to the tests).
#[pyfunction]
#[pyo3(name = "_engine_reference", signature = (case, positions, radii, velocities, steps, threads = 1, open_gate = true))]
#[allow(clippy::too_many_arguments)]
pub fn engine_reference<'py>(
    py: Python<'py>,
    case: PyRef<'_, Case>,
    positions: Vec<[f64; 3]>,
    radii: Vec<f64>,
    velocities: Vec<[f64; 3]>,
    steps: u64,
    threads: i64,
    open_gate: bool,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let threads = checked_threads(threads)?;
    let case = case.case.clone();
    let result = py.detach(move || -> Result<dem::Simulation, String> {
        let (mut sim, walls, material) =
            case_simulation(&case, threads).map_err(|e| e.to_string())?;
        for ((p, r), v) in positions.iter().zip(&radii).zip(&velocities) {
            let mut init = ParticleInit::at_rest(DVec3::from_array(*p), *r, material);
            init.velocity = DVec3::from_array(*v);
            sim.add_particle(init).map_err(|e| e.to_string())?;
        }
        if open_gate {
            sim.remove_wall(walls.gate()).map_err(|e| e.to_string())?;
        }
        sim.run(steps).map_err(|e| e.to_string())?;
        Ok(sim)
    });
    let sim = result.map_err(|e| RunError::new_err(format!("simulation: {e}")))?;
    let p = sim.particles();
    Ok((
        array(py, vec3_bytes(p.positions()), "float64", 3)?,
        array(py, vec3_bytes(p.velocities()), "float64", 3)?,
        array(py, vec3_bytes(p.angular_velocities()), "float64", 3)?,
    ))
}

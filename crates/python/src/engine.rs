//! `Simulation`: the engine of a case, stepped from Python, its state read as numpy arrays.
//!
//! The simulation starts as a run does: the case's hopper walls with the gate closed and
//! the case's particle material, but no particles; the caller adds them. Arrays are read-only
//! copies (numpy arrays over bytes), so no Python object ever points into the engine's
//! storage while it steps.

use std::collections::HashSet;

use dem::{DVec3, DemError, MaterialId, ParticleInit, Wall, WallId};
use pyo3::exceptions::{PyKeyError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};
use study::hopper::{hopper_simulation, HopperWalls};

use crate::case::Case;
use crate::errors::RunError;
use crate::run::{checked_threads, panic_text};

/// Steps taken between two looks at signals (Ctrl-C) during `step(n)`: each `run` ends
/// with every kick done, exactly as single steps do, so the split changes no bit.
const STEPS_PER_SLICE: u64 = 2000;

/// Most steps one `step(n)` call accepts; a larger count is almost surely a mistake (at the
/// paper's Δt it is 2500 s of simulated time).
const MAX_STEPS: i64 = 1_000_000_000;

/// The engine of a case (see `hopperflow.Simulation`).
#[pyclass(module = "hopperflow._native", name = "Simulation")]
pub struct Simulation {
    sim: dem::Simulation,
    walls: HopperWalls,
    material: MaterialId,
    case: study::config::Case,
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

fn f64_bytes(values: impl Iterator<Item = f64>) -> Vec<u8> {
    values.flat_map(f64::to_ne_bytes).collect()
}

fn vec3_bytes(values: &[DVec3]) -> Vec<u8> {
    f64_bytes(values.iter().flat_map(|v| v.to_array()))
}

impl Simulation {
    fn build(case: &study::config::Case, threads: usize) -> PyResult<Self> {
        let (sim, walls, material) =
            hopper_simulation(case, threads).map_err(|e| engine_error(&e))?;
        Ok(Self {
            sim,
            walls,
            material,
            case: case.clone(),
        })
    }

    fn init(
        &self,
        position: [f64; 3],
        radius: f64,
        velocity: Option<[f64; 3]>,
        angular_velocity: Option<[f64; 3]>,
    ) -> PyResult<ParticleInit> {
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "radius = {radius}: must be positive and finite [m]"
            )));
        }
        let mut init = ParticleInit::at_rest(vec3("position", position)?, radius, self.material);
        if let Some(v) = velocity {
            init.velocity = vec3("velocity", v)?;
        }
        if let Some(w) = angular_velocity {
            init.angular_velocity = vec3("angular_velocity", w)?;
        }
        Ok(init)
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
                "wall {id}: no such wall (removed, or never added); `walls` lists the hopper's"
            ))
        })
    }
}

#[pymethods]
impl Simulation {
    /// The engine of `case`: its walls (gate closed) and material, no particles yet.
    #[staticmethod]
    #[pyo3(signature = (case, threads = 1))]
    fn from_case(case: PyRef<'_, Case>, threads: i64) -> PyResult<Self> {
        let threads = checked_threads(threads)?;
        Self::build(&case.case, threads)
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

    /// Adds one particle of the case's material; returns its id.
    #[pyo3(signature = (position, radius, velocity = None, angular_velocity = None))]
    fn add_particle(
        &mut self,
        position: [f64; 3],
        radius: f64,
        velocity: Option<[f64; 3]>,
        angular_velocity: Option<[f64; 3]>,
    ) -> PyResult<u64> {
        let init = self.init(position, radius, velocity, angular_velocity)?;
        self.sim.add_particle(init).map_err(|e| engine_error(&e))
    }

    /// Adds particles at `positions` (N×3) with `radii` (N) and optional `velocities`
    /// (N×3); returns their ids. Nothing is added when any of them is refused.
    #[pyo3(signature = (positions, radii, velocities = None))]
    fn add_particles(
        &mut self,
        positions: Vec<[f64; 3]>,
        radii: Vec<f64>,
        velocities: Option<Vec<[f64; 3]>>,
    ) -> PyResult<Vec<u64>> {
        if radii.len() != positions.len() {
            return Err(PyValueError::new_err(format!(
                "radii has {} entries but positions has {}: one radius per particle",
                radii.len(),
                positions.len()
            )));
        }
        if let Some(v) = &velocities {
            if v.len() != positions.len() {
                return Err(PyValueError::new_err(format!(
                    "velocities has {} rows but positions has {}: one velocity per particle",
                    v.len(),
                    positions.len()
                )));
            }
        }
        let inits = positions
            .iter()
            .zip(&radii)
            .enumerate()
            .map(|(k, (p, r))| {
                let v = velocities.as_ref().map(|v| v[k]);
                self.init(*p, *r, v, None)
                    .map_err(|e| PyValueError::new_err(format!("particle {k}: {e}")))
            })
            .collect::<PyResult<Vec<_>>>()?;
        inits
            .into_iter()
            .map(|init| self.sim.add_particle(init).map_err(|e| engine_error(&e)))
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

    /// Removes every particle whose centre is below height `z` [m]; returns their ids.
    fn remove_below(&mut self, z: f64) -> PyResult<Vec<u64>> {
        if z.is_nan() {
            return Err(PyValueError::new_err("z = nan: must be a number [m]"));
        }
        Ok(self
            .sim
            .remove_particles(|k, p| p.positions()[k].z < z)
            .iter()
            .map(|r| r.tag)
            .collect())
    }

    /// Adds an infinite plane wall of the case's wall material; returns its id.
    fn add_plane(&mut self, point: [f64; 3], normal: [f64; 3]) -> PyResult<u32> {
        let (material, interaction) = self.wall_material();
        let wall = Wall::plane(
            vec3("point", point)?,
            vec3("normal", normal)?,
            material,
            interaction,
        )
        .map_err(|e| PyValueError::new_err(format!("plane: {e}")))?;
        Ok(self.sim.add_wall(wall).map_err(|e| engine_error(&e))?.0)
    }

    /// Adds a convex planar polygon wall (vertices in order) of the case's wall material.
    fn add_polygon(&mut self, vertices: Vec<[f64; 3]>) -> PyResult<u32> {
        let (material, interaction) = self.wall_material();
        let vertices = vertices
            .into_iter()
            .map(|v| vec3("vertex", v))
            .collect::<PyResult<Vec<_>>>()?;
        let wall = Wall::polygon(vertices, material, interaction)
            .map_err(|e| PyValueError::new_err(format!("polygon: {e}")))?;
        Ok(self.sim.add_wall(wall).map_err(|e| engine_error(&e))?.0)
    }

    /// Removes a wall (the gate, say).
    fn remove_wall(&mut self, id: i64) -> PyResult<()> {
        let id = self.wall_id(id)?;
        self.sim.remove_wall(id).map_err(|e| engine_error(&e))?;
        Ok(())
    }

    /// Opens the outlet: removes the gate.
    fn open_gate(&mut self) -> PyResult<()> {
        self.remove_wall(i64::from(self.walls.gate.0))
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
    /// first step, and for the front and back faces, whose load is not summed.
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

    /// The hopper's walls by name: left, right, front, back, plate_left, plate_right (when
    /// present) and gate (while present).
    #[getter]
    fn walls<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let w = &self.walls;
        let named = [
            ("left", Some(w.sides[0])),
            ("right", Some(w.sides[1])),
            ("front", Some(w.faces[0])),
            ("back", Some(w.faces[1])),
            ("plate_left", w.plates[0]),
            ("plate_right", w.plates[1]),
            ("gate", Some(w.gate)),
        ];
        for (name, id) in named {
            if let Some(id) = id.filter(|id| self.sim.wall(*id).is_some()) {
                d.set_item(name, id.0)?;
            }
        }
        Ok(d)
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

impl Simulation {
    /// The material and interaction of the case's walls, as the hopper's walls have them.
    fn wall_material(&self) -> (dem::WallMaterial, dem::Interaction) {
        // The hopper's walls all share one material; the left side wall always exists.
        let wall = self.sim.wall(self.walls.sides[0]);
        match wall {
            Some(w) => (w.material, w.interaction),
            None => (
                dem::WallMaterial::Rigid,
                dem::Interaction {
                    friction: self.case.wall.interaction.friction,
                    rolling_friction: self.case.wall.interaction.rolling_friction,
                    restitution: self.case.wall.interaction.restitution,
                },
            ),
        }
    }
}

/// The reference for the bit-identity test of `Simulation`: the same set-up stepped by the
/// engine in one uninterrupted `run`, without the Python class in between. Returns the
/// positions, velocities and angular velocities as read-only N×3 arrays.
#[pyfunction]
#[pyo3(signature = (case, positions, radii, velocities, steps, threads = 1, open_gate = true))]
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
            hopper_simulation(&case, threads).map_err(|e| e.to_string())?;
        for ((p, r), v) in positions.iter().zip(&radii).zip(&velocities) {
            let mut init = ParticleInit::at_rest(DVec3::from_array(*p), *r, material);
            init.velocity = DVec3::from_array(*v);
            sim.add_particle(init).map_err(|e| e.to_string())?;
        }
        if open_gate {
            sim.remove_wall(walls.gate).map_err(|e| e.to_string())?;
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

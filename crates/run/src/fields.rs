//! Coarse-grained continuum fields of a run (`[output.fields]`, docs/physics.md §7.13): the
//! bed at rest when the gate opens, and the discharge averaged over its steady window, at
//! the case's kernel width and at each width of its check.
//!
//! The engine gives the contacts of a look ([`dem::Watched::contacts`], recomputed only
//! here, only when the section is given); the measure crate's [`CoarseGrainProbe`]s sum
//! them with the particles. A run without the section builds none of this: its steps, files
//! and checkpoints keep their bits.

use std::path::Path;

use case::{Case, FieldKernel, FieldsSpec, Geometry};
use dem::Watched;
use files::{
    write_csv_table, write_grid_vti, Cell, FieldsSummary, GridArray, GridFields, WidthChange,
};
use measure::{
    width_scan, CgContacts, CgField, CgGeometry, CgGrid, CgKernel, CgPairContact, CgWallContact,
    CoarseGrainProbe, TimeWindow,
};
use serde::{Deserialize, Serialize};

use super::protocol::OwnedSnapshot;
use super::RunError;

/// What the fields of a run recorded: one probe per width (the case's first, then its
/// check's), over the discharge, and one over the bed at rest at the case's width.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct FieldsRecorder {
    /// The case's width first, then `widths`.
    discharge: Vec<CoarseGrainProbe>,
    /// The one frame of the bed at rest, taken when the gate opens.
    settled: CoarseGrainProbe,
    /// Whether the settled frame was taken.
    settled_seen: bool,
    /// Time of the next discharge frame [s].
    next_frame: f64,
    /// The particles' mass in the settled frame [kg].
    settled_mass: f64,
    interval: f64,
}

impl FieldsRecorder {
    /// The recorder of `case`'s fields; `None` where it has no `[output.fields]`.
    pub(crate) fn new(case: &Case) -> Result<Option<Self>, RunError> {
        let Some(spec) = &case.fields else {
            return Ok(None);
        };
        let grid = grid(case, spec)?;
        let kernel = match spec.kernel {
            FieldKernel::Lucy => CgKernel::Lucy,
            FieldKernel::Gaussian => CgKernel::Gaussian,
        };
        let probe = |w| CoarseGrainProbe::new(grid, kernel, w, spec.window);
        let mut discharge = vec![probe(spec.width)?];
        for &w in &spec.widths {
            if w != spec.width {
                discharge.push(probe(w)?);
            }
        }
        Ok(Some(Self {
            discharge,
            settled: probe(spec.width)?,
            settled_seen: false,
            next_frame: f64::NEG_INFINITY,
            settled_mass: f64::NAN,
            interval: spec.interval,
        }))
    }

    /// Coarse-grains the bed at rest, once: the look when the gate opens.
    pub(crate) fn observe_settled(&mut self, seen: &Watched<'_>) -> Result<(), RunError> {
        if self.settled_seen {
            return Ok(());
        }
        self.settled_seen = true;
        self.settled_mass = seen.masses().iter().sum();
        let (frame, pairs, walls) = frame_of(seen);
        let contacts = CgContacts {
            pairs: &pairs,
            walls: &walls,
        };
        self.settled
            .observe(&frame.view(seen.time(), 1.0), contacts)?;
        Ok(())
    }

    /// Coarse-grains a look of the discharge, every `interval` of simulated time.
    pub(crate) fn observe(&mut self, seen: &Watched<'_>) -> Result<(), RunError> {
        let t = seen.time();
        if t < self.next_frame {
            return Ok(());
        }
        self.next_frame = if self.next_frame.is_finite() {
            self.next_frame + self.interval
        } else {
            t + self.interval
        };
        let (frame, pairs, walls) = frame_of(seen);
        let contacts = CgContacts {
            pairs: &pairs,
            walls: &walls,
        };
        let view = frame.view(t, 1.0);
        for probe in &mut self.discharge {
            probe.observe(&view, contacts)?;
        }
        Ok(())
    }

    /// Writes `fields.vti` (the discharge's steady window `window`, or all of it where
    /// there is none), `fields_settled.vti`, one `fields_w<k>.vti` per width of the check
    /// and `field_widths.csv`; returns the summary.
    pub(crate) fn write(
        &self,
        out_dir: &Path,
        window: Option<TimeWindow>,
    ) -> Result<FieldsSummary, RunError> {
        let average = |probe: &CoarseGrainProbe| {
            let record = probe.record();
            window
                .and_then(|w| record.fields(w).ok())
                .map_or_else(|| record.all_fields(), Ok)
        };
        let mut fields = Vec::new();
        for probe in &self.discharge {
            if probe.record().blocks.is_empty() {
                continue;
            }
            fields.push(average(probe)?);
        }
        if let Some(main) = fields.first() {
            write_field_vti(&out_dir.join("fields.vti"), main, "discharge")?;
        }
        for (k, f) in fields.iter().enumerate().skip(1) {
            write_field_vti(&out_dir.join(format!("fields_w{k}.vti")), f, "discharge")?;
        }
        let settled = self
            .settled_seen
            .then(|| self.settled.record().all_fields())
            .transpose()?;
        if let Some(s) = &settled {
            write_field_vti(&out_dir.join("fields_settled.vti"), s, "bed at rest")?;
        }
        let scan = if fields.len() > 1 {
            let scan = width_scan(&fields)?;
            let rows: Vec<Vec<Cell>> = scan
                .steps
                .iter()
                .map(|s| {
                    vec![
                        s.width.into(),
                        s.next_width.into(),
                        s.density_change.into(),
                        s.pressure_change.into(),
                        s.velocity_change.into(),
                    ]
                })
                .collect();
            write_csv_table(
                out_dir.join("field_widths.csv"),
                &[
                    "width",
                    "next_width",
                    "density_change",
                    "pressure_change",
                    "velocity_change",
                ],
                &rows,
            )?;
            Some(scan)
        } else {
            None
        };
        let main = self.discharge[0].record();
        Ok(FieldsSummary {
            kernel: main.kernel.name().to_string(),
            width: main.width,
            cell_size: main.grid.cell_size,
            frames: fields.first().map_or(0, |f| f.frames),
            settled_field_mass: settled.as_ref().map(CgField::mass),
            settled_particle_mass: self.settled_seen.then_some(self.settled_mass),
            widths: scan.as_ref().map_or_else(Vec::new, |s| {
                s.steps
                    .iter()
                    .map(|s| WidthChange {
                        width: s.width,
                        next_width: s.next_width,
                        density_change: s.density_change,
                        pressure_change: s.pressure_change,
                        velocity_change: s.velocity_change,
                    })
                    .collect()
            }),
            plateau_width: scan.as_ref().and_then(|s| s.plateau),
            least_change: scan.as_ref().and_then(|s| s.least_change),
        })
    }
}

/// The grid of `case`: (x, z) over a slab's or a box's width, averaged across its
/// thickness; (r, z) from a cylinder's axis to its wall; from 3 cells below the outlet
/// plane (z = 0) to a cell above the container's top.
fn grid(case: &Case, spec: &FieldsSpec) -> Result<CgGrid, RunError> {
    let h = spec.cell_size;
    let (geometry, across, height) = match &case.geometry {
        Geometry::Slab(g) => (
            CgGeometry::Slab {
                thickness: g.thickness,
            },
            (-0.5 * g.width, 0.5 * g.width),
            g.height,
        ),
        Geometry::Cuboid(g) => (
            CgGeometry::Slab { thickness: g.depth },
            (-0.5 * g.width, 0.5 * g.width),
            g.height,
        ),
        Geometry::Cylinder(g) => (
            CgGeometry::Axisymmetric { axis: [0.0, 0.0] },
            (0.0, g.radius),
            g.height,
        ),
        Geometry::Mesh(_) | Geometry::Heap(_) | Geometry::DrawDown(_) => {
            return Err(RunError::NotMeasured(
                "coarse-grained fields of this geometry, which has no (x, z) or (r, z) grid",
            ))
        }
    };
    Ok(CgGrid::new(geometry, across, (-3.0 * h, height + h), h)?)
}

/// All particles of a look, with each one's own mass, and their contacts.
fn frame_of(seen: &Watched<'_>) -> (OwnedSnapshot, Vec<CgPairContact>, Vec<CgWallContact>) {
    let frame = OwnedSnapshot::of_with_masses(seen, |_| true, true);
    let contacts = seen.contacts().unwrap_or_default();
    let pairs = contacts
        .pairs
        .iter()
        .map(|c| CgPairContact {
            i: c.i,
            j: c.j,
            force: c.force.to_array(),
        })
        .collect();
    let walls = contacts
        .walls
        .iter()
        .map(|c| CgWallContact {
            particle: c.particle,
            force: c.force.to_array(),
            point: c.point.to_array(),
        })
        .collect();
    (frame, pairs, walls)
}

/// Writes one field as a `.vti`: the grid's plane as (x, z) with y = 0, every field with its
/// unit in its name, the stress tensors with 9 components (row-major, compression
/// positive), the pressure p = tr σ/3 and the shear stress √J₂.
fn write_field_vti(path: &Path, f: &CgField, what: &str) -> Result<(), RunError> {
    let g = &f.grid;
    let basis = match g.geometry {
        CgGeometry::Slab { .. } => "x, y, z (x along the grid, y across the slab)",
        CgGeometry::Axisymmetric { .. } => "r, theta, z (the grid's x is the radius r)",
    };
    let comment = format!(
        "hopperflow coarse-grained fields, {what}: {} kernel, width {} m, {} frames. Vectors \
         and tensors in the basis {basis}; tensors row-major; stresses compression positive \
         [Pa]; pressure = tr(stress)/3. docs/physics.md 7.13",
        f.kernel.name(),
        f.width,
        f.frames
    );
    let cells = &f.cells;
    let scalar = |get: &dyn Fn(&measure::CgCell) -> f64| cells.iter().map(get).collect::<Vec<_>>();
    let density = scalar(&|c| c.density);
    let phi = scalar(&|c| c.volume_fraction);
    let pressure = scalar(&|c| c.pressure());
    let shear = scalar(&|c| c.shear_stress());
    let velocity: Vec<f64> = cells.iter().flat_map(|c| c.velocity).collect();
    let kinetic: Vec<f64> = cells.iter().flat_map(|c| c.kinetic_stress).collect();
    let contact: Vec<f64> = cells.iter().flat_map(|c| c.contact_stress).collect();
    let total: Vec<f64> = cells.iter().flat_map(|c| c.stress()).collect();
    let arrays = [
        GridArray {
            name: "density_kg_m3",
            components: 1,
            values: &density,
        },
        GridArray {
            name: "volume_fraction",
            components: 1,
            values: &phi,
        },
        GridArray {
            name: "velocity_m_s",
            components: 3,
            values: &velocity,
        },
        GridArray {
            name: "kinetic_stress_Pa",
            components: 9,
            values: &kinetic,
        },
        GridArray {
            name: "contact_stress_Pa",
            components: 9,
            values: &contact,
        },
        GridArray {
            name: "stress_Pa",
            components: 9,
            values: &total,
        },
        GridArray {
            name: "pressure_Pa",
            components: 1,
            values: &pressure,
        },
        GridArray {
            name: "shear_stress_Pa",
            components: 1,
            values: &shear,
        },
    ];
    let [x0, z0] = g.cell_centre(0, 0);
    write_grid_vti(
        path,
        &GridFields {
            origin: [x0, 0.0, z0],
            spacing: [g.cell_size; 3],
            dimensions: [g.columns, 1, g.rows],
            arrays: &arrays,
            notes: &[
                ("width_m", f.width),
                ("cell_size_m", g.cell_size),
                ("frames", f.frames as f64),
            ],
            comment: &comment,
        },
    )?;
    Ok(())
}

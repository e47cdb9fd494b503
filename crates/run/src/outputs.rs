//! What a finished run writes: flow.csv, wall_forces.csv, profiles.csv, field.csv, plots,
//! frames, VTU/PVD, and the summary (docs/physics.md §7).

use std::path::{Path, PathBuf};

use analysis::flowrate::{axisymmetric_discharge_rate, AxisymmetricFlowParameters};
use analysis::janssen::janssen_wall_pressure;
use analysis::profile::BinnedProfile;
use analysis::selfsimilar::{
    fit_collapsed_power_profile, fit_power_profile, power_profile, PROFILE_FIT_HALF_WIDTH,
};
use analysis::series::{find_steady_window, mean_rate, RateSeries, SteadyWindowOptions};

use super::composition::{composition_columns, composition_rows};
use super::protocol::{outlet_depth, outlet_geometry, CaseRun, OwnedSnapshot, Phase};
use super::remaining::REMAINING_COLUMNS;
use super::wall_forces::WALL_FORCE_COLUMNS;
use super::wall_pressure::PRESSURE_COLUMNS;
use super::RunError;
use crate::{
    cuboid_outline, cuboid_wall_polygons, cylinder_outline, cylinder_wall_polygons, heap_outline,
    heap_wall_polygons, mesh_outline, mesh_wall_polygons, slab_outline, wall_names,
};
use case::{Case, Geometry};
use files::{
    area_fraction_profile_figure, discharge_rate_figure, plot_png, plot_svg,
    velocity_profile_figure, wall_pressure_figure, write_csv_table, write_frame_png,
    write_particles_vtu, write_walls_vtu, Cell, FittedCurve, FrameParticle, FrameViewport,
    ParticleFields, Profile, PvdCollection, PvdEntry, WallSegment,
};
use files::{ArchSummary, CaseSummary, ProfileRow, RadialFit, StopReason};
use measure::{
    radial_profiles, x_profiles, CrossingRecord, OutletBins, OutletSummary, RadialBin, TimeWindow,
    XProfileBin,
};

/// The results a finished run writes beside its summary, besides the snapshot folder.
pub(crate) const RESULT_FILES: &[&str] = &[
    "flow.csv",
    "wall_forces.csv",
    "remaining.csv",
    "arch.csv",
    "avalanches.csv",
    "wall_pressure.csv",
    "crossings.csv",
    "composition.csv",
    "profiles.csv",
    "field.csv",
    "flow_rate.png",
    "flow_rate.svg",
    "velocity_profile.png",
    "area_fraction_profile.png",
    "particles.pvd",
    "heap_surface.csv",
    "shelf_surface.csv",
];
/// The folder of VTU snapshots and PNG frames inside a run directory.
pub(crate) const SNAPSHOT_DIR: &str = "snapshots";

/// Simulated time between PNG frames of the discharge [s].
const FRAME_INTERVAL: f64 = 0.1;

/// Where the snapshot series of a run stands: what a checkpoint keeps so that a resumed run
/// writes the same VTU files, PVD collection and numbered frames as an uninterrupted one.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PictureSchedule {
    /// Simulated time of the next VTU snapshot [s].
    next_vtu: f64,
    /// Simulated time of the next PNG frame [s] (NaN before the gate opens).
    next_frame: f64,
    /// Frames written so far (the next frame's number).
    frames: usize,
    /// The PVD collection's datasets so far.
    pvd: Vec<PvdEntry>,
}

/// Snapshots written while the case runs: VTU + PVD and PNG frames.
pub struct Pictures {
    enabled: bool,
    dir: PathBuf,
    pvd: PvdCollection,
    vtu_interval: f64,
    next_vtu: f64,
    next_frame: f64,
    frames: usize,
    walls: Vec<WallSegment>,
    geometry_height: f64,
    /// The x range a frame shows [m].
    x_range: (f64, f64),
    /// The vertical cut a frame of a 3D container draws: its plane y = y_c [m] and its
    /// half-thickness c, y ∈ [y_c − c, y_c + c] [m]; `None` for a slab, which is drawn whole.
    cut: Option<(f64, f64)>,
}

impl Pictures {
    /// Prepares the snapshot folders of `out_dir`.
    pub fn new(out_dir: &Path, case: &Case, enabled: bool) -> Result<Self, RunError> {
        let dir = out_dir.join(SNAPSHOT_DIR);
        if enabled {
            std::fs::create_dir_all(&dir).map_err(|source| RunError::Directory {
                path: dir.clone(),
                source,
            })?;
            let polygons: Vec<Vec<[f64; 3]>> = match &case.geometry {
                Geometry::Slab(g) => slab_outline(g)
                    .iter()
                    .map(|s| {
                        let (a, b) = (s[0], s[1]);
                        let z = g.thickness;
                        vec![
                            [a.0, 0.0, a.1],
                            [b.0, 0.0, b.1],
                            [b.0, z, b.1],
                            [a.0, z, a.1],
                        ]
                    })
                    .collect(),
                Geometry::Cylinder(g) => cylinder_wall_polygons(g),
                Geometry::Cuboid(g) => cuboid_wall_polygons(g),
                Geometry::DrawDown(g) => cuboid_wall_polygons(&g.container),
                Geometry::Heap(g) => heap_wall_polygons(g),
                Geometry::Mesh(g) => mesh_wall_polygons(g),
            };
            write_walls_vtu(dir.join("walls.vtu"), &polygons, 0.0)?;
        }
        // A cut two mean diameters thick: one layer of spheres about the plane.
        let layer = case.particles.mean_diameter();
        let (segments, x_range, cut, top) = match &case.geometry {
            Geometry::Slab(g) => (
                slab_outline(g),
                (-0.5 * g.width, 0.5 * g.width),
                None,
                g.height,
            ),
            Geometry::Cylinder(g) => (
                cylinder_outline(g),
                (-g.radius, g.radius),
                Some((0.0, layer)),
                g.height,
            ),
            Geometry::Cuboid(g) | Geometry::DrawDown(case::DrawDownGeometry { container: g }) => (
                cuboid_outline(g),
                (-0.5 * g.width, 0.5 * g.width),
                Some((0.0, layer)),
                g.height,
            ),
            Geometry::Heap(g) => (
                heap_outline(g),
                (-g.plate_radius, g.plate_radius),
                Some((0.0, layer)),
                g.height,
            ),
            // The cut through the orifice's centre; the view spans the walls' bounds.
            Geometry::Mesh(g) => {
                let (lo, hi) = g.bounds();
                (
                    mesh_outline(g),
                    (lo[0], hi[0]),
                    Some((g.outlet.centre()[1], layer)),
                    hi[2].max(g.fill_max[2]),
                )
            }
        };
        let walls = segments
            .iter()
            .map(|s| WallSegment {
                start: [s[0].0, s[0].1],
                end: [s[1].0, s[1].1],
            })
            .collect();
        Ok(Self {
            enabled,
            pvd: PvdCollection::new(out_dir.join("particles.pvd")),
            dir,
            vtu_interval: case.output.vtu_interval,
            next_vtu: 0.0,
            next_frame: f64::NAN,
            frames: 0,
            walls,
            geometry_height: top,
            x_range,
            cut,
        })
    }

    /// Where the snapshot series stands, for a checkpoint.
    pub fn schedule(&self) -> PictureSchedule {
        PictureSchedule {
            next_vtu: self.next_vtu,
            next_frame: self.next_frame,
            frames: self.frames,
            pvd: self.pvd.entries().to_vec(),
        }
    }

    /// Continues the series of a checkpointed run.
    pub fn resume(&mut self, schedule: PictureSchedule) {
        self.next_vtu = schedule.next_vtu;
        self.next_frame = schedule.next_frame;
        self.frames = schedule.frames;
        self.pvd = PvdCollection::with_entries(self.pvd.path().to_path_buf(), schedule.pvd);
    }

    /// Writes whatever snapshot is due.
    pub fn observe(&mut self, run: &CaseRun) -> Result<(), RunError> {
        if !self.enabled {
            return Ok(());
        }
        let sim = run.simulation();
        let t = sim.time();
        let p = sim.particles();
        if self.vtu_interval > 0.0 && t >= self.next_vtu {
            self.next_vtu = t + self.vtu_interval;
            let name = format!("particles_{:06}.vtu", (t * 1e4).round() as u64);
            let positions: Vec<[f64; 3]> = p.positions().iter().map(|x| x.to_array()).collect();
            let velocities: Vec<[f64; 3]> = p.velocities().iter().map(|x| x.to_array()).collect();
            let omegas: Vec<[f64; 3]> = p
                .angular_velocities()
                .iter()
                .map(|x| x.to_array())
                .collect();
            // A mixture's components, by the particles' tags, so that ParaView can colour
            // by them and the snapshot reads back as a packing of the same mixture.
            let by_tag = run.particle_components();
            let components: Option<Vec<u8>> = (!by_tag.is_empty()).then(|| {
                p.tags()
                    .iter()
                    .map(|&t| by_tag.get(t as usize).copied().unwrap_or(u8::MAX))
                    .collect()
            });
            // Each sphere's grain, where grains are clumps.
            let clumps = sim.clumps();
            let bodies: Option<Vec<u64>> = (!clumps.is_empty()).then(|| {
                p.tags()
                    .iter()
                    .zip(p.clump_indices())
                    .map(|(&tag, &c)| match c {
                        dem::NO_CLUMP => tag,
                        c => clumps.first_tags()[c as usize],
                    })
                    .collect()
            });
            let fields = ParticleFields {
                ids: p.tags(),
                positions: &positions,
                radii: p.radii(),
                velocities: &velocities,
                angular_velocities: &omegas,
                components: components.as_deref(),
                bodies: bodies.as_deref(),
            };
            write_particles_vtu(self.dir.join(&name), &fields, t)?;
            self.pvd.push(t, 0, self.dir.join(&name))?;
            self.pvd.push(t, 1, self.dir.join("walls.vtu"))?;
        }
        if let Some(opened) = run.phase().opened() {
            if self.next_frame.is_nan() {
                self.next_frame = opened;
            }
            if t >= self.next_frame {
                self.next_frame += FRAME_INTERVAL;
                let cut = self.cut;
                let particles: Vec<FrameParticle> = (0..p.len())
                    .filter(|&k| cut.is_none_or(|(y, c)| (p.positions()[k].y - y).abs() <= c))
                    .map(|k| FrameParticle {
                        x: p.positions()[k].x,
                        z: p.positions()[k].z,
                        radius: p.radii()[k],
                        speed: p.velocities()[k].length(),
                    })
                    .collect();
                let view = FrameViewport::fitted(
                    self.x_range,
                    (-0.02, self.geometry_height),
                    1200,
                    (0.0, 1.5),
                );
                let name = format!("frame_{:04}.png", self.frames);
                self.frames += 1;
                write_frame_png(
                    self.dir.join(name),
                    &view,
                    &particles,
                    &self.walls,
                    t - opened,
                )?;
            }
        }
        Ok(())
    }
}

fn or_nan(x: Option<f64>) -> f64 {
    x.unwrap_or(f64::NAN)
}

/// Columns of `crossings.csv`, SI units in the names.
pub(crate) const CROSSING_COLUMNS: [&str; 8] = [
    "time_s",
    "x_m",
    "velocity_x_m_per_s",
    "velocity_z_m_per_s",
    "radius_m",
    "mass_kg",
    "material_density_kg_per_m3",
    "id",
];

/// Writes `crossings.csv`: every downward crossing of the outlet line by a particle centre,
/// in time order (time from the start of the run, interpolated x and velocity, v_z < 0
/// downward; physics spec §7.2), with the particle's radius, mass, material (its density)
/// and identifier. The record is part of the checkpointed run state, so a resumed run
/// writes the same file.
///
/// A 3D container (every kind but the slab) adds the crossing's y as a column, `y_m`; a
/// mixture adds the name of the particle's component as the last column, `component`.
fn write_crossings(path: &Path, record: &CrossingRecord, run: &CaseRun) -> Result<(), RunError> {
    let circular = run.case.slab().is_none();
    let particles = &run.case.particles;
    let mixture = particles.is_mixture();
    let component = |id: u64| {
        run.state
            .components
            .get(id as usize)
            .and_then(|&c| particles.components.get(c as usize))
    };
    let rows: Vec<Vec<Cell>> = record
        .events
        .iter()
        .map(|e| {
            let density = match component(e.id) {
                Some(c) if mixture => c.material.density,
                _ => particles.density(),
            };
            let mut row = vec![
                e.time.into(),
                e.x.into(),
                e.velocity_x.into(),
                e.velocity_z.into(),
                e.radius.into(),
                e.mass.into(),
                density.into(),
                Cell::Text(e.id.to_string()),
            ];
            if circular {
                row.push(e.y.into());
            }
            if mixture {
                row.push(Cell::Text(
                    component(e.id).map_or("", |c| &c.name).to_string(),
                ));
            }
            row
        })
        .collect();
    let mut columns = CROSSING_COLUMNS.to_vec();
    if circular {
        columns.push("y_m");
    }
    if mixture {
        columns.push("component");
    }
    write_csv_table(path, &columns, &rows)?;
    Ok(())
}

/// The grains behind a case's coarse-grained parcels, with `discharged` [kg] of them gone;
/// `None` for a case of grains.
fn coarse_graining_summary(case: &Case, discharged: f64) -> Option<files::CoarseGrainingSummary> {
    let c = case.particles.coarse_graining.as_ref()?;
    let grain_diameter = case.particles.grain_mean_diameter();
    // A grain's mean mass: the parcels' mean mass over κ³ (the same material).
    let mean_mass = case.particles.total_mass() / case.particles.count as f64;
    let grain_mass = mean_mass / c.grains_per_parcel();
    let outlet = case.geometry.outlet_size();
    Some(files::CoarseGrainingSummary {
        factor: c.factor,
        grains_per_parcel: c.grains_per_parcel(),
        grain_diameter,
        grains: c.grain_count,
        outlet_parcels: outlet / case.particles.mean_diameter(),
        outlet_grains: outlet / grain_diameter,
        discharged_grains: discharged / grain_mass,
    })
}

/// Exponent b of φ/φ_c = (1 − x*²)^b (paper Eq. 11) fitted to one profile as the paper
/// does for a set (divided by its centre value, bins |x*| ≤ 0.9, amplitude held at 1,
/// weighted by the bins' errors when all are known); `None` when it cannot be fitted.
fn packing_exponent(rows: &[ProfileRow], value: fn(&ProfileRow) -> (f64, f64)) -> Option<f64> {
    let centres = rows.iter().map(|r| r.x_star).collect();
    let (values, errors): (Vec<f64>, Vec<f64>) = rows.iter().map(value).unzip();
    let counts = values.iter().map(|v| u64::from(v.is_finite())).collect();
    let profile = BinnedProfile::new(centres, values, counts, errors).ok()?;
    let fit = fit_collapsed_power_profile(&[profile], PROFILE_FIT_HALF_WIDTH).ok()?;
    fit.exponent.value.is_finite().then_some(fit.exponent.value)
}

/// Analyses the finished run, writes flow.csv, wall_forces.csv, profiles.csv, field.csv and
/// the plots, and returns the summary (the caller writes it last).
pub fn finish(
    run: &CaseRun,
    out_dir: &Path,
    hash: &str,
    pictures: bool,
) -> Result<CaseSummary, RunError> {
    let case = &run.case;
    let state = &run.state;
    let Phase::Done { reason, opened } = run.phase() else {
        unreachable!("finish is called once the protocol is done")
    };
    let record = state.crossing.record();
    let end = run.simulation().time() - opened;
    let series = run.discharge_series(opened)?;
    let options = SteadyWindowOptions {
        start_fraction: case.measure.steady_start_fraction,
        end_fraction: case.measure.steady_end_fraction,
        // Fractions of the fill (docs/physics.md §7: "15 % to 70 % of the particles
        // discharged"), so that `protocol.stop_fraction` cannot move the window.
        reference_mass: (state.fill_mass > 0.0).then_some(state.fill_mass),
        ..SteadyWindowOptions::default()
    };
    let window = find_steady_window(&series, &options).ok();
    let rate = window.as_ref().and_then(|w| mean_rate(&series, w).ok());

    // flow.csv: W(t) per bin and the cumulative discharged mass.
    let (_, cumulative) = series.cumulative_mass();
    let rows: Vec<Vec<Cell>> = (0..series.len())
        .map(|k| {
            vec![
                series.bin_centre(k).into(),
                series.rates[k].into(),
                cumulative.get(k + 1).copied().unwrap_or(f64::NAN).into(),
            ]
        })
        .collect();
    write_csv_table(
        out_dir.join("flow.csv"),
        &["time", "rate", "cumulative_mass"],
        &rows,
    )?;

    // wall_forces.csv: the mean load on each wall that sums it, by window (`wall_forces`).
    write_csv_table(
        out_dir.join("wall_forces.csv"),
        &WALL_FORCE_COLUMNS,
        &state.wall_forces.table(&wall_names(&case.geometry)),
    )?;

    let outlet_window = window
        .as_ref()
        .and_then(|w| TimeWindow::new(opened + w.start_time, opened + w.end_time).ok());
    let density = case.particles.density();
    let d = case.particles.mean_diameter();
    let outlet = outlet_window.and_then(|w| {
        let strip = state.strip.as_ref()?;
        OutletSummary::new(record, strip.record(), w, density).ok()
    });

    write_crossings(&out_dir.join("crossings.csv"), record, run)?;

    // residence.csv: each grain of the bed at the opening and how long it stayed.
    let residence = if state.opening.is_empty() {
        None
    } else {
        let (rows, summary) = state.opening.table(record, opened);
        write_csv_table(
            out_dir.join("residence.csv"),
            &super::residence::RESIDENCE_COLUMNS,
            &rows,
        )?;
        summary
    };

    // composition.csv: a mixture's outflow by component, on the bins of flow.csv.
    if case.particles.is_mixture() {
        let names: Vec<String> = case
            .particles
            .components
            .iter()
            .map(|c| c.name.clone())
            .collect();
        let columns = composition_columns(&names);
        let columns: Vec<&str> = columns.iter().map(String::as_str).collect();
        let rows = composition_rows(
            &record.events,
            opened,
            end,
            case.measure.rate_bin_width,
            &state.components,
            &names,
        );
        write_csv_table(out_dir.join("composition.csv"), &columns, &rows)?;
    }

    // wall_pressure.csv: a silo's wall pressure against height, settled and discharging.
    if let Some(p) = &state.pressure {
        write_csv_table(
            out_dir.join("wall_pressure.csv"),
            &PRESSURE_COLUMNS,
            &p.table(),
        )?;
    }

    // avalanches.csv: a run that breaks its arches, cut into avalanches at its clogs.
    let avalanches = match &state.unclog {
        Some(clogs) if case.protocol.unclog.is_some() => {
            let list = super::unclog::avalanches(&record.events, clogs);
            write_csv_table(
                out_dir.join("avalanches.csv"),
                &super::unclog::AVALANCHE_COLUMNS,
                &super::unclog::avalanche_rows(&list, reason),
            )?;
            let lapses = super::unclog::lapses(&record.events, clogs);
            Some(super::unclog::avalanche_summary(&list, &lapses, clogs))
        }
        _ => None,
    };

    // arch.csv: where the arch over a clogged orifice stands (the last one, for a run that
    // stopped on its count of avalanches).
    let arch = if reason == StopReason::Clogged || reason == StopReason::Avalanches {
        write_arch(&out_dir.join("arch.csv"), run)?
    } else {
        None
    };

    // fields.vti and its kin: the coarse-grained fields, where the case asks for them.
    let fields = match &state.fields {
        Some(f) => Some(f.write(out_dir, outlet_window)?),
        None => None,
    };

    // remaining.csv: N(t), the particles still above the orifice plane; for parcels also
    // the grains they stand for.
    let grains_per_parcel = case
        .particles
        .coarse_graining
        .as_ref()
        .map(case::CoarseGraining::grains_per_parcel);
    let mut remaining_columns = REMAINING_COLUMNS.to_vec();
    if grains_per_parcel.is_some() {
        remaining_columns.push("grains");
    }
    write_csv_table(
        out_dir.join("remaining.csv"),
        &remaining_columns,
        &state.remaining.table(grains_per_parcel),
    )?;

    let mut profile_rows = Vec::new();
    if let Some(o) = &outlet {
        let crossing = record.crossing_density_profile(o.window, &o.velocity.bins);
        for (k, (v, a)) in o
            .velocity
            .entries
            .iter()
            .zip(&o.area_fraction.entries)
            .enumerate()
        {
            profile_rows.push(ProfileRow {
                x_star: v.x_star,
                x: v.x,
                velocity: or_nan(v.mean_speed),
                velocity_error: or_nan(v.standard_error),
                crossings: v.count as usize,
                area_fraction: a.area_fraction,
                area_fraction_error: or_nan(a.area_fraction_standard_error),
                area_fraction_velocity: a.area_fraction_speed,
                snapshot_velocity: or_nan(a.snapshot_speed),
                crossing_area_fraction: or_nan(crossing.area_fraction[k]),
                crossing_area_fraction_error: or_nan(crossing.standard_error[k]),
            });
        }
    }
    let headers = [
        "x_star",
        "x",
        "velocity",
        "velocity_error",
        "crossings",
        "area_fraction",
        "area_fraction_error",
        "area_fraction_velocity",
        "snapshot_velocity",
        "crossing_area_fraction",
        "crossing_area_fraction_error",
    ];
    let rows: Vec<Vec<Cell>> = profile_rows
        .iter()
        .map(|r| {
            vec![
                r.x_star.into(),
                r.x.into(),
                r.velocity.into(),
                r.velocity_error.into(),
                (r.crossings as f64).into(),
                r.area_fraction.into(),
                r.area_fraction_error.into(),
                r.area_fraction_velocity.into(),
                r.snapshot_velocity.into(),
                r.crossing_area_fraction.into(),
                r.crossing_area_fraction_error.into(),
            ]
        })
        .collect();
    let mut radial_fit = None;
    let mut centre_velocity = outlet.as_ref().map_or(f64::NAN, |o| or_nan(o.centre_speed));
    // What the profile figures draw: the slot's bins, or a circle's annuli mirrored to ±r*.
    let mut plotted = profile_rows.clone();
    match (&state.radial, outlet_depth(case)) {
        // A circular orifice: the radial profiles replace the slot's x-profiles.
        (Some(packing), _) => {
            let bins = outlet_window.map(|w| radial_profiles(record, packing, w));
            let bins = bins.unwrap_or_default();
            write_radial_profiles(&out_dir.join("profiles.csv"), &bins)?;
            radial_fit = fit_radial(&bins, packing.bins().radius, density);
            plotted = mirrored(&bins);
        }
        // A slot or rectangle of a 3D container: x-profiles from the crossings alone.
        (None, Some(depth)) => {
            let bins = OutletBins::with_width(&record.geometry, case.measure.x_bin_width)?;
            let rows = outlet_window.map_or_else(Vec::new, |w| x_profiles(record, &bins, depth, w));
            write_x_profiles(&out_dir.join("profiles.csv"), &rows)?;
            if !rows.is_empty() {
                let central: Vec<f64> = bins
                    .central_bins()
                    .into_iter()
                    .map(|i| rows[i].velocity)
                    .filter(|v| v.is_finite())
                    .collect();
                if !central.is_empty() {
                    centre_velocity = central.iter().sum::<f64>() / central.len() as f64;
                }
            }
            plotted = rows.iter().map(x_profile_row).collect();
        }
        (None, None) => write_csv_table(out_dir.join("profiles.csv"), &headers, &rows)?,
    }

    // field.csv: coarse-grained velocity around the outlet over the steady window (Fig. 9).
    if let (Some(w), Some(probe)) = (outlet_window, &state.field) {
        if let Ok(field) = probe.record().field(w) {
            let rows: Vec<Vec<Cell>> = field
                .cells
                .iter()
                .map(|c| {
                    let v = c.velocity.unwrap_or([f64::NAN, f64::NAN]);
                    vec![
                        c.centre[0].into(),
                        c.centre[1].into(),
                        c.mass_density.into(),
                        v[0].into(),
                        v[1].into(),
                    ]
                })
                .collect();
            write_csv_table(
                out_dir.join("field.csv"),
                &["x", "z", "mass_density", "velocity_x", "velocity_z"],
                &rows,
            )?;
        }
    }

    if pictures {
        plots(
            out_dir,
            &series,
            window.as_ref().map(|w| (w.start_time, w.end_time)),
            rate.as_ref().map(|r| r.rate.value),
            &plotted,
        )?;
    }

    let bulk = state.bulk.as_ref();
    // A silo has no slab width, thickness or gap: NaN, written as null.
    let slab = case.slab();
    let of_slab = |f: fn(&case::SlabGeometry) -> f64| slab.map_or(f64::NAN, f);
    // Janssen's law on a silo's settled bed (docs/physics.md §7.7), or why there is none.
    let (janssen, janssen_not_fitted) = match (&state.pressure, case.geometry.cylinder()) {
        (Some(p), Some(silo)) => {
            let fit = match bulk {
                Some(b) => p.janssen(
                    silo.radius,
                    silo.cone_height(),
                    (b.bed_height, d),
                    b.volume_fraction * density,
                    case.gravity,
                ),
                None => Err("the settled bed's height and bulk density were not measured".into()),
            };
            match fit {
                Ok(fit) => (Some(fit), None),
                Err(why) => (None, Some(why)),
            }
        }
        _ => (None, None),
    };
    // The calibration tests' own measures (docs/physics.md §7.10–7.11).
    let repose = match &case.geometry {
        Geometry::Heap(test) => Some(super::pile_outputs::heap_outputs(run, test, out_dir)?),
        _ => None,
    };
    let draw_down = match &case.geometry {
        Geometry::DrawDown(test) => {
            Some(super::pile_outputs::draw_down_outputs(run, test, out_dir)?)
        }
        _ => None,
    };
    // Shaped grains: the settled bed's long axes, grain by grain.
    let orientation = match &state.orientation {
        Some(o) => {
            write_csv_table(
                out_dir.join("orientations.csv"),
                &super::orientations::ORIENTATION_COLUMNS,
                &o.bed_rows(),
            )?;
            Some(o.summary())
        }
        None => None,
    };
    if pictures {
        if let (Some(p), Some(silo), Some(b)) = (&state.pressure, case.geometry.cylinder(), bulk) {
            let zones = p.settled_cylinder(b.bed_height);
            let hydrostatic = b.volume_fraction * density * case.gravity;
            wall_pressure_plot(out_dir, &zones, janssen.as_ref(), hydrostatic, silo.radius)?;
        }
    }
    Ok(CaseSummary {
        version: env!("CARGO_PKG_VERSION").to_string(),
        seed: case.seed,
        config_hash: hash.to_string(),
        outlet_width: case.geometry.outlet_size(),
        hopper_angle_deg: case.geometry.hopper_angle_deg(),
        outlet_gap: of_slab(|g| g.outlet_gap),
        dimensionless_gap: of_slab(|g| g.dimensionless_gap()),
        width: of_slab(|g| g.width),
        thickness: of_slab(|g| g.thickness),
        particle_diameter: d,
        particle_density: density,
        particles: case.particles.count,
        discharge_rate: rate.as_ref().map_or(f64::NAN, |r| r.rate.value),
        discharge_rate_error: rate.as_ref().map_or(f64::NAN, |r| r.rate.standard_error),
        steady_window: window
            .as_ref()
            .map_or([f64::NAN; 2], |w| [w.start_time, w.end_time]),
        plateau_found: window.as_ref().is_some_and(|w| w.is_plateau),
        flux_check_rate: outlet
            .as_ref()
            .map_or(f64::NAN, |o| o.flux_from_area_velocity),
        flux_check_rate_profiles: outlet.as_ref().map_or(f64::NAN, |o| o.flux_from_profiles),
        bulk_volume_fraction: bulk.map_or(f64::NAN, |b| b.volume_fraction),
        bulk_area_fraction: bulk.map_or(f64::NAN, |b| b.area_fraction),
        bed_height: bulk.map_or(f64::NAN, |b| b.bed_height),
        centre_velocity,
        centre_area_fraction: outlet
            .as_ref()
            .map_or(f64::NAN, |o| or_nan(o.centre_area_fraction)),
        max_area_fraction: outlet
            .as_ref()
            .map_or(f64::NAN, |o| or_nan(o.max_area_fraction)),
        max_area_fraction_position: outlet
            .as_ref()
            .map_or(f64::NAN, |o| or_nan(o.max_area_fraction_position)),
        clogged: reason == StopReason::Clogged,
        stop_reason: reason,
        discharged_mass: state.discharged_mass,
        discharge_time: end,
        fill_time: opened,
        settled_kinetic_energy: state.settled_kinetic_energy,
        settled: state.settled,
        area_fraction_exponent: packing_exponent(&profile_rows, |r| {
            (r.area_fraction, r.area_fraction_error)
        }),
        crossing_area_fraction_exponent: packing_exponent(&profile_rows, |r| {
            (r.crossing_area_fraction, r.crossing_area_fraction_error)
        }),
        radial_fit,
        janssen,
        janssen_not_fitted,
        start: None,
        arch,
        repose,
        draw_down,
        fields,
        avalanches,
        coarse_graining: coarse_graining_summary(case, state.discharged_mass),
        orientation,
        residence,
    })
}

/// Columns of `arch.csv`: each arch grain's id, centre [m] and radius [m].
const ARCH_COLUMNS: [&str; 5] = ["id", "x", "y", "z", "radius"];

/// Finds the arch over the clogged orifice in the run's last state (`measure::find_arch`),
/// writes its grains to `path` and returns where it stands; `None` (and no file) when no
/// grain is over the opening.
fn write_arch(path: &Path, run: &CaseRun) -> Result<Option<ArchSummary>, RunError> {
    let sim = run.simulation();
    let particles = OwnedSnapshot::of(&sim.watched(), |_| true);
    let snapshot = particles.view(sim.time(), run.case.particles.density());
    let Some(arch) = measure::find_arch(&snapshot, &outlet_geometry(&run.case)) else {
        return Ok(None);
    };
    let rows: Vec<Vec<Cell>> = arch
        .members
        .iter()
        .map(|m| {
            let [x, y, z] = m.position;
            vec![
                Cell::Text(m.id.to_string()),
                x.into(),
                y.into(),
                z.into(),
                m.radius.into(),
            ]
        })
        .collect();
    write_csv_table(path, &ARCH_COLUMNS, &rows)?;
    Ok(Some(ArchSummary {
        particles: arch.members.len(),
        apex_height: arch.apex_height(),
        lowest_height: arch.lowest_height(),
        mean_height: arch.mean_height(),
    }))
}

/// The last five columns of `profiles.csv` in a 3D container: v [m/s] with its error, the
/// crossings counted, and the volume fraction [-] with its error. The first two give the bin's
/// position: `r_star`, `r` [m] over a circular orifice (the annulus's area-weighted mean
/// radius, `measure::radial`), `x_star`, `x` [m] along a slot or rectangle (`measure::x_profile`).
const PROFILE_3D_COLUMNS: [&str; 5] = [
    "velocity",
    "velocity_error",
    "crossings",
    "volume_fraction",
    "volume_fraction_error",
];

/// Writes a 3D container's `profiles.csv`: per bin its position `[normalised, in m]` under the
/// names `position`, then the columns of [`PROFILE_3D_COLUMNS`].
fn write_profiles_3d(
    path: &Path,
    position: [&str; 2],
    bins: impl Iterator<Item = ([f64; 2], [f64; 5])>,
) -> Result<(), RunError> {
    let rows: Vec<Vec<Cell>> = bins
        .map(|(at, values)| at.into_iter().chain(values).map(Cell::from).collect())
        .collect();
    let columns: Vec<&str> = position.into_iter().chain(PROFILE_3D_COLUMNS).collect();
    write_csv_table(path, &columns, &rows)?;
    Ok(())
}

/// Writes a circular orifice's `profiles.csv`: per annulus `r_star`, `r` [m], `velocity`,
/// `velocity_error` [m/s], `crossings`, `volume_fraction` and `volume_fraction_error` [-].
pub fn write_radial_profiles(path: &Path, bins: &[RadialBin]) -> Result<(), RunError> {
    let rows = bins.iter().map(|b| {
        let v = [b.velocity, b.velocity_error, b.crossings as f64];
        (
            [b.r_star, b.r],
            [v[0], v[1], v[2], b.volume_fraction, b.volume_fraction_error],
        )
    });
    write_profiles_3d(path, ["r_star", "r"], rows)
}

fn write_x_profiles(path: &Path, bins: &[XProfileBin]) -> Result<(), RunError> {
    let rows = bins.iter().map(|b| {
        let v = [b.velocity, b.velocity_error, b.crossings as f64];
        (
            [b.x_star, b.x],
            [v[0], v[1], v[2], b.volume_fraction, b.volume_fraction_error],
        )
    });
    write_profiles_3d(path, ["x_star", "x"], rows)
}

/// An x-bin of a 3D slot as a profile row (the volume fraction in the area fraction's place),
/// for the profile figures.
fn x_profile_row(b: &XProfileBin) -> ProfileRow {
    ProfileRow {
        x_star: b.x_star,
        x: b.x,
        velocity: b.velocity,
        velocity_error: b.velocity_error,
        crossings: b.crossings as usize,
        area_fraction: b.volume_fraction,
        area_fraction_error: b.volume_fraction_error,
        area_fraction_velocity: f64::NAN,
        snapshot_velocity: f64::NAN,
        crossing_area_fraction: f64::NAN,
        crossing_area_fraction_error: f64::NAN,
    }
}

/// A circle's annuli as profile rows at −r* and r* (the volume fraction in the area
/// fraction's place), so that the profile figures show the whole orifice.
fn mirrored(bins: &[RadialBin]) -> Vec<ProfileRow> {
    let row = |b: &RadialBin, sign: f64| ProfileRow {
        x_star: sign * b.r_star,
        x: sign * b.r,
        velocity: b.velocity,
        velocity_error: b.velocity_error,
        crossings: b.crossings as usize,
        area_fraction: b.volume_fraction,
        area_fraction_error: b.volume_fraction_error,
        area_fraction_velocity: f64::NAN,
        snapshot_velocity: f64::NAN,
        crossing_area_fraction: f64::NAN,
        crossing_area_fraction_error: f64::NAN,
    };
    let mut rows: Vec<ProfileRow> = bins.iter().rev().map(|b| row(b, -1.0)).collect();
    rows.extend(bins.iter().map(|b| row(b, 1.0)));
    rows
}

/// The self-similar fits of the radial profiles (bins r* ≤ 0.9, as for the slot, weighted by
/// the bins' errors) and the flow rate they give, over an orifice of radius `radius` [m] of
/// particles of density `density` [kg/m³]: `summary.json`'s `radial_fit`; `None` when either
/// fit fails.
pub fn fit_radial(bins: &[RadialBin], radius: f64, density: f64) -> Option<RadialFit> {
    let fit = |value: fn(&RadialBin) -> (f64, f64)| {
        let good: Vec<&RadialBin> = bins.iter().filter(|b| value(b).0.is_finite()).collect();
        let centres = good.iter().map(|b| b.r_star).collect();
        let (values, errors): (Vec<f64>, Vec<f64>) = good.iter().map(|b| value(b)).unzip();
        let counts = vec![1u64; values.len()];
        let profile = BinnedProfile::new(centres, values, counts, errors).ok()?;
        fit_power_profile(&profile, PROFILE_FIT_HALF_WIDTH).ok()
    };
    let v = fit(|b| (b.velocity, b.velocity_error))?;
    let phi = fit(|b| (b.volume_fraction, b.volume_fraction_error))?;
    let rate = axisymmetric_discharge_rate(
        &AxisymmetricFlowParameters {
            centre_velocity: v.amplitude,
            velocity_exponent: v.exponent,
            centre_fraction: phi.amplitude,
            packing_exponent: phi.exponent,
            particle_density: density,
        },
        radius,
    )
    .ok()?;
    let pair = |e: analysis::Estimate| [e.value, e.standard_error];
    Some(RadialFit {
        centre_velocity: pair(v.amplitude),
        velocity_exponent: pair(v.exponent),
        centre_volume_fraction: pair(phi.amplitude),
        packing_exponent: pair(phi.exponent),
        profile_rate: pair(rate),
    })
}

/// `wall_pressure.png` and `.svg`: the settled bed's cylinder zones `zones` (depth [m],
/// pressure and shear [Pa], deepest last) against depth, with ρ_b g h (`hydrostatic` = ρ_b g
/// [Pa/m]) and the Janssen fit `janssen` of a cylinder of radius `radius` [m] where there is
/// one. Nothing when no zone lies below the surface.
fn wall_pressure_plot(
    out_dir: &Path,
    zones: &[(f64, f64, f64)],
    janssen: Option<&files::JanssenSummary>,
    hydrostatic: f64,
    radius: f64,
) -> Result<(), RunError> {
    let deepest = zones.last().map_or(0.0, |z| z.0);
    if deepest.is_nan() || deepest <= 0.0 {
        return Ok(());
    }
    let depths = (0.0, deepest);
    let weight = FittedCurve::sampled("ρ_b g h", depths, 2, |h| hydrostatic * h);
    let fit = janssen.map(|j| {
        let label = format!(
            "Janssen, K = {:.2}, μ_w = {:.3}",
            j.stress_ratio[0], j.wall_friction[0]
        );
        // A cylinder's hydraulic radius is R/2 (docs/physics.md §7.7).
        FittedCurve::sampled(label, depths, 60, |h| {
            janssen_wall_pressure(h, j.saturation_pressure[0], j.k_mu[0], 0.5 * radius)
        })
    });
    let depth: Vec<f64> = zones.iter().map(|z| z.0).collect();
    let pressure: Vec<f64> = zones.iter().map(|z| z.1).collect();
    let shear: Vec<f64> = zones.iter().map(|z| z.2).collect();
    let fig = wall_pressure_figure(&depth, &pressure, &shear, fit.as_ref(), &weight);
    plot_png(&fig, out_dir.join("wall_pressure.png"), 900, 600)?;
    plot_svg(&fig, out_dir.join("wall_pressure.svg"), 900, 600)?;
    Ok(())
}

fn plots(
    out_dir: &Path,
    series: &RateSeries,
    window: Option<(f64, f64)>,
    rate: Option<f64>,
    rows: &[ProfileRow],
) -> Result<(), RunError> {
    let times: Vec<f64> = (0..series.len()).map(|k| series.bin_centre(k)).collect();
    let fig = discharge_rate_figure(&times, &series.rates, window, rate);
    plot_png(&fig, out_dir.join("flow_rate.png"), 900, 600)?;
    plot_svg(&fig, out_dir.join("flow_rate.svg"), 900, 600)?;
    let good: Vec<&ProfileRow> = rows.iter().filter(|r| r.velocity.is_finite()).collect();
    let xs: Vec<f64> = good.iter().map(|r| r.x_star).collect();
    let v: Vec<f64> = good.iter().map(|r| r.velocity).collect();
    let ve: Vec<f64> = good
        .iter()
        .map(|r| {
            if r.velocity_error.is_finite() {
                r.velocity_error
            } else {
                0.0
            }
        })
        .collect();
    let phi: Vec<f64> = good.iter().map(|r| r.area_fraction).collect();
    let pe: Vec<f64> = good
        .iter()
        .map(|r| {
            if r.area_fraction_error.is_finite() {
                r.area_fraction_error
            } else {
                0.0
            }
        })
        .collect();
    let fit = |values: &[f64], errors: &[f64], label: &str| -> Option<FittedCurve> {
        let counts = vec![1u64; values.len()];
        let profile =
            BinnedProfile::new(xs.clone(), values.to_vec(), counts, errors.to_vec()).ok()?;
        let f = fit_power_profile(&profile, PROFILE_FIT_HALF_WIDTH).ok()?;
        let (amp, exp) = (f.amplitude.value, f.exponent.value);
        Some(FittedCurve::sampled(
            format!("{label} = {exp:.2}"),
            (-1.0, 1.0),
            101,
            move |x| power_profile(x, amp, exp),
        ))
    };
    let v_fit = fit(&v, &ve, "(1 − x*²)^a, a");
    let fig = velocity_profile_figure(
        &Profile {
            x_star: &xs,
            value: &v,
            error: Some(&ve),
        },
        v_fit.as_ref(),
    );
    plot_png(&fig, out_dir.join("velocity_profile.png"), 900, 600)?;
    let phi_fit = fit(&phi, &pe, "(1 − x*²)^b, b");
    let fig = area_fraction_profile_figure(
        &Profile {
            x_star: &xs,
            value: &phi,
            error: Some(&pe),
        },
        phi_fit.as_ref(),
    );
    plot_png(&fig, out_dir.join("area_fraction_profile.png"), 900, 600)?;
    Ok(())
}

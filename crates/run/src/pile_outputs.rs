//! What the calibration tests add to a finished run (docs/physics.md §7.10–7.11): the heap's
//! angle of repose with `heap_surface.csv`, and the draw-down box's shelf angles with
//! `shelf_surface.csv`, measured on the run's last state.

use std::path::Path;

use case::{DrawDownGeometry, HeapGeometry};
use files::{write_csv_table, Cell, DrawDownSummary, ReposeSummary};
use measure::{
    heap_angle, shelf_angles, FlankFit, HeapBinning, Shelf, ShelfBinning, SurfaceBin, HEAP_SECTORS,
};

use super::protocol::CaseRun;
use super::RunError;

/// Columns of `heap_surface.csv`: the sector, the bin's radius about the axis [m], the highest
/// particle top in it [m], the sector's fitted line at that radius [m] (NaN where the sector
/// has no fit) and whether the bin was fitted (1) or not (0: the cap, the toe, or past them).
pub(crate) const HEAP_SURFACE_COLUMNS: [&str; 5] = ["sector", "r_m", "top_m", "fit_m", "fitted"];

/// Columns of `shelf_surface.csv`: the shelf (`left`, `right`), the strip across the depth,
/// the bin's x [m] and its distance u from the slot's edge [m], the highest particle top in it
/// [m], the strip's fitted line there [m] (NaN without a fit) and whether it was fitted.
pub(crate) const SHELF_SURFACE_COLUMNS: [&str; 7] =
    ["shelf", "strip", "x_m", "u_m", "top_m", "fit_m", "fitted"];

/// The spheres' centres [m] and radii [m] in the run's last state, a shaped grain's members
/// each: the surface the slopes are fitted to is the envelope of every sphere.
fn last_spheres(run: &CaseRun) -> (Vec<[f64; 3]>, Vec<f64>) {
    let p = run.simulation().particles();
    let positions = p.positions().iter().map(|x| x.to_array()).collect();
    (positions, p.radii().to_vec())
}

/// The grains' centres of mass [m] and masses [kg] in the run's last state: a shaped grain
/// once, with its whole mass (its members each carry it for the contact laws).
fn last_grains(run: &CaseRun) -> (Vec<[f64; 3]>, Vec<f64>) {
    let grains = run.simulation().watched().bodies(|_| true);
    let positions = grains.positions.iter().map(|x| x.to_array()).collect();
    (positions, grains.masses)
}

/// A surface bin's row tail: top, the line `line(u)` of `fit` there, and whether it was
/// fitted.
fn fitted_cells(
    bin: &SurfaceBin,
    fit: Option<&FlankFit>,
    line: impl Fn(&FlankFit) -> f64,
) -> [Cell; 3] {
    let on = fit.is_some_and(|f| f.fitted(bin));
    [
        bin.height.into(),
        fit.map_or(f64::NAN, line).into(),
        f64::from(u8::from(on)).into(),
    ]
}

/// Measures the heap left on the plate, writes `heap_surface.csv` and returns `repose`.
pub(crate) fn heap_outputs(
    run: &CaseRun,
    test: &HeapGeometry,
    out_dir: &Path,
) -> Result<ReposeSummary, RunError> {
    let (positions, radii) = last_spheres(run);
    let binning = HeapBinning {
        axis: [0.0, 0.0],
        bin_width: run.case.particles.mean_diameter(),
        sectors: HEAP_SECTORS,
    };
    let heap = heap_angle(&positions, &radii, &binning)?;
    let mut rows = Vec::new();
    for sector in &heap.sectors {
        for bin in &sector.surface {
            let r = bin.position;
            let mut row = vec![Cell::Text(sector.sector.to_string()), r.into()];
            row.extend(fitted_cells(bin, sector.fit.as_ref(), |f| {
                f.intercept - r * f.angle_deg.to_radians().tan()
            }));
            rows.push(row);
        }
    }
    write_csv_table(
        out_dir.join("heap_surface.csv"),
        &HEAP_SURFACE_COLUMNS,
        &rows,
    )?;
    let on_plate = last_grains(run)
        .0
        .iter()
        .filter(|p| p[2] >= 0.0 && p[0].hypot(p[1]) <= test.plate_radius)
        .count();
    Ok(ReposeSummary {
        angle_deg: heap.angle_deg,
        angle_error_deg: heap.angle_error_deg,
        height: heap.height,
        base_radius: heap.base_radius,
        sectors: heap.fitted_sectors,
        sectors_total: HEAP_SECTORS,
        particles: on_plate,
    })
}

/// Measures the material left on the shelves, writes `shelf_surface.csv` and returns
/// `draw_down`.
pub(crate) fn draw_down_outputs(
    run: &CaseRun,
    test: &DrawDownGeometry,
    out_dir: &Path,
) -> Result<DrawDownSummary, RunError> {
    let (positions, radii) = last_spheres(run);
    let binning = ShelfBinning {
        width: test.width(),
        depth: test.depth(),
        slot_width: test.slot_width(),
        bin_width: run.case.particles.mean_diameter(),
    };
    let angles = shelf_angles(&positions, &radii, &binning)?;
    let half_slot = 0.5 * test.slot_width();
    let mut rows = Vec::new();
    for strip in &angles.strips {
        let (word, sign) = match strip.shelf {
            Shelf::Left => ("left", -1.0),
            Shelf::Right => ("right", 1.0),
        };
        for bin in &strip.surface {
            let u = bin.position;
            let mut row = vec![
                Cell::Text(word.to_string()),
                Cell::Text(strip.strip.to_string()),
                (sign * (half_slot + u)).into(),
                u.into(),
            ];
            row.extend(fitted_cells(bin, strip.fit.as_ref(), |f| {
                f.intercept + u * f.angle_deg.to_radians().tan()
            }));
            rows.push(row);
        }
    }
    write_csv_table(
        out_dir.join("shelf_surface.csv"),
        &SHELF_SURFACE_COLUMNS,
        &rows,
    )?;
    // What stays in the box: the grains above its floor (those still falling through the
    // slot are on their way out).
    let (centres, masses) = last_grains(run);
    let residual_mass = centres
        .iter()
        .zip(&masses)
        .filter(|(p, _)| p[2] >= 0.0)
        .map(|(_, m)| m)
        .sum();
    Ok(DrawDownSummary {
        shelf_angle_deg: angles.angle_deg,
        shelf_angle_error_deg: angles.angle_error_deg,
        left_angle_deg: angles.left_angle_deg,
        right_angle_deg: angles.right_angle_deg,
        strips: angles.fitted_strips,
        residual_mass,
    })
}

//! Case and sweep files: located TOML documents, then validated domain types.
//!
//! Reading a case goes document → overrides → validated [`Case`]:
//! the TOML text is parsed once into a tree that keeps the line of every key
//! (`document`), `--set key=value` overrides replace nodes of that tree, and `resolve`
//! reads the tree section by section, filling defaults and collecting every error with
//! its file, key, line and value. Keys are plain SI names (`outlet_width` in metres); the
//! only non-SI unit is the degree, used for angles and marked by a `_deg` suffix.

#![warn(missing_docs)]

mod builtin;
mod calibration_file;
mod case;
mod cuboid;
mod cylinder;
mod document;
mod draw_down;
mod error;
mod fill_height;
mod geometry;
mod grain_shape;
mod heap;
mod limits;
mod mesh;
mod named_file;
mod overrides;
mod particles;
mod reader;
mod resolve;
mod resolve_cohesion;
mod resolve_cuboid;
mod resolve_cylinder;
mod resolve_draw_down;
mod resolve_heap;
mod resolve_materials;
mod resolve_mesh;
mod resolve_particles;
mod resolve_run;
mod resolve_shape;
mod slab;
mod sources;
mod sweep;
mod sweep_file;
mod template;
mod wall_surface;
mod write;

use std::path::Path;
use std::sync::Arc;

pub use builtin::{
    builtin_sweep, BUILTIN_SWEEP_NAMES, FAN2023_QUICK_SWEEP, FAN2023_SENSITIVITY_SWEEP,
    FAN2023_SWEEP,
};
pub use calibration_file::{
    load_calibration, parse_calibration, CalibrationParameter, CalibrationPlan, CalibrationTarget,
    CalibrationTest, MAX_CALIBRATION_PARAMETERS, MAX_CALIBRATION_TARGETS,
};
pub use case::{
    Case, ContactSpec, FieldKernel, FieldsSpec, InteractionSpec, MeasureSpec, OutputSpec, Protocol,
    RollingLawSpec, TangentialLawSpec, UnclogMethod, UnclogSpec, WallMaterialSpec, WallSpec,
    BULK_VOLUME_FRACTION, CASE_FORMAT_VERSION, MAX_AVALANCHES, MAX_GRAVITY, MAX_RAYLEIGH_FRACTION,
    MAX_UNCLOG_FORCE_RATIO, MONOLAYER_AREA_FRACTION, THICK_SLAB_DIAMETERS,
};
pub use cuboid::{CuboidFace, CuboidGeometry, CuboidOutlet, HalfSpace};
pub use cylinder::CylinderGeometry;
pub use draw_down::DrawDownGeometry;
pub use error::{ConfigError, ConfigErrors, ErrorKind, Location};
pub use geometry::Geometry;
pub use grain_shape::{default_beads, GrainShape, ShapeGiven, MAX_ASPECT_RATIO};
pub use heap::HeapGeometry;
pub use mesh::{box_meets_triangle, MeshGeometry, MeshOutlet, MeshWall, MAX_MESH_WALLS};
pub use particles::{
    mass_fractions_from_number, number_fractions_from_mass, CoarseGraining, Component,
    FractionBasis, MaterialSpec, ParticleSpec, SizeDistribution,
};
pub use slab::SlabGeometry;
pub use sweep::{
    load_sweep, parse_sweep, replica_seed, sweep_with_replicas, SkippedCase, SweepCase, SweepPlan,
};
pub use template::{
    template, template_files, BOX_TEMPLATE, CASE_TEMPLATE, CYLINDER_TEMPLATE, DRAW_DOWN_TEMPLATE,
    HEAP_TEMPLATE, MESH_TEMPLATE,
};
pub use wall_surface::{WallSurface, DEFAULT_MESH_SEGMENTS};

use document::parse_document;
use error::ErrorKind as Kind;

/// Reads, overrides and validates a case file.
///
/// `sets` are `key=value` overrides (dotted key, TOML value) applied before validation.
/// Errors name the file (or `--set`), the key, its line, the value and what is allowed.
///
/// Relative paths in the case (the STL files of `geometry.kind = "mesh"`) are taken from the
/// case file's folder, and the resolved case holds them absolute.
pub fn load_case(path: &Path, sets: &[String]) -> Result<Case, ConfigErrors> {
    let name = path.display().to_string();
    let text = read_text(path, &name)?;
    parse_case_in(&text, &name, path.parent(), sets)
}

/// Validates case text; `source_name` is the name errors give for it (e.g. the file name).
/// Relative paths in it are taken from the current folder.
///
/// A text without any key is refused: an empty file is almost always a mistake, and
/// `version = 1` alone asks for the paper's base case explicitly.
pub fn parse_case(src: &str, source_name: &str, sets: &[String]) -> Result<Case, ConfigErrors> {
    parse_case_in(src, source_name, None, sets)
}

/// [`parse_case`] for text whose relative paths are taken from `dir` (`None`: the current
/// folder), as for a case file in `dir`.
pub fn parse_case_in(
    src: &str,
    source_name: &str,
    dir: Option<&Path>,
    sets: &[String],
) -> Result<Case, ConfigErrors> {
    let source: Arc<str> = Arc::from(source_name);
    let src = src.strip_prefix('\u{feff}').unwrap_or(src);
    let mut document = parse_document(src, &source)?;
    if document.is_empty() {
        return Err(ConfigErrors::single(ConfigError::new(
            Kind::Missing,
            Location::whole(&source),
            "",
            None,
            "the case file has no keys; write `version = 1` for the paper's base case, \
             or run `hopperflow init` for a commented template",
        )));
    }
    let set_errors = overrides::apply_sets(&mut document, sets).err();
    merge_errors(resolve::resolve_case(&document, &source, dir), set_errors)
}

/// The paper's base case with `--set` overrides applied and validated (a run without a
/// case file).
pub fn default_case(sets: &[String]) -> Result<Case, ConfigErrors> {
    let source: Arc<str> = Arc::from("default");
    let mut document = document::Table::default();
    let set_errors = overrides::apply_sets(&mut document, sets).err();
    merge_errors(resolve::resolve_case(&document, &source, None), set_errors)
}

/// Adds the errors of malformed `--set` overrides to a validation result, so that one
/// report lists every problem.
pub(crate) fn merge_errors<T>(
    result: Result<T, ConfigErrors>,
    set_errors: Option<ConfigErrors>,
) -> Result<T, ConfigErrors> {
    match (result, set_errors) {
        (result, None) => result,
        (Ok(_), Some(errors)) => Err(errors),
        (Err(mut errors), Some(mut more)) => {
            errors.errors.append(&mut more.errors);
            Err(errors)
        }
    }
}

/// Reads a file as UTF-8 text; errors name the file and, for bad bytes, their line.
pub(crate) fn read_text(path: &Path, name: &str) -> Result<String, ConfigErrors> {
    let source: Arc<str> = Arc::from(name);
    let bytes = std::fs::read(path).map_err(|e| {
        ConfigErrors::single(ConfigError::new(
            Kind::Io,
            Location::whole(&source),
            "",
            None,
            format!("cannot read the file: {e}"),
        ))
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let valid = e.utf8_error().valid_up_to();
        let bytes = e.as_bytes();
        let line = bytes[..valid].iter().filter(|b| **b == b'\n').count() + 1;
        ConfigErrors::single(ConfigError::new(
            Kind::Io,
            Location {
                source: Arc::clone(&source),
                line: Some(line),
                column: None,
            },
            "",
            None,
            format!("the file is not valid UTF-8 (first bad byte at offset {valid}); TOML files must be UTF-8"),
        ))
    })
}

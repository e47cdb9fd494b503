//! VTK XML unstructured grids (`.vtu`) for ParaView: particles as vertices, walls as polygons;
//! and VTK XML image data (`.vti`): fields on a regular grid ([`write_grid_vti`]).
//!
//! The format is the VTK XML "UnstructuredGrid" file (VTK File Formats, version 1.0). Data are
//! written inline as ASCII: a 3000-particle snapshot is about 1 MB, small enough that the
//! simplicity (readable, diffable, no base64 or byte-order concerns) wins over binary. Numbers
//! use the shortest text that parses back to the same `f64`, so nothing is lost.

use std::fmt::Write as _;
use std::path::Path;

use super::table::format_number;
use super::{write_atomic, OutputError};

/// VTK cell type of a single point (`VTK_VERTEX`).
const VTK_VERTEX: u8 = 1;
/// VTK cell type of a planar polygon with any number of corners (`VTK_POLYGON`).
const VTK_POLYGON: u8 = 7;
/// Numbers per line in the ASCII arrays, to keep lines short for text tools.
const VALUES_PER_LINE: usize = 12;

/// One snapshot of the particles, as parallel slices indexed by particle.
///
/// All slices must have the same length.
#[derive(Debug, Clone, Copy)]
pub struct ParticleFields<'a> {
    /// Stable particle identifiers (written as `Int64`, so each must be at most `i64::MAX`).
    pub ids: &'a [u64],
    /// Centre positions [m].
    pub positions: &'a [[f64; 3]],
    /// Radii [m].
    pub radii: &'a [f64],
    /// Translational velocities [m/s].
    pub velocities: &'a [[f64; 3]],
    /// Angular velocities [rad/s].
    pub angular_velocities: &'a [[f64; 3]],
    /// Each particle's component in a mixture, an index into the case's
    /// `particles.components` (written as the `Int32` array `component`); `None` for a case of
    /// one component.
    pub components: Option<&'a [u8]>,
    /// Each sphere's grain where grains are rigid clumps of spheres: the id of the grain's
    /// first member, the sphere's own id for a free sphere (written as the `Int64` array
    /// `body`, so that ParaView can colour, threshold or count by grain); `None` for a
    /// case of spheres only.
    pub bodies: Option<&'a [u64]>,
}

/// Writes the particles as a `.vtu` of `VTK_VERTEX` cells at simulation time `time` [s].
///
/// Point data: `id` (Int64), `radius` [m], `velocity` [m/s] (3 components),
/// `angular_velocity` [rad/s] (3 components), `speed` = |velocity| [m/s], for a mixture
/// `component` (Int32, an index into `particles.components`) and, for grains that are clumps
/// of spheres, `body` (Int64, the grain each sphere belongs to). A clump is drawn as its
/// member spheres (ParaView's Glyph filter scaled by `radius`), which is its actual shape. The time is also
/// stored as the `TimeValue` field, which ParaView shows when the file is opened alone.
pub fn write_particles_vtu(
    path: impl AsRef<Path>,
    particles: &ParticleFields<'_>,
    time: f64,
) -> Result<(), OutputError> {
    let path = path.as_ref();
    let count = particles.positions.len();
    let lengths = [
        ("ids", particles.ids.len()),
        ("radii", particles.radii.len()),
        ("velocities", particles.velocities.len()),
        ("angular_velocities", particles.angular_velocities.len()),
        (
            "components",
            particles.components.map_or(count, <[u8]>::len),
        ),
        ("bodies", particles.bodies.map_or(count, <[u64]>::len)),
    ];
    if let Some((name, length)) = lengths.iter().find(|(_, length)| *length != count) {
        return Err(OutputError::invalid(
            path,
            format!("{count} positions but {length} {name}"),
        ));
    }
    if let Some(index) = particles.ids.iter().position(|&id| id > i64::MAX as u64) {
        return Err(OutputError::invalid(
            path,
            format!("particle {index} has an id above the Int64 range"),
        ));
    }
    ensure_finite(path, "time", std::slice::from_ref(&time))?;
    ensure_finite_vectors(path, "position", particles.positions)?;
    ensure_finite(path, "radius", particles.radii)?;
    ensure_finite_vectors(path, "velocity", particles.velocities)?;
    ensure_finite_vectors(path, "angular velocity", particles.angular_velocities)?;

    let speeds: Vec<f64> = particles
        .velocities
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .collect();

    let mut xml = String::with_capacity(400 * count + 2048);
    open_grid(&mut xml, time, count, count);
    xml.push_str("      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n");
    let ids = particles.ids.iter().map(|id| id.to_string());
    data_array(&mut xml, "Int64", "id", 1, ids);
    float_array(&mut xml, "radius", 1, particles.radii.iter().copied());
    if let Some(components) = particles.components {
        let values = components.iter().map(|c| c.to_string());
        data_array(&mut xml, "Int32", "component", 1, values);
    }
    if let Some(bodies) = particles.bodies {
        let values = bodies.iter().map(|b| b.to_string());
        data_array(&mut xml, "Int64", "body", 1, values);
    }
    float_array(
        &mut xml,
        "velocity",
        3,
        particles.velocities.iter().flatten().copied(),
    );
    float_array(
        &mut xml,
        "angular_velocity",
        3,
        particles.angular_velocities.iter().flatten().copied(),
    );
    float_array(&mut xml, "speed", 1, speeds.iter().copied());
    xml.push_str("      </PointData>\n");
    points(&mut xml, particles.positions.iter().flatten().copied());
    // One vertex cell per particle: connectivity i, offset i + 1.
    cells(
        &mut xml,
        (0..count).map(|i| i.to_string()),
        (1..=count).map(|i| i.to_string()),
        (0..count).map(|_| VTK_VERTEX),
    );
    close_grid(&mut xml);
    write_atomic(path, xml.as_bytes())
}

/// Writes wall polygons as a `.vtu` of `VTK_POLYGON` cells at simulation time `time` [s].
///
/// Each polygon is its list of corners [m] in order around the face (at least three). The
/// cell data `wall` holds the polygon's index in `polygons`, so walls can be coloured apart.
pub fn write_walls_vtu<P: AsRef<[[f64; 3]]>>(
    path: impl AsRef<Path>,
    polygons: &[P],
    time: f64,
) -> Result<(), OutputError> {
    let path = path.as_ref();
    ensure_finite(path, "time", std::slice::from_ref(&time))?;
    for (index, polygon) in polygons.iter().enumerate() {
        let corners = polygon.as_ref();
        if corners.len() < 3 {
            return Err(OutputError::invalid(
                path,
                format!(
                    "wall polygon {index} has {} corners, needs 3",
                    corners.len()
                ),
            ));
        }
        ensure_finite_vectors(path, "wall corner", corners)?;
    }
    let point_count: usize = polygons.iter().map(|p| p.as_ref().len()).sum();
    let offsets: Vec<usize> = polygons
        .iter()
        .scan(0, |end, polygon| {
            *end += polygon.as_ref().len();
            Some(*end)
        })
        .collect();

    let mut xml = String::with_capacity(100 * point_count + 2048);
    open_grid(&mut xml, time, point_count, polygons.len());
    xml.push_str("      <CellData Scalars=\"wall\">\n");
    let wall_indices = (0..polygons.len()).map(|i| i.to_string());
    data_array(&mut xml, "Int64", "wall", 1, wall_indices);
    xml.push_str("      </CellData>\n");
    points(
        &mut xml,
        polygons
            .iter()
            .flat_map(|p| p.as_ref().iter().flatten().copied()),
    );
    // Corners are not shared between polygons, so the connectivity is simply 0..point_count.
    cells(
        &mut xml,
        (0..point_count).map(|i| i.to_string()),
        offsets.iter().map(|end| end.to_string()),
        (0..polygons.len()).map(|_| VTK_POLYGON),
    );
    close_grid(&mut xml);
    write_atomic(path, xml.as_bytes())
}

/// Refuses NaN and infinities: VTK's ASCII reader cannot parse them, and they mean the
/// caller's state is already broken.
fn ensure_finite(path: &Path, name: &str, values: &[f64]) -> Result<(), OutputError> {
    match values.iter().position(|value| !value.is_finite()) {
        Some(index) => Err(OutputError::invalid(
            path,
            format!("{name} {index} is not finite ({})", values[index]),
        )),
        None => Ok(()),
    }
}

/// [`ensure_finite`] for three-component vectors.
fn ensure_finite_vectors(path: &Path, name: &str, values: &[[f64; 3]]) -> Result<(), OutputError> {
    match values
        .iter()
        .position(|value| value.iter().any(|c| !c.is_finite()))
    {
        Some(index) => Err(OutputError::invalid(
            path,
            format!("{name} {index} is not finite ({:?})", values[index]),
        )),
        None => Ok(()),
    }
}

/// Header, time field and the opening of the single piece.
fn open_grid(xml: &mut String, time: f64, points: usize, cells: usize) {
    xml.push_str("<?xml version=\"1.0\"?>\n");
    xml.push_str(
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n",
    );
    xml.push_str("  <UnstructuredGrid>\n");
    xml.push_str("    <FieldData>\n");
    let _ = writeln!(
        xml,
        "      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" \
         format=\"ascii\">{}</DataArray>",
        format_number(time)
    );
    xml.push_str("    </FieldData>\n");
    let _ = writeln!(
        xml,
        "    <Piece NumberOfPoints=\"{points}\" NumberOfCells=\"{cells}\">"
    );
}

/// Closes the piece, the grid and the file.
fn close_grid(xml: &mut String) {
    xml.push_str("    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
}

/// The `<Points>` section from flattened x, y, z triples [m].
fn points(xml: &mut String, coordinates: impl Iterator<Item = f64>) {
    xml.push_str("      <Points>\n");
    float_array(xml, "position", 3, coordinates);
    xml.push_str("      </Points>\n");
}

/// The `<Cells>` section: connectivity, offsets (one past each cell's last point) and types.
fn cells(
    xml: &mut String,
    connectivity: impl Iterator<Item = String>,
    offsets: impl Iterator<Item = String>,
    types: impl Iterator<Item = u8>,
) {
    xml.push_str("      <Cells>\n");
    data_array(xml, "Int64", "connectivity", 1, connectivity);
    data_array(xml, "Int64", "offsets", 1, offsets);
    data_array(xml, "UInt8", "types", 1, types.map(|t| t.to_string()));
    xml.push_str("      </Cells>\n");
}

/// A `Float64` data array with `components` values per tuple.
fn float_array(xml: &mut String, name: &str, components: usize, values: impl Iterator<Item = f64>) {
    data_array(xml, "Float64", name, components, values.map(format_number));
}

/// One inline ASCII `<DataArray>` of already formatted values.
fn data_array(
    xml: &mut String,
    vtk_type: &str,
    name: &str,
    components: usize,
    values: impl Iterator<Item = String>,
) {
    let _ = write!(
        xml,
        "        <DataArray type=\"{vtk_type}\" Name=\"{name}\" "
    );
    if components > 1 {
        let _ = write!(xml, "NumberOfComponents=\"{components}\" ");
    }
    xml.push_str("format=\"ascii\">\n");
    let mut column = 0;
    for value in values {
        xml.push_str(if column == 0 { "          " } else { " " });
        xml.push_str(&value);
        column += 1;
        if column == VALUES_PER_LINE {
            xml.push('\n');
            column = 0;
        }
    }
    if column != 0 {
        xml.push('\n');
    }
    xml.push_str("        </DataArray>\n");
}

/// One point-data array of a grid: its name (units in the name, `density_kg_m3`), the
/// values per point and the values, point by point with x fastest, then y, then z.
#[derive(Debug, Clone, Copy)]
pub struct GridArray<'a> {
    /// Name, with its unit.
    pub name: &'a str,
    /// Values per point (1 scalar, 3 vector, 9 tensor, row-major).
    pub components: usize,
    /// The values, `components` per point.
    pub values: &'a [f64],
}

/// A regular grid of points for a VTK XML image file (`.vti`): `dimensions` points along
/// x, y and z from `origin` [m], `spacing` [m] apart.
#[derive(Debug, Clone, Copy)]
pub struct GridFields<'a> {
    /// The first point [m].
    pub origin: [f64; 3],
    /// The distance between neighbouring points along each axis [m].
    pub spacing: [f64; 3],
    /// Points along each axis.
    pub dimensions: [usize; 3],
    /// Point data.
    pub arrays: &'a [GridArray<'a>],
    /// Single numbers stored as field data, each named with its unit (`width_m`).
    pub notes: &'a [(&'a str, f64)],
    /// A comment written at the top of the file (units, basis, sign convention).
    pub comment: &'a str,
}

/// Writes a regular grid as a VTK XML `ImageData` file (`.vti`), which ParaView opens, with
/// its arrays as point data and its notes as field data; atomically. Refuses arrays of the
/// wrong length and non-finite values, naming them.
pub fn write_grid_vti(path: impl AsRef<Path>, grid: &GridFields<'_>) -> Result<(), OutputError> {
    let path = path.as_ref();
    let count: usize = grid.dimensions.iter().product();
    if count == 0 {
        return Err(OutputError::invalid(path, "the grid has no points"));
    }
    for a in grid.arrays {
        if a.components == 0 || a.values.len() != count * a.components {
            return Err(OutputError::invalid(
                path,
                format!(
                    "{count} points but {} values of {} components in {}",
                    a.values.len(),
                    a.components,
                    a.name
                ),
            ));
        }
        ensure_finite(path, a.name, a.values)?;
    }
    for (name, value) in grid.notes {
        ensure_finite(path, name, std::slice::from_ref(value))?;
    }
    ensure_finite(path, "origin", &grid.origin)?;
    ensure_finite(path, "spacing", &grid.spacing)?;
    let extent = grid
        .dimensions
        .iter()
        .map(|n| format!("0 {}", n - 1))
        .collect::<Vec<_>>()
        .join(" ");
    let three = |v: [f64; 3]| v.map(format_number).join(" ");
    let mut xml = String::with_capacity(64 * count * grid.arrays.len() + 2048);
    xml.push_str("<?xml version=\"1.0\"?>\n");
    let comment = grid.comment.replace("--", "- -");
    let _ = writeln!(xml, "<!-- {comment} -->");
    xml.push_str(
        "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">\n",
    );
    let _ = writeln!(
        xml,
        "  <ImageData WholeExtent=\"{extent}\" Origin=\"{}\" Spacing=\"{}\">",
        three(grid.origin),
        three(grid.spacing)
    );
    if !grid.notes.is_empty() {
        xml.push_str("    <FieldData>\n");
        for (name, value) in grid.notes {
            let _ = writeln!(
                xml,
                "      <DataArray type=\"Float64\" Name=\"{name}\" NumberOfTuples=\"1\" \
                 format=\"ascii\">{}</DataArray>",
                format_number(*value)
            );
        }
        xml.push_str("    </FieldData>\n");
    }
    let _ = writeln!(xml, "    <Piece Extent=\"{extent}\">");
    xml.push_str("      <PointData>\n");
    for a in grid.arrays {
        float_array(&mut xml, a.name, a.components, a.values.iter().copied());
    }
    xml.push_str("      </PointData>\n");
    xml.push_str("    </Piece>\n  </ImageData>\n</VTKFile>\n");
    write_atomic(path, xml.as_bytes())
}

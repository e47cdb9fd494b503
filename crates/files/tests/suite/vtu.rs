//! Behaviour of the VTU and PVD writers: well-formed XML, consistent counts, exact values.

use files::{write_particles_vtu, write_walls_vtu, OutputError, ParticleFields, PvdCollection};

/// Checks that every tag is closed in the right order and that there is a single root
/// element. Enough of XML for files we generate ourselves: no comments, no CDATA.
fn assert_well_formed(xml: &str) {
    let mut stack: Vec<String> = Vec::new();
    let mut roots = 0;
    let mut rest = xml;
    while let Some(start) = rest.find('<') {
        let text = &rest[..start];
        assert!(!text.contains('>'), "stray '>' in text: {text:?}");
        let end = rest[start..].find('>').expect("tag is closed") + start;
        let tag = &rest[start + 1..end];
        rest = &rest[end + 1..];
        if tag.starts_with('?') {
            assert!(tag.ends_with('?'), "processing instruction {tag:?}");
            continue;
        }
        if let Some(name) = tag.strip_prefix('/') {
            let open = stack.pop().expect("closing tag has an opening tag");
            assert_eq!(open, name.trim(), "tags close in the order they opened");
            continue;
        }
        let name = tag
            .split_whitespace()
            .next()
            .expect("tag has a name")
            .trim_end_matches('/')
            .to_string();
        // Attribute values are double-quoted, so the quote count must be even.
        assert_eq!(
            tag.matches('"').count() % 2,
            0,
            "unbalanced quotes in {tag:?}"
        );
        if stack.is_empty() {
            roots += 1;
        }
        if !tag.ends_with('/') {
            stack.push(name);
        }
    }
    assert!(stack.is_empty(), "unclosed tags {stack:?}");
    assert_eq!(roots, 1, "exactly one root element");
}

/// The value of attribute `name` on the first element that has it.
fn attribute<'a>(xml: &'a str, name: &str) -> &'a str {
    let key = format!("{name}=\"");
    let start = xml.find(&key).expect("attribute present") + key.len();
    let end = xml[start..].find('"').expect("attribute closed") + start;
    &xml[start..end]
}

/// The whitespace-separated values of the `DataArray` called `name`.
fn array<'a>(xml: &'a str, name: &str) -> Vec<&'a str> {
    let key = format!("Name=\"{name}\"");
    let start = xml.find(&key).expect("array present");
    let open_end = xml[start..].find('>').expect("opening tag closed") + start + 1;
    let close = xml[open_end..].find("</DataArray>").expect("array closed") + open_end;
    xml[open_end..close].split_whitespace().collect()
}

/// [`array`] parsed as numbers.
fn numbers(xml: &str, name: &str) -> Vec<f64> {
    array(xml, name)
        .iter()
        .map(|value| value.parse().expect("number"))
        .collect()
}

/// Five particles whose values need full precision to survive the trip.
struct Sample {
    ids: Vec<u64>,
    positions: Vec<[f64; 3]>,
    radii: Vec<f64>,
    velocities: Vec<[f64; 3]>,
    angular_velocities: Vec<[f64; 3]>,
}

impl Sample {
    fn new() -> Self {
        let count = 5;
        Self {
            ids: (0..count).map(|i| 1000 + 7 * i as u64).collect(),
            positions: (0..count)
                .map(|i| [0.001 * i as f64 / 3.0, 1e-9, 0.4 - 0.1 * i as f64])
                .collect(),
            radii: (0..count)
                .map(|i| 1.5e-3 * (1.0 + 0.01 * i as f64))
                .collect(),
            velocities: (0..count)
                .map(|i| [0.3 * i as f64, -1.0 / 7.0, -0.25 * i as f64])
                .collect(),
            angular_velocities: (0..count)
                .map(|i| [1e-12, 123.456 * i as f64, -0.0])
                .collect(),
        }
    }

    fn fields(&self) -> ParticleFields<'_> {
        ParticleFields {
            ids: &self.ids,
            positions: &self.positions,
            radii: &self.radii,
            velocities: &self.velocities,
            angular_velocities: &self.angular_velocities,
            components: None,
            bodies: None,
        }
    }
}

#[test]
fn particle_file_is_well_formed_with_one_vertex_per_particle() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("particles_0001.vtu");
    let sample = Sample::new();
    write_particles_vtu(&path, &sample.fields(), 0.125).expect("write");
    let xml = std::fs::read_to_string(&path).expect("read back");
    assert_well_formed(&xml);
    assert_eq!(attribute(&xml, "type"), "UnstructuredGrid");
    assert_eq!(attribute(&xml, "NumberOfPoints"), "5");
    assert_eq!(attribute(&xml, "NumberOfCells"), "5");
    // Every array holds count × components values.
    assert_eq!(array(&xml, "id").len(), 5);
    assert_eq!(array(&xml, "radius").len(), 5);
    assert_eq!(array(&xml, "velocity").len(), 15);
    assert_eq!(array(&xml, "angular_velocity").len(), 15);
    assert_eq!(array(&xml, "speed").len(), 5);
    assert_eq!(array(&xml, "position").len(), 15);
    // VTK_VERTEX is cell type 1; cell i holds point i alone.
    assert_eq!(array(&xml, "types"), vec!["1"; 5]);
    assert_eq!(array(&xml, "connectivity"), vec!["0", "1", "2", "3", "4"]);
    assert_eq!(array(&xml, "offsets"), vec!["1", "2", "3", "4", "5"]);
    assert_eq!(numbers(&xml, "TimeValue"), vec![0.125]);
}

#[test]
fn particle_values_round_trip_bit_for_bit() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("particles.vtu");
    let sample = Sample::new();
    write_particles_vtu(&path, &sample.fields(), 1.0 / 3.0).expect("write");
    let xml = std::fs::read_to_string(&path).expect("read back");
    let ids: Vec<u64> = array(&xml, "id")
        .iter()
        .map(|v| v.parse().expect("id"))
        .collect();
    assert_eq!(ids, sample.ids);
    // Shortest round-trip formatting: equality is exact, no tolerance needed.
    let flat = |vectors: &[[f64; 3]]| vectors.iter().flatten().copied().collect::<Vec<f64>>();
    assert_eq!(numbers(&xml, "position"), flat(&sample.positions));
    assert_eq!(numbers(&xml, "radius"), sample.radii);
    assert_eq!(numbers(&xml, "velocity"), flat(&sample.velocities));
    assert_eq!(
        numbers(&xml, "angular_velocity"),
        flat(&sample.angular_velocities)
    );
    assert_eq!(numbers(&xml, "TimeValue"), vec![1.0 / 3.0]);
    for (speed, velocity) in numbers(&xml, "speed").iter().zip(&sample.velocities) {
        let expected = velocity.iter().map(|c| c * c).sum::<f64>().sqrt();
        // A few roundings in the sum of squares and the root: 4 ulp is ample.
        assert!(
            (speed - expected).abs() <= 4.0 * f64::EPSILON * expected,
            "speed {speed} vs {expected}"
        );
    }
}

#[test]
fn empty_particle_set_gives_an_empty_but_valid_grid() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("empty.vtu");
    let fields = ParticleFields {
        ids: &[],
        positions: &[],
        radii: &[],
        velocities: &[],
        angular_velocities: &[],
        components: None,
        bodies: None,
    };
    write_particles_vtu(&path, &fields, 2.0).expect("write");
    let xml = std::fs::read_to_string(&path).expect("read back");
    assert_well_formed(&xml);
    assert_eq!(attribute(&xml, "NumberOfPoints"), "0");
    assert!(array(&xml, "radius").is_empty());
}

#[test]
fn mismatched_particle_slices_are_refused_without_writing() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("bad.vtu");
    let sample = Sample::new();
    let mut fields = sample.fields();
    fields.radii = &sample.radii[..4];
    let error = write_particles_vtu(&path, &fields, 0.0).expect_err("length mismatch");
    assert!(
        matches!(error, OutputError::InvalidData { .. }),
        "got {error:?}"
    );
    assert!(!path.exists());
}

#[test]
fn non_finite_positions_are_refused() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("nan.vtu");
    let mut sample = Sample::new();
    sample.positions[3][2] = f64::NAN;
    let error = write_particles_vtu(&path, &sample.fields(), 0.0).expect_err("NaN position");
    assert!(error.to_string().contains("position 3"), "message: {error}");
    assert!(!path.exists());
}

#[test]
fn wall_file_has_one_polygon_cell_per_wall_with_its_corners() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("walls.vtu");
    let left = vec![
        [0.0, 0.0, 0.0],
        [0.0, 3.03e-3, 0.0],
        [0.0, 3.03e-3, 0.4],
        [0.0, 0.0, 0.4],
    ];
    let right = vec![
        [0.1, 0.0, 0.0],
        [0.1, 3.03e-3, 0.0],
        [0.1, 3.03e-3, 0.4],
        [0.1, 0.0, 0.4],
    ];
    let triangle = vec![[0.0, 0.0, 0.0], [0.05, 0.0, -0.01], [0.1, 0.0, 0.0]];
    let polygons = [left.clone(), right.clone(), triangle.clone()];
    write_walls_vtu(&path, &polygons, 0.0).expect("write");
    let xml = std::fs::read_to_string(&path).expect("read back");
    assert_well_formed(&xml);
    assert_eq!(attribute(&xml, "NumberOfPoints"), "11");
    assert_eq!(attribute(&xml, "NumberOfCells"), "3");
    // VTK_POLYGON is cell type 7; offsets mark the end of each polygon's corner list.
    assert_eq!(array(&xml, "types"), vec!["7"; 3]);
    assert_eq!(array(&xml, "offsets"), vec!["4", "8", "11"]);
    assert_eq!(array(&xml, "connectivity").len(), 11);
    assert_eq!(array(&xml, "wall"), vec!["0", "1", "2"]);
    let corners: Vec<f64> = [left, right, triangle]
        .iter()
        .flatten()
        .flatten()
        .copied()
        .collect();
    assert_eq!(numbers(&xml, "position"), corners);
}

#[test]
fn wall_polygon_with_two_corners_is_refused() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("walls.vtu");
    let polygons = [[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]];
    let error = write_walls_vtu(&path, &polygons, 0.0).expect_err("degenerate polygon");
    assert!(
        matches!(error, OutputError::InvalidData { .. }),
        "got {error:?}"
    );
    assert!(!path.exists());
}

#[test]
fn pvd_collection_is_rewritten_as_the_series_grows() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("series.pvd");
    let mut collection = PvdCollection::new(&path);
    assert!(
        !path.exists(),
        "nothing is written before the first dataset"
    );

    // Given as a path inside the collection's directory: stored relative to it.
    collection
        .push(0.0, 0, directory.path().join("frames").join("p_0000.vtu"))
        .expect("first push");
    collection.push(0.0, 1, "walls.vtu").expect("walls");
    let xml = std::fs::read_to_string(&path).expect("read back");
    assert_well_formed(&xml);
    assert_eq!(xml.matches("<DataSet ").count(), 2);

    collection.push(0.05, 0, "frames/p_0001.vtu").expect("push");
    collection.push(0.05, 1, "walls & more.vtu").expect("push");
    let xml = std::fs::read_to_string(&path).expect("read back");
    assert_well_formed(&xml);
    assert_eq!(attribute(&xml, "type"), "Collection");
    let datasets: Vec<&str> = xml.lines().filter(|l| l.contains("<DataSet ")).collect();
    assert_eq!(datasets.len(), 4);
    assert_eq!(attribute(datasets[0], "file"), "frames/p_0000.vtu");
    assert_eq!(attribute(datasets[1], "part"), "1");
    assert_eq!(
        attribute(datasets[2], "timestep").parse::<f64>().ok(),
        Some(0.05)
    );
    // The ampersand must be escaped or the XML would be malformed.
    assert_eq!(attribute(datasets[3], "file"), "walls &amp; more.vtu");
    assert_eq!(collection.entries().len(), 4);
    assert_eq!(collection.entries()[0].file, "frames/p_0000.vtu");
}

#[test]
fn pvd_collection_refuses_a_non_finite_time() {
    let directory = tempfile::tempdir().expect("temporary directory");
    let path = directory.path().join("series.pvd");
    let mut collection = PvdCollection::new(&path);
    let error = collection
        .push(f64::INFINITY, 0, "p.vtu")
        .expect_err("infinite time");
    assert!(
        matches!(error, OutputError::InvalidData { .. }),
        "got {error:?}"
    );
    assert!(collection.entries().is_empty());
    assert!(!path.exists());
}

#[test]
fn a_grid_is_written_as_image_data_with_every_value_and_refused_when_inconsistent() {
    // A 3 × 1 × 2 grid with a scalar and a 3-vector: the file must be well-formed XML (the
    // comment aside), state its extent, origin and spacing, hold every value to the bit
    // (shortest round-trip text) and the notes as field data; wrong lengths and NaN refused.
    use files::{write_grid_vti, GridArray, GridFields};
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("fields.vti");
    let density = [1.0, 2.5, 1.0 / 3.0, 4.0, 5.0, 6.0];
    let velocity: Vec<f64> = (0..18).map(|k| k as f64 * 0.1).collect();
    let arrays = [
        GridArray {
            name: "density_kg_m3",
            components: 1,
            values: &density,
        },
        GridArray {
            name: "velocity_m_s",
            components: 3,
            values: &velocity,
        },
    ];
    let grid = GridFields {
        origin: [0.5e-3, 0.0, -1.0e-3],
        spacing: [1.0e-3, 1.0e-3, 1.0e-3],
        dimensions: [3, 1, 2],
        arrays: &arrays,
        notes: &[("width_m", 1.5e-3)],
        comment: "compression positive",
    };
    write_grid_vti(&path, &grid).expect("written");
    let xml = std::fs::read_to_string(&path).unwrap();
    let start = xml.find("<!--").unwrap();
    let end = xml.find("-->").unwrap() + 3;
    assert_well_formed(&format!("{}{}", &xml[..start], &xml[end..]));
    assert!(xml.contains("WholeExtent=\"0 2 0 0 0 1\""));
    assert!(xml.contains("Origin=\"0.0005 0 -0.001\""));
    assert!(xml.contains("Name=\"width_m\""));
    assert!(
        xml.contains(&format!(" {}", 1.0 / 3.0)),
        "a third to the bit"
    );
    assert!(xml.contains("NumberOfComponents=\"3\""));
    let short = [GridArray {
        name: "density_kg_m3",
        components: 1,
        values: &density[..5],
    }];
    let bad = GridFields {
        arrays: &short,
        ..grid
    };
    assert!(matches!(
        write_grid_vti(&path, &bad),
        Err(OutputError::InvalidData { .. })
    ));
    let nan = [f64::NAN; 6];
    let with_nan = [GridArray {
        name: "pressure_Pa",
        components: 1,
        values: &nan,
    }];
    let bad = GridFields {
        arrays: &with_nan,
        ..grid
    };
    let error = write_grid_vti(&path, &bad).unwrap_err().to_string();
    assert!(error.contains("pressure_Pa"), "{error}");
}

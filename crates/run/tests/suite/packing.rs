//! Starting a run from a packing file instead of the fill (`read_packing`,
//! `run_case_from` with `Start::Packing`; docs/user-guide.md §5).
//!
//! A CSV and a VTU of the same particles read back to the same numbers bit for bit and start
//! the same run, as does a CSV of a one-component case without its `material` column; every
//! malformed or misfitting file is refused with a message that names the file, the line
//! (CSV) or the point or array value (VTU), the value and what is allowed.

use std::path::{Path, PathBuf};

use proptest::prelude::*;

use crate::tiny_hopper;

use case::parse_case;
use files::StopReason;
use files::{write_particles_vtu, ParticleFields};
use files::{StartKind, SUMMARY_FILE};
use run::{read_packing, PackedParticle, Packing};
use run::{run_case_from, RunOptions, RunOutcome, Start};
use tiny_hopper::{read, tiny_case};

/// 250 spheres of the tiny hopper on a square lattice 1 % wider than a diameter, from
/// 0.1 mm above the floor and the left wall: at rest and touching nothing, so the run
/// settles them onto each other.
fn lattice() -> Vec<PackedParticle> {
    let (r, spacing, thickness) = (1.5e-3, 3.03e-3, 3.03e-3);
    (0..250)
        .map(|k| PackedParticle {
            position: dem::DVec3::new(
                -0.025 + r + 1e-4 + (k % 16) as f64 * spacing,
                0.5 * thickness,
                r + 1e-4 + (k / 16) as f64 * spacing,
            ),
            radius: r,
        })
        .collect()
}

/// The CSV of `particles`, with the columns in the order `header` names them and numbers in
/// their shortest exact form.
fn csv_text(particles: &[PackedParticle], header: &[&str]) -> String {
    let mut text = format!("# a lattice\n{}\n", header.join(", "));
    for p in particles {
        let fields: Vec<String> = header
            .iter()
            .map(|column| match column.to_ascii_lowercase().as_str() {
                "x" => format!("{:?}", p.position.x),
                "y" => format!("{:?}", p.position.y),
                "z" => format!("{:?}", p.position.z),
                "radius" => format!("{:?}", p.radius),
                _ => "glass".to_string(),
            })
            .collect();
        text.push_str(&fields.join(", "));
        text.push('\n');
    }
    text
}

/// Writes particles at rest as a hopperflow VTU snapshot at `path`: centres [m], radii [m]
/// and, for a mixture, each particle's component index.
fn write_vtu(path: &Path, positions: &[[f64; 3]], radii: &[f64], components: Option<&[u8]>) {
    let zeros = vec![[0.0; 3]; positions.len()];
    let ids: Vec<u64> = (0..positions.len() as u64).collect();
    write_particles_vtu(
        path,
        &ParticleFields {
            ids: &ids,
            positions,
            radii,
            velocities: &zeros,
            angular_velocities: &zeros,
            components,
            bodies: None,
        },
        0.0,
    )
    .expect("the VTU writer");
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("writable scratch file");
    path
}

#[test]
fn a_csv_and_a_vtu_of_one_packing_read_back_exactly_and_start_the_same_run() {
    let root = tempfile::tempdir().expect("temporary directory");
    let case = tiny_case(&[]);
    let particles = lattice();
    let csv = write(
        root.path(),
        "lattice.csv",
        &csv_text(&particles, &["x", "y", "z", "radius", "material"]),
    );
    let reordered = write(
        root.path(),
        "reordered.csv",
        &csv_text(&particles, &["material", "radius", "z", "y", "x"]),
    );
    let vtu = root.path().join("lattice.vtu");
    let positions: Vec<[f64; 3]> = particles.iter().map(|p| p.position.to_array()).collect();
    let radii: Vec<f64> = particles.iter().map(|p| p.radius).collect();
    write_vtu(&vtu, &positions, &radii, None);

    // Every number comes back with the bits it was written with.
    let from_csv = read_packing(&csv, &case).expect("the CSV packing is valid");
    assert_eq!(from_csv.particles(), &particles[..]);
    assert_eq!(from_csv.material(), Some("glass"));
    // A case of one component needs no material column: it names nothing the case lacks.
    let unlabelled = write(
        root.path(),
        "unlabelled.csv",
        &csv_text(&particles, &["x", "y", "z", "radius"]),
    );
    let from_unlabelled = read_packing(&unlabelled, &case).expect("no material column");
    assert_eq!(from_unlabelled.particles(), &particles[..]);
    assert_eq!(from_unlabelled.material(), None);
    let from_reordered = read_packing(&reordered, &case).expect("columns in any order");
    assert_eq!(from_reordered.particles(), &particles[..]);
    // A spreadsheet's byte-order mark and upper-case names change nothing.
    let marked = write(
        root.path(),
        "marked.csv",
        &format!(
            "\u{feff}{}",
            csv_text(&particles, &["X", "Y", "Z", "Radius", "Material"])
        ),
    );
    let from_marked = read_packing(&marked, &case).expect("a byte-order mark");
    assert_eq!(from_marked.particles(), &particles[..]);
    let from_vtu = read_packing(&vtu, &case).expect("the VTU packing is valid");
    assert_eq!(from_vtu.particles(), &particles[..]);
    assert_eq!(from_vtu.material(), None);
    assert_ne!(
        from_csv.sha256(),
        from_vtu.sha256(),
        "two files, two identities"
    );

    // The same particles start the same run, whichever file they came from.
    let options = RunOptions {
        resume: false,
        ..RunOptions::default()
    };
    let mut summaries = Vec::new();
    for (packing, out) in [
        (from_csv, "csv-run"),
        (from_vtu, "vtu-run"),
        (from_unlabelled, "unlabelled-run"),
    ] {
        let sha = packing.sha256().to_string();
        let started = std::time::Instant::now();
        let outcome = run_case_from(
            &case,
            &root.path().join(out),
            &options,
            &Start::Packing(Box::new(packing)),
        )
        .expect("the packing runs");
        eprintln!(
            "run from the packing: {:.1} s wall",
            started.elapsed().as_secs_f64()
        );
        let RunOutcome::Finished(summary) = outcome else {
            panic!("interrupted without a chunk limit")
        };
        let start = summary.start.clone().expect("the start is recorded");
        assert_eq!((start.kind, start.sha256), (StartKind::Packing, sha));
        summaries.push(summary);
    }
    for name in [
        "flow.csv",
        "crossings.csv",
        "remaining.csv",
        "wall_forces.csv",
    ] {
        let reference = read(&root.path().join("csv-run"), name);
        for other in ["vtu-run", "unlabelled-run"] {
            assert!(
                reference == read(&root.path().join(other), name),
                "{name} differs between the CSV start and the {other}"
            );
        }
    }
    // The summaries differ only in the start's file identity (the files' bytes differ).
    let without_start = |s: &files::CaseSummary| {
        let mut value = serde_json::to_value(s).expect("a summary serialises");
        value["start"] = serde_json::Value::Null;
        value
    };
    assert_eq!(without_start(&summaries[0]), without_start(&summaries[2]));
    // start.json records the one material name when the file gives it, and none otherwise.
    let start_of = |out: &str| -> serde_json::Value {
        serde_json::from_slice(&read(&root.path().join(out), "start.json")).expect("JSON")
    };
    assert_eq!(start_of("csv-run")["material"], "glass");
    assert_eq!(
        start_of("unlabelled-run").get("material"),
        None,
        "{}",
        start_of("unlabelled-run")
    );
    let s = &summaries[0];
    assert!(s.settled, "the lattice settles below the threshold");
    // The settling is checked from 0.05 s on (as after a fill), and the lattice falls
    // through its 1 % gaps in a few ms, so it settles soon after.
    assert!(
        (0.05..0.15).contains(&s.fill_time),
        "settled after {} s",
        s.fill_time
    );
    assert!(s.discharged_mass > 0.0 && s.particles == 250);
    assert!(root.path().join("csv-run").join(SUMMARY_FILE).is_file());
}

/// The message `read_packing` gives for `text` in a file `name` under the case with `sets`.
fn refusal(dir: &Path, name: &str, text: &str, sets: &[&str]) -> String {
    let path = write(dir, name, text);
    let case = tiny_case(sets);
    match read_packing(&path, &case) {
        Ok(p) => panic!("{name} was accepted: {} particles", p.particles().len()),
        Err(e) => e.to_string(),
    }
}

fn assert_names(message: &str, fragments: &[&str]) {
    for fragment in fragments {
        assert!(
            message.contains(fragment),
            "`{fragment}` missing from:\n{message}"
        );
    }
}

/// Three spheres of the tiny hopper side by side on the mid-plane, 10 mm above the floor.
const GOOD_ROWS: [&str; 3] = [
    "-0.01,0.001515,0.01,0.0015,glass",
    "0.0,0.001515,0.01,0.0015,glass",
    "0.01,0.001515,0.01,0.0015,glass",
];

/// A CSV of the good rows with row `k` (0-based) replaced by `row`.
fn with_row(k: usize, row: &str) -> String {
    let mut rows = GOOD_ROWS.map(str::to_string);
    rows[k] = row.to_string();
    format!("x,y,z,radius,material\n{}\n", rows.join("\n"))
}

#[test]
fn each_bad_packing_csv_is_refused_naming_file_line_value_and_range() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = root.path();
    let three = ["particles.count=3"];
    let path = |name: &str| dir.join(name).display().to_string();

    // The good rows pass: every refusal below is the one row's doing.
    let good = write(dir, "good.csv", &with_row(0, GOOD_ROWS[0]));
    read_packing(&good, &tiny_case(&three)).expect("the good rows");

    let m = refusal(dir, "empty.csv", "", &three);
    assert_names(
        &m,
        &[&path("empty.csv"), "is empty", "x,y,z,radius,material"],
    );
    let m = refusal(dir, "comments.csv", "# nothing but a comment\n", &three);
    assert_names(&m, &["is empty"]);
    let m = refusal(dir, "header.csv", "x,y,z,radius,material\n", &three);
    assert_names(&m, &["has a header but no particles"]);
    let m = refusal(dir, "lacks.csv", "x,y,z,material\n0,0,0,glass\n", &three);
    assert_names(
        &m,
        &[
            &format!("{} line 1:", path("lacks.csv")),
            "lacks the column(s) radius",
            "found: x, y, z, material",
        ],
    );
    // Without a material column (a case of one component) the good rows pass as well, and
    // the header it has is the one the rows are held to.
    let bare = GOOD_ROWS.map(|row| row.trim_end_matches(",glass").to_string());
    let unlabelled = write(
        dir,
        "unlabelled.csv",
        &format!("x,y,z,radius\n{}\n", bare.join("\n")),
    );
    read_packing(&unlabelled, &tiny_case(&three)).expect("the good rows, no material");
    let m = refusal(
        dir,
        "ragged.csv",
        &format!(
            "x,y,z,radius\n{}\n{}\n",
            bare[0..2].join("\n"),
            GOOD_ROWS[2]
        ),
        &three,
    );
    assert_names(
        &m,
        &[&format!(
            "{} line 4: has 5 fields, the header has 4 (x, y, z, radius)",
            path("ragged.csv")
        )],
    );
    let m = refusal(dir, "bare.csv", "x,y,z\n0,0,0\n", &three);
    assert_names(
        &m,
        &[
            "line 1:",
            "lacks the column(s) radius",
            "material for a mixture",
            "found: x, y, z",
        ],
    );
    let m = refusal(dir, "extra.csv", "x,y,z,radius,material,vx\n", &three);
    assert_names(
        &m,
        &["line 1: unknown column `vx`", "no velocities are read"],
    );
    let m = refusal(dir, "twice.csv", "x,y,z,radius,material,x\n", &three);
    assert_names(&m, &["line 1: column `x` appears twice"]);

    let m = refusal(
        dir,
        "word.csv",
        &with_row(1, "0.0,abc,0.01,0.0015,glass"),
        &three,
    );
    assert_names(
        &m,
        &[&format!(
            "{} line 3: y `abc` is not a number",
            path("word.csv")
        )],
    );
    let m = refusal(
        dir,
        "blank.csv",
        &with_row(0, "-0.01,,0.01,0.0015,glass"),
        &three,
    );
    assert_names(&m, &["line 2: y is empty"]);
    let m = refusal(
        dir,
        "nan.csv",
        &with_row(0, "NaN,0.001515,0.01,0.0015,glass"),
        &three,
    );
    assert_names(&m, &["line 2: x = NaN is not finite"]);
    let m = refusal(
        dir,
        "inf.csv",
        &with_row(2, "0.01,0.001515,0.01,inf,glass"),
        &three,
    );
    assert_names(&m, &["line 4: radius = inf must be finite and > 0 [m]"]);
    let m = refusal(
        dir,
        "neg.csv",
        &with_row(0, "-0.01,0.001515,0.01,-0.0015,glass"),
        &three,
    );
    assert_names(&m, &["line 2: radius = -0.0015 must be finite and > 0 [m]"]);
    let m = refusal(
        dir,
        "size.csv",
        &with_row(0, "-0.01,0.001515,0.01,0.002,glass"),
        &three,
    );
    assert_names(
        &m,
        &[
            "line 2: radius = 0.002 m is outside the case's radii [0.0015, 0.0015] m",
            "0.01 % tolerance",
        ],
    );
    let m = refusal(
        dir,
        "fields.csv",
        &with_row(0, "-0.01,0.001515,0.01,0.0015"),
        &three,
    );
    assert_names(&m, &["line 2: has 4 fields, the header has 5"]);
    let m = refusal(
        dir,
        "two.csv",
        &with_row(1, "0.0,0.001515,0.01,0.0015,steel"),
        &three,
    );
    assert_names(
        &m,
        &[
            "line 3: material `steel` differs from `glass` (line 2)",
            "one particle material",
        ],
    );
    let m = refusal(
        dir,
        "nameless.csv",
        &with_row(0, "-0.01,0.001515,0.01,0.0015,"),
        &three,
    );
    assert_names(&m, &["line 2: material is empty"]);

    // Outside the slab: beyond a side wall, through the floor, across the slab.
    let m = refusal(
        dir,
        "wall.csv",
        &with_row(2, "0.0245,0.001515,0.01,0.0015,glass"),
        &three,
    );
    assert_names(
        &m,
        &[
            "line 4: the particle at (x, y, z) = (0.0245, 0.001515, 0.01) m of radius 0.0015 m lies outside the slab",
            "x must lie in [-2.351500e-2, 2.351500e-2] m between the side walls at x = ±0.025 m",
            "at most 1 % of its radius",
        ],
    );
    let m = refusal(
        dir,
        "floor.csv",
        &with_row(0, "-0.01,0.001515,0.001,0.0015,glass"),
        &three,
    );
    assert_names(
        &m,
        &[
            "line 2:",
            "z must lie in [1.485000e-3, 9.851500e-2] m above the orifice plane",
        ],
    );
    let m = refusal(
        dir,
        "across.csv",
        &with_row(0, "-0.01,0.0025,0.01,0.0015,glass"),
        &three,
    );
    assert_names(&m, &["line 2:", "y must lie in", "front and back walls"]);
    // Two spheres 2 mm apart overlap by 1 mm, two thirds of a radius.
    let m = refusal(
        dir,
        "overlap.csv",
        &with_row(1, "-0.008,0.001515,0.01,0.0015,glass"),
        &three,
    );
    assert_names(
        &m,
        &["line 3: overlaps the particle of line 2 by 1.000000e-3 m, 66.667 % of the smaller radius; at most 1 % is allowed"],
    );
    // A count other than the case's.
    let m = refusal(
        dir,
        "count.csv",
        &with_row(0, GOOD_ROWS[0]),
        &["particles.count=4"],
    );
    assert_names(
        &m,
        &[
            "holds 3 particles; the case has particles.count = 4",
            "--set particles.count=3",
        ],
    );

    // Past twenty problems the rest are counted.
    let many = format!(
        "x,y,z,radius,material\n{}",
        "0,0.001515,0.05,-1,glass\n".repeat(25)
    );
    let m = refusal(dir, "many.csv", &many, &["particles.count=25"]);
    assert_eq!(m.lines().count(), 21, "{m}");
    assert_names(&m, &["line 21: radius = -1", "and 5 more problems"]);

    let m = refusal(dir, "packing.txt", "x,y,z,radius,material\n", &three);
    assert_names(
        &m,
        &["unknown packing format (extension `.txt`)", ".csv", ".vtu"],
    );
    let missing = dir.join("missing.csv");
    let err = read_packing(&missing, &tiny_case(&three)).unwrap_err();
    assert_names(
        &err.to_string(),
        &[&missing.display().to_string(), "cannot be read"],
    );
}

#[test]
fn a_particle_outside_a_silo_is_refused_naming_the_wall_it_crosses() {
    let root = tempfile::tempdir().expect("temporary directory");
    let silo = r#"
[geometry]
kind = "cylinder"
radius = 0.02
height = 0.05
outlet_diameter = 0.01
hopper_angle_deg = 45.0

[particles]
count = 1
diameter = 0.002
"#;
    let case = parse_case(silo, "silo.toml", &[]).expect("a valid silo");
    let check = |name: &str, row: &str| {
        let path = write(
            root.path(),
            name,
            &format!("x,y,z,radius,material\n{row}\n"),
        );
        read_packing(&path, &case)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    check("inside.csv", "0.0,0.0,0.03,0.001,m1").expect("on the axis, above the cone");
    let m = check("cylinder.csv", "0.014,0.014,0.03,0.001,m1").unwrap_err();
    assert_names(
        &m,
        &[
            "line 2:",
            "lies outside the cylinder",
            "distance from the axis",
        ],
    );
    // At z = 5 mm the cone's radius is 10 mm: 9 mm from the axis is inside it but closer to
    // it than the sphere's radius.
    let m = check("cone.csv", "0.009,0.0,0.005,0.001,m1").unwrap_err();
    assert_names(&m, &["line 2:", "inside the cone (half-angle 45°)"]);
}

/// A VTU file of three points with the `position` and `radius` arrays given.
fn vtu(positions: &str, radius_array: &str) -> String {
    format!(
        r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <UnstructuredGrid>
    <Piece NumberOfPoints="3" NumberOfCells="0">
      <PointData Scalars="radius">
        <DataArray type="Int64" Name="id" format="ascii">0 1 2</DataArray>
        {radius_array}
      </PointData>
      <Points>
        <DataArray type="Float64" Name="position" NumberOfComponents="3" format="ascii">
          {positions}
        </DataArray>
      </Points>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
"#
    )
}

const GOOD_POSITIONS: &str = "-0.01 0.001515 0.01 0.0 0.001515 0.01 0.01 0.001515 0.01";
const GOOD_RADII: &str =
    r#"<DataArray type="Float64" Name="radius" format="ascii">0.0015 0.0015 0.0015</DataArray>"#;

#[test]
fn each_bad_packing_vtu_is_refused_naming_the_array_or_point() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = root.path();
    let three = ["particles.count=3"];
    let good = write(dir, "good.vtu", &vtu(GOOD_POSITIONS, GOOD_RADII));
    let packing: Packing = read_packing(&good, &tiny_case(&three)).expect("the good VTU");
    assert_eq!(packing.particles()[2].position.x, 0.01);

    let binary = r#"<DataArray type="Float64" Name="radius" format="binary">AAAA</DataArray>"#;
    let m = refusal(dir, "binary.vtu", &vtu(GOOD_POSITIONS, binary), &three);
    assert_names(
        &m,
        &[
            &dir.join("binary.vtu").display().to_string(),
            "array `radius` is stored as `binary`",
            "Data Mode `Ascii`",
        ],
    );
    let appended = r#"<DataArray type="Float64" Name="radius" format="appended" offset="0"/>"#;
    let m = refusal(dir, "appended.vtu", &vtu(GOOD_POSITIONS, appended), &three);
    assert_names(&m, &["array `radius` is stored as `appended`"]);
    let m = refusal(dir, "noradius.vtu", &vtu(GOOD_POSITIONS, ""), &three);
    assert_names(
        &m,
        &["no point-data array named `radius` (its point data: id)"],
    );
    let short =
        r#"<DataArray type="Float64" Name="radius" format="ascii">0.0015 0.0015</DataArray>"#;
    let m = refusal(dir, "short.vtu", &vtu(GOOD_POSITIONS, short), &three);
    assert_names(
        &m,
        &["array `radius` holds 2 values; NumberOfPoints = 3 needs 1 per point"],
    );
    let word = "-0.01 0.001515 0.01 0.0 x 0.01 0.01 0.001515 0.01";
    let m = refusal(dir, "word.vtu", &vtu(word, GOOD_RADII), &three);
    assert_names(&m, &["array `position` value 4: `x` is not a number"]);
    let nan = "-0.01 0.001515 0.01 0.0 0.001515 nan 0.01 0.001515 0.01";
    let m = refusal(dir, "nan.vtu", &vtu(nan, GOOD_RADII), &three);
    assert_names(&m, &["point 1: z = NaN is not finite"]);
    let negative =
        r#"<DataArray type="Float64" Name="radius" format="ascii">0.0015 0 0.0015</DataArray>"#;
    let m = refusal(dir, "zero.vtu", &vtu(GOOD_POSITIONS, negative), &three);
    assert_names(&m, &["point 1: radius = 0 must be finite and > 0 [m]"]);
    let outside = "-0.01 0.001515 0.01 0.0 0.001515 0.2 0.01 0.001515 0.01";
    let m = refusal(dir, "outside.vtu", &vtu(outside, GOOD_RADII), &three);
    assert_names(&m, &["point 1: the particle at", "z must lie in"]);
    let compressed = vtu(GOOD_POSITIONS, GOOD_RADII).replace(
        "header_type=\"UInt64\"",
        "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
    );
    let m = refusal(dir, "zlib.vtu", &compressed, &three);
    assert_names(&m, &["is compressed (vtkZLibDataCompressor)"]);
    let m = refusal(dir, "plain.vtu", "x y z\n", &three);
    assert_names(&m, &["is not a VTK XML file"]);
    let two = vtu(GOOD_POSITIONS, GOOD_RADII)
        .replace("</Piece>", "</Piece><Piece NumberOfPoints=\"0\"></Piece>");
    let m = refusal(dir, "pieces.vtu", &two, &three);
    assert_names(&m, &["has 2 pieces"]);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Whatever a file holds, reading it as a packing returns a packing or its problems:
    /// never a panic, whether the bytes are random or a damaged valid file (a VTU or CSV cut
    /// somewhere and spliced with text of its own alphabet).
    #[test]
    fn no_file_makes_the_packing_reader_panic(
        bytes in proptest::collection::vec(any::<u8>(), 0..400),
        cut in 0usize..1000,
        splice in "[ 0-9a-z.,<>=\"/\n-]{0,40}",
    ) {
        let root = tempfile::tempdir().expect("temporary directory");
        let case = tiny_case(&["particles.count=3"]);
        let good_vtu = vtu(GOOD_POSITIONS, GOOD_RADII);
        let good_csv = with_row(0, GOOD_ROWS[0]);
        let damaged = |text: &str| {
            let mut k = cut.min(text.len());
            while !text.is_char_boundary(k) {
                k -= 1;
            }
            let rest = (k + 10).min(text.len());
            format!("{}{splice}{}", &text[..k], &text[rest..])
        };
        for (name, content) in [
            ("random.csv", bytes.clone()),
            ("random.vtu", bytes.clone()),
            ("damaged.vtu", damaged(&good_vtu).into_bytes()),
            ("damaged.csv", damaged(&good_csv).into_bytes()),
        ] {
            let path = root.path().join(name);
            std::fs::write(&path, content).unwrap();
            let _ = read_packing(&path, &case);
        }
    }
}

/// The benchmark's material table as cases/README.md writes it, between its markers.
fn benchmark_materials() -> String {
    let readme = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../cases/README.md"
    ))
    .expect("cases/README.md");
    let block = &readme[readme
        .find("<!-- dosta2024-table -->")
        .expect("the table's marker")..];
    let body = &block[block.find("```toml\n").expect("a TOML block") + 8..];
    body[..body.find("```").expect("the block's end")].to_string()
}

/// A small cylindrical silo (R = 16 mm, a 45° cone to a 16 mm orifice, 50 mm tall) holding
/// `count` spheres of two components: `big`, 4 mm spheres of M1 (2500 kg/m³), and `fine`,
/// 2 mm spheres of M2 (2000 kg/m³), in steel walls.
fn mixture_case(count: usize) -> case::Case {
    let text = format!(
        r#"version = 1
seed = 3
{table}
[geometry]
kind = "cylinder"
radius = 0.016
height = 0.05
outlet_diameter = 0.016
hopper_angle_deg = 45.0

[wall]
material = "steel"

[particles]
count = {count}
fraction_by = "number"

[[particles.components]]
name = "big"
diameter = 0.004
material = "M1"
fraction = 0.5

[[particles.components]]
name = "fine"
diameter = 0.002
material = "M2"
fraction = 0.5

[time]
time_step = 2.0e-6

[protocol]
settle_kinetic_energy = 1.0e-8
max_settle_time = 0.15
clog_timeout = 0.1
time_limit = 1.0

[output]
plots = true
checkpoint_interval = 0.0
vtu_interval = 0.2
"#,
        table = benchmark_materials()
    );
    parse_case(&text, "mixture.toml", &[])
        .unwrap_or_else(|e| panic!("the mixture case is valid: {e}"))
}

/// A packing of the mixture case's silo: square layers of `big` spheres (4 mm) above the
/// cone, then layers of `fine` ones (2 mm) above them, each sphere 0.1 mm clear of its
/// neighbours and the wall. Rows: (x, y, z, radius, label).
fn mixture_packing() -> Vec<(f64, f64, f64, f64, &'static str)> {
    let mut rows = Vec::new();
    let silo_radius: f64 = 0.016;
    // The cone meets the cylinder at z = R − D/2 = 8 mm; the layers start above it.
    let mut z = 0.0085;
    for (radius, label, layers) in [(0.002_f64, "big", 2), (0.001_f64, "fine", 2)] {
        let spacing = 2.0 * radius + 1.0e-4;
        z += radius;
        for _ in 0..layers {
            let n = (silo_radius / spacing).ceil() as i32;
            for i in -n..=n {
                for j in -n..=n {
                    let (x, y) = (f64::from(i) * spacing, f64::from(j) * spacing);
                    if x.hypot(y) + radius + 1.0e-4 <= silo_radius {
                        rows.push((x, y, z, radius, label));
                    }
                }
            }
            z += spacing;
        }
        z += 1.0e-4 - radius;
    }
    rows
}

fn mixture_csv(rows: &[(f64, f64, f64, f64, &str)]) -> String {
    let mut text = String::from("x,y,z,radius,material\n");
    for (x, y, z, r, label) in rows {
        text.push_str(&format!("{x:?},{y:?},{z:?},{r:?},{label}\n"));
    }
    text
}

#[test]
fn a_mixture_starts_from_a_csv_naming_each_particles_component() {
    let root = tempfile::tempdir().expect("temporary directory");
    let rows = mixture_packing();
    let bigs = rows.iter().filter(|r| r.4 == "big").count();
    let fines = rows.len() - bigs;
    assert!(
        bigs > 20 && fines > 100,
        "{bigs} big and {fines} fine spheres"
    );
    let case = mixture_case(rows.len());
    let path = write(root.path(), "mixture.csv", &mixture_csv(&rows));
    let packing = read_packing(&path, &case).unwrap_or_else(|e| panic!("{e}"));
    // Components by index into particles.components, in file order: big = 0, fine = 1.
    let expected: Vec<u8> = rows.iter().map(|r| u8::from(r.4 == "fine")).collect();
    assert_eq!(packing.components(), &expected[..]);
    assert_eq!(packing.material(), None);

    // A component may also be named by its material when no other is made of it.
    let by_material = mixture_csv(
        &rows
            .iter()
            .map(|&(x, y, z, r, label)| (x, y, z, r, if label == "big" { "M1" } else { "M2" }))
            .collect::<Vec<_>>(),
    );
    let again = read_packing(&write(root.path(), "m.csv", &by_material), &case)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(again.components(), packing.components());

    // The run: every particle has its component's material, so each crossing's density is
    // its component's (M1 2500, M2 2000 kg/m³), and composition.csv counts the components.
    let out = root.path().join("run");
    let options = RunOptions {
        // Pictures on (and plots in the case): the particle snapshots are among them.
        pictures: true,
        ..RunOptions::default()
    };
    let outcome = run_case_from(&case, &out, &options, &Start::Packing(Box::new(packing)))
        .unwrap_or_else(|e| panic!("{e}"));
    let RunOutcome::Finished(summary) = outcome else {
        panic!("the run finished")
    };
    let crossings = String::from_utf8(read(&out, "crossings.csv")).expect("UTF-8");
    let mut lines = crossings.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    let at = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("crossings.csv lacks {name}: {header:?}"))
    };
    let (density, component) = (at("material_density_kg_per_m3"), at("component"));
    let mass = at("mass_kg");
    let (mut seen, mut left) = ((0, 0), (0.0, 0.0));
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let rho: f64 = cells[density].parse().expect("a density");
        let m: f64 = cells[mass].parse().expect("a mass");
        match cells[component] {
            "big" => {
                assert_eq!(rho, 2500.0, "{line}");
                seen.0 += 1;
                left.0 += m;
            }
            "fine" => {
                assert_eq!(rho, 2000.0, "{line}");
                seen.1 += 1;
                left.1 += m;
            }
            other => panic!("crossing of component `{other}`: {line}"),
        }
    }
    // Each component's particles are conserved from the packing to the outlet: the silo
    // empties, and every particle placed leaves once, under its own component.
    assert_eq!(summary.stop_reason, StopReason::Empty);
    assert_eq!(
        seen,
        (bigs, fines),
        "crossings by component of {bigs}, {fines}"
    );
    // So is each component's mass: its crossings' masses add up to the count placed times
    // the component's particle mass (M1 2500, M2 2000 kg/m³), to the rounding of the sums
    // (a few hundred additions of like numbers: 1e-12 relative).
    let sphere = |d: f64, rho: f64| rho * std::f64::consts::PI / 6.0 * d * d * d;
    let placed = (
        bigs as f64 * sphere(0.004, 2500.0),
        fines as f64 * sphere(0.002, 2000.0),
    );
    assert!(
        (left.0 - placed.0).abs() <= 1e-12 * placed.0
            && (left.1 - placed.1).abs() <= 1e-12 * placed.1,
        "left {left:?} kg, placed {placed:?} kg"
    );
    let start: serde_json::Value =
        serde_json::from_slice(&read(&out, "start.json")).expect("start.json is JSON");
    assert_eq!(
        start["components"]["big"],
        serde_json::json!(bigs),
        "{start}"
    );
    assert_eq!(
        start["components"]["fine"],
        serde_json::json!(fines),
        "{start}"
    );

    // The run's first snapshot, taken while the bed settles, carries each particle's
    // component: it reads back as a packing of the same mixture, components in tag order.
    let mut snapshots: Vec<PathBuf> = std::fs::read_dir(out.join("snapshots"))
        .expect("snapshots")
        .map(|e| e.expect("an entry").path())
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("particles_"))
        })
        .collect();
    snapshots.sort();
    let first = snapshots.first().expect("a particle snapshot");
    let snapshot = read_packing(first, &case).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(snapshot.components(), &expected[..]);
}

#[test]
fn a_mixture_packing_that_misnames_or_missizes_a_component_is_refused() {
    let root = tempfile::tempdir().expect("temporary directory");
    let rows = mixture_packing();
    let case = mixture_case(rows.len());
    let refuse = |name: &str, text: &str| -> String {
        let path = write(root.path(), name, text);
        read_packing(&path, &case)
            .map(|_| ())
            .expect_err("refused")
            .to_string()
    };
    // Line 1 is the header, so particle k is on line k + 2.
    let mut named = rows.clone();
    named[5].4 = "sand";
    let message = refuse("sand.csv", &mixture_csv(&named));
    assert_names(
        &message,
        &[
            "sand.csv line 7",
            "material `sand` names no component",
            "`big`, `fine`",
        ],
    );
    // A 4 mm sphere called fine: outside fine's radii, though inside the case's.
    let mut sized = rows.clone();
    sized[0].4 = "fine";
    let message = refuse("sized.csv", &mixture_csv(&sized));
    assert_names(
        &message,
        &[
            "sized.csv line 2",
            "radius = 0.002 m",
            "component `fine`'s radii [0.001, 0.001]",
        ],
    );
    // A CSV without the material column names no component: refused at its header.
    let unlabelled = rows
        .iter()
        .map(|(x, y, z, r, _)| format!("{x:?},{y:?},{z:?},{r:?}\n"))
        .collect::<String>();
    let message = refuse("unlabelled.csv", &format!("x,y,z,radius\n{unlabelled}"));
    assert_names(
        &message,
        &[
            "unlabelled.csv line 1: the header has no column `material`",
            "a mixture of 2 components (particles.components: `big`, `fine`)",
        ],
    );
    assert_eq!(
        message.lines().count(),
        1,
        "one problem, at the header:\n{message}"
    );
    // A VTU names no component.
    let vtu = root.path().join("mixture.vtu");
    let positions: Vec<[f64; 3]> = rows.iter().map(|r| [r.0, r.1, r.2]).collect();
    let radii: Vec<f64> = rows.iter().map(|r| r.3).collect();
    write_vtu(&vtu, &positions, &radii, None);
    let message = read_packing(&vtu, &case)
        .map(|_| ())
        .expect_err("refused")
        .to_string();
    assert_names(
        &message,
        &[
            "mixture.vtu",
            "gives no particle its component",
            "CSV packing",
            "`component` point-data array",
        ],
    );
    // With the array, each index must be a component's: 0 or 1 here.
    let mut indices: Vec<u8> = rows.iter().map(|r| u8::from(r.4 == "fine")).collect();
    indices[3] = 2;
    write_vtu(&vtu, &positions, &radii, Some(&indices));
    let message = read_packing(&vtu, &case)
        .map(|_| ())
        .expect_err("refused")
        .to_string();
    assert_names(
        &message,
        &[
            "mixture.vtu point 3",
            "component = 2 is not a component of the case",
            "from 0 to 1",
        ],
    );
}

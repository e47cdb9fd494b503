//! Case files of the rectangular silo (`kind = "box"`) and of STL walls (`kind = "mesh"`):
//! templates, exact round trips of the resolved text, paths taken from the case file's folder,
//! and the refusals that need files (the bad cases in `tests/data/bad_cases/` cover the rest).

use std::path::Path;

use case::{
    load_case, parse_case, template, template_files, Case, CuboidOutlet, ErrorKind, Geometry,
    MeshOutlet, WallSurface, BOX_TEMPLATE, DRAW_DOWN_TEMPLATE, HEAP_TEMPLATE, MESH_TEMPLATE,
};
use glam::DVec3;

/// Every key of `case`'s resolved text appears in `template` (live or commented out).
fn template_documents_every_key(case: &Case, template: &str) {
    for line in case.to_toml_string().lines() {
        let line = line.trim();
        if line.starts_with('#') || line.starts_with('[') || line.is_empty() {
            continue;
        }
        let key = line.split('=').next().unwrap().trim();
        assert!(
            template.contains(&format!("{key} =")),
            "template lacks key `{key}`"
        );
    }
}

/// The resolved text reads back to the same case, bit for bit.
fn round_trips(case: &Case) {
    let text = case.to_toml_string();
    let back = parse_case(&text, "resolved.toml", &[])
        .unwrap_or_else(|e| panic!("resolved text refused:\n{e}\n{text}"));
    assert_eq!(&back, case, "{text}");
    assert_eq!(back.to_toml_string(), text);
}

/// Writes ASCII STL `triangles` to `path`.
fn write_stl(path: &Path, triangles: &[stl::Triangle]) {
    let mut bytes = Vec::new();
    stl::write_ascii(&mut bytes, triangles, "wall").unwrap();
    std::fs::write(path, bytes).unwrap();
}

#[test]
fn box_template_is_valid_complete_and_round_trips() {
    let case = parse_case(BOX_TEMPLATE, "box.toml", &[]).expect("template must be valid");
    assert_eq!(template("box"), Some(BOX_TEMPLATE));
    let silo = case.geometry.cuboid().expect("a box case");
    assert_eq!(
        (silo.width, silo.depth, silo.outlet, silo.hopper_angle_deg),
        (0.1, 0.05, CuboidOutlet::Slot, 60.0)
    );
    template_documents_every_key(&case, BOX_TEMPLATE);
    round_trips(&case);
    // 4000 spheres of 3 mm at volume fraction 0.64 fill the 23 mm wedge and 4 mm above it.
    let h = case.fill_height().expect("they fit");
    assert!((h - 0.0269).abs() < 1e-4, "fill height {h}");
}

/// The calibration tests' templates read back to their kinds' defaults, document every key
/// of the resolved case, round-trip, and their fills fit: the heap's 2000 spheres stand
/// 2000 × (π/6)(3 mm)³/0.64 / (π (20 mm)²) = 35 mm high in its 80 mm cylinder.
#[test]
fn heap_and_draw_down_templates_are_valid_complete_and_round_trip() {
    let heap = parse_case(HEAP_TEMPLATE, "heap.toml", &[]).expect("heap template valid");
    assert_eq!(template("heap"), Some(HEAP_TEMPLATE));
    assert_eq!(heap.geometry.heap(), Some(&case::HeapGeometry::example()));
    template_documents_every_key(&heap, HEAP_TEMPLATE);
    round_trips(&heap);
    let h = heap.fill_height().expect("they fit");
    assert!((h - 0.0352).abs() < 1e-4, "fill height {h}");

    let box_test = parse_case(DRAW_DOWN_TEMPLATE, "dd.toml", &[]).expect("draw-down valid");
    assert_eq!(template("draw-down"), Some(DRAW_DOWN_TEMPLATE));
    assert_eq!(template("draw_down"), Some(DRAW_DOWN_TEMPLATE));
    let g = box_test.geometry.draw_down().expect("a draw-down case");
    assert_eq!(g, &case::DrawDownGeometry::example());
    // The box it builds: a flat floor and a slot centred across the whole depth.
    let container = box_test.geometry.rectangular().expect("a box");
    assert_eq!(
        (
            container.hopper_angle_deg,
            container.outlet_offset,
            container.outlet
        ),
        (90.0, 0.0, CuboidOutlet::Slot)
    );
    template_documents_every_key(&box_test, DRAW_DOWN_TEMPLATE);
    round_trips(&box_test);

    // The example cases under cases/ are these templates below a line naming them.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../cases");
    for (file, text) in [
        ("repose.toml", HEAP_TEMPLATE),
        ("draw-down.toml", DRAW_DOWN_TEMPLATE),
    ] {
        let shipped = std::fs::read_to_string(root.join(file)).expect("the example case");
        let (first, rest) = shipped.split_once('\n').expect("a first line");
        assert!(first.starts_with(&format!("# {file}")), "{first}");
        assert_eq!(rest, text, "cases/{file} differs from its template");
    }
}

#[test]
fn box_variants_round_trip() {
    for geometry in [
        "outlet = \"square\"\nhopper_angle_deg = 45.0\ndepth = 0.06\nwalls = \"meshed\"",
        "outlet = \"square\"\nhopper_angle_deg = 90.0\noutlet_offset = -0.0123",
        "outlet = \"slot\"\nhopper_angle_deg = 90\noutlet_offset = 0.01\nwidth = 0.0999",
        "hopper_angle_deg = 75.5\noutlet_width = 0.0170001",
    ] {
        let text = format!(
            "version = 1\n[geometry]\nkind = \"box\"\n{geometry}\n[particles]\ncount = 500\n"
        );
        let case = parse_case(&text, "box.toml", &[]).unwrap_or_else(|e| panic!("{e}"));
        round_trips(&case);
    }
    let meshed = parse_case(
        "version = 1\n[geometry]\nkind = \"box\"\nwalls = \"meshed\"\n",
        "b.toml",
        &[],
    )
    .unwrap();
    assert_eq!(meshed.geometry.cuboid().unwrap().walls, WallSurface::Meshed);
}

#[test]
fn box_errors_name_key_line_value_and_range() {
    let text = "version = 1\n[geometry]\nkind = \"box\"\noutlet = \"hexagon\"\n\
                outlet_width = 0.002\nthickness = 0.003\n";
    let errors = parse_case(text, "box.toml", &[]).unwrap_err().to_string();
    for fragment in [
        "box.toml:4:1: geometry.outlet = \"hexagon\": must be one of \"slot\", \"square\"",
        "box.toml:6:1: geometry.thickness: unknown key; allowed here: kind, width, depth",
    ] {
        assert!(errors.contains(fragment), "lacks `{fragment}`:\n{errors}");
    }
    let small = parse_case(
        "version = 1\n[geometry]\nkind = \"box\"\noutlet_width = 0.005\n",
        "box.toml",
        &[],
    )
    .unwrap_err()
    .to_string();
    assert!(
        small.contains("box.toml:4:1: geometry.outlet_width = 0.005 m: must be ≥ 3 particle diameters (0.009 m)"),
        "{small}"
    );
}

/// The mesh template reads with the files `template_files` gives, written beside it; its
/// resolved text names them absolute and reads back to the same case wherever it is read.
#[test]
fn mesh_template_with_its_files_is_valid_complete_and_round_trips() {
    let dir = tempfile::tempdir().unwrap();
    // Without its files the template is refused, naming the first file's key.
    let alone = dir.path().join("alone");
    std::fs::create_dir(&alone).unwrap();
    std::fs::write(alone.join("case.toml"), MESH_TEMPLATE).unwrap();
    let refused = load_case(&alone.join("case.toml"), &[]).unwrap_err();
    assert!(
        refused
            .errors
            .iter()
            .any(|e| e.key == "geometry.walls[0].file"
                && e.kind == ErrorKind::Io
                && e.message.contains("silo_wall.stl")),
        "{refused}"
    );
    let files = template_files("mesh");
    assert_eq!(files.len(), 2);
    for (name, text) in &files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let path = dir.path().join("case.toml");
    std::fs::write(&path, MESH_TEMPLATE).unwrap();
    let case = load_case(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let mesh = case.geometry.mesh().expect("a mesh case");
    assert_eq!(mesh.walls.len(), 2);
    assert_eq!(mesh.walls[0].name, "cylinder");
    assert_eq!(mesh.walls[0].file, dir.path().join("silo_wall.stl"));
    // 48 segments of 2 triangles each; millimetres scaled to metres.
    assert_eq!(mesh.walls[0].triangles.len(), 96);
    let (lo, hi) = mesh.bounds();
    assert!(
        (hi[2] - 0.2).abs() < 1e-15 && lo[2].abs() < 1e-15,
        "{lo:?} {hi:?}"
    );
    assert_eq!(case.geometry.height(), 0.2);
    template_documents_every_key(&case, MESH_TEMPLATE);
    round_trips(&case);
    // From another folder, too: the paths are absolute.
    let elsewhere = tempfile::tempdir().unwrap();
    let copy = elsewhere.path().join("resolved.toml");
    std::fs::write(&copy, case.to_toml_string()).unwrap();
    assert_eq!(load_case(&copy, &[]).unwrap(), case);
}

/// Relative paths come from the case file's folder, transforms are applied in the stl
/// crate's order (scale, rotation, translation), and a rectangle outlet, odd file names and
/// every transform key survive the round trip.
#[test]
fn mesh_paths_transforms_and_rectangles_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let sub = dir.path().join("a dir with \"quotes\" and \\ slash");
    std::fs::create_dir(&sub).unwrap();
    // A 100 × 100 mm floor-like square in the x–z plane at y = 0, in millimetres.
    let square =
        stl::shapes::rectangle(DVec3::ZERO, 100.0 * DVec3::X, 100.0 * DVec3::Z, 2, 2).unwrap();
    write_stl(&sub.join("plate #1.stl"), &square);
    let case_text = "version = 1\n[geometry]\nkind = \"mesh\"\n\
        fill_min = [-0.02, 0.01, 0.01]\nfill_max = [0.02, 0.05, 0.09]\n\
        outlet = { shape = \"rectangle\", centre = [0.0, 0.03], size = [0.02, 0.015] }\n\
        [[geometry.walls]]\nfile = \"plate #1.stl\"\nscale = 0.001\n\
        rotate_axis = [0.0, 0.0, 2.0]\nrotate_deg = 90.0\ntranslate = [0.07, 0.0, 0.0]\n\
        [particles]\ncount = 100\n";
    let path = sub.join("case.toml");
    std::fs::write(&path, case_text).unwrap();
    let case = load_case(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let mesh = case.geometry.mesh().unwrap();
    // The stem is no wall name (a space and `#`): the default is wall_0.
    assert_eq!(mesh.walls[0].name, "wall_0");
    assert_eq!(mesh.walls[0].file, sub.join("plate #1.stl"));
    // Rotated 90° about z, the square lies in the plane x = 0.07, y from 0 to 0.1.
    for t in mesh.walls[0].triangles.iter() {
        for p in t {
            assert!((p.x - 0.07).abs() < 1e-15, "{p}");
            assert!(p.y > -1e-15 && p.y < 0.1 + 1e-15 && p.z >= 0.0, "{p}");
        }
    }
    assert_eq!(
        mesh.outlet,
        MeshOutlet::Rectangle {
            centre: [0.0, 0.03],
            size: [0.02, 0.015]
        }
    );
    assert_eq!(case.geometry.outlet_size(), 0.02);
    assert!(case.geometry.hopper_angle_deg().is_nan());
    round_trips(&case);
    let text = case.to_toml_string();
    assert!(text.contains("sha256 = \""), "{text}");
    // A case text read without a folder takes the current one: the absolute path still works.
    assert_eq!(parse_case(&text, "t.toml", &[]).unwrap(), case);
}

/// A case that gives the file's SHA-256 refuses the file once it has changed; the STL's own
/// messages come out under the file's key; a fill box cutting a triangle is refused.
#[test]
fn mesh_files_are_checked() {
    let dir = tempfile::tempdir().unwrap();
    let cone = stl::shapes::frustum_side(DVec3::ZERO, 0.04 * DVec3::Z, 0.01, 0.05, 24).unwrap();
    write_stl(&dir.path().join("cone.stl"), &cone);
    let write_case = |extra: &str, fill_max: &str| {
        let text = format!(
            "version = 1\n[geometry]\nkind = \"mesh\"\nfill_min = [-0.01, -0.01, 0.03]\n\
             fill_max = {fill_max}\noutlet = {{ shape = \"disc\", radius = 0.01 }}\n\
             [[geometry.walls]]\nfile = \"cone.stl\"\n{extra}\n[particles]\ncount = 50\n\
             diameter = 0.003\n"
        );
        let path = dir.path().join("case.toml");
        std::fs::write(&path, text).unwrap();
        load_case(&path, &[])
    };
    let case = write_case("", "[0.01, 0.01, 0.04]").unwrap_or_else(|e| panic!("{e}"));
    let sha = case.geometry.mesh().unwrap().walls[0].sha256.clone();
    assert_eq!(sha.len(), 64);
    assert!(write_case(&format!("sha256 = \"{sha}\""), "[0.01, 0.01, 0.04]").is_ok());
    // The same triangles rewritten in another order: another file.
    let mut reversed = cone.clone();
    reversed.reverse();
    write_stl(&dir.path().join("cone.stl"), &reversed);
    let changed = write_case(&format!("sha256 = \"{sha}\""), "[0.01, 0.01, 0.04]")
        .unwrap_err()
        .to_string();
    assert!(
        changed.contains("case.toml:9:1: geometry.walls[0].sha256")
            && changed.contains("the file changed since this case named it"),
        "{changed}"
    );
    // A box reaching above the cone's top rim (radius 50 mm at 40 mm) still clears it; one
    // 80 mm wide from 30 mm up, where the cone's radius is 40 mm, cuts it.
    assert!(write_case("", "[0.01, 0.01, 0.06]").is_ok());
    let cut = write_case("", "[0.04, 0.04, 0.04]")
        .unwrap_err()
        .to_string();
    assert!(
        cut.contains("case.toml:4:1: geometry.fill_min = [-0.01, -0.01, 0.03] m")
            && cut.contains("meets triangle")
            && cut.contains("of geometry.walls[0]")
            && cut.contains("must lie inside the walls"),
        "{cut}"
    );
    // A malformed STL: the reader's message, with the file and line, under the file's key.
    std::fs::write(
        dir.path().join("cone.stl"),
        "solid s\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 x\n",
    )
    .unwrap();
    let malformed = write_case("", "[0.01, 0.01, 0.04]").unwrap_err();
    let message = malformed.to_string();
    assert!(
        message.contains(
            "case.toml:8:1: geometry.walls[0].file = \"cone.stl\": not a usable STL wall: "
        ) && message.contains("cone.stl, line 5: `x` in vertex 2 of triangle 1"),
        "{message}"
    );
    assert_eq!(malformed.errors.len(), 1);
    // Particles are inserted below protocol.fill_top inside the box: it must reach the box.
    write_stl(&dir.path().join("cone.stl"), &cone);
    let low = write_case("[protocol]\nfill_top = 0.02", "[0.01, 0.01, 0.04]")
        .unwrap_err()
        .to_string();
    assert!(
        low.contains("case.toml:10:1: protocol.fill_top = 0.02 m: must be > the fill box's bottom, geometry.fill_min[2] = 0.03 m"),
        "{low}"
    );
}

/// The mesh kind's case keys feed the same checks as the other kinds: the outlet's size
/// against the particles, the fill box's corners.
#[test]
fn mesh_geometry_errors_name_their_keys() {
    let text = "version = 1\n[geometry]\nkind = \"mesh\"\nfill_min = [0.0, 0.0, -0.01]\n\
                fill_max = [0.001, 0.1, 0.1]\noutlet = { shape = \"disc\", radius = 0.004 }\n\
                [[geometry.walls]]\nfile = \"/no/such/wall.stl\"\n";
    let errors = parse_case(text, "m.toml", &[]).unwrap_err();
    let report = errors.to_string();
    for fragment in [
        "m.toml:4:1: geometry.fill_min = [0, 0, -0.01] m: z must be ≥ 0",
        "m.toml:5:1: geometry.fill_max = [0.001, 0.1, 0.1] m: x must exceed geometry.fill_min[0] = 0 m by more than the largest particle diameter (0.003 m)",
        "geometry.outlet.radius = 0.004 m: the diameter 2 × geometry.outlet.radius must be ≥ 3 particle diameters (0.009 m)",
        "m.toml:8:1: geometry.walls[0].file = \"/no/such/wall.stl\": cannot read the STL file: /no/such/wall.stl",
    ] {
        assert!(report.contains(fragment), "lacks `{fragment}`:\n{report}");
    }
    let missing = parse_case("version = 1\n[geometry]\nkind = \"mesh\"\n", "m.toml", &[])
        .unwrap_err()
        .to_string();
    for key in [
        "geometry.walls",
        "geometry.outlet",
        "geometry.fill_min",
        "geometry.fill_max",
    ] {
        assert!(
            missing.contains(&format!("{key}: required for geometry.kind = \"mesh\"")),
            "lacks {key}:\n{missing}"
        );
    }
    assert!(matches!(
        parse_case("version = 1\n", "b.toml", &[]).unwrap().geometry,
        Geometry::Slab(_)
    ));
}

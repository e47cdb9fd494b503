//! The `hopperflow` binary refuses malformed case files and overrides with exit code 2,
//! a message naming the file, the key and its line, and no output directory.

use crate::bad_case_files::{bad_case_files, expectations};
use crate::run_cli;
use run_cli::{assert_refused, hopperflow, stderr_of};
use std::path::{Path, PathBuf};

use proptest::prelude::*;

/// Exit code the command line promises for bad input.
const EXIT_BAD_INPUT: i32 = 2;

/// Runs `check FILE` and `run FILE --out DIR/out --quiet` on `file`; both must refuse it
/// with the same fragments, and `run` must not create its output directory.
fn assert_both_commands_refuse(file: &Path, fragments: &[&str]) {
    let scratch = tempfile::tempdir().expect("temporary directory");
    let out = scratch.path().join("out");
    let file_arg = file.to_str().expect("UTF-8 test path");
    let what = file.display().to_string();
    assert_refused(
        &hopperflow(&["check", file_arg]),
        &format!("check {what}"),
        fragments,
    );
    let out_arg = out.to_str().expect("UTF-8 test path");
    assert_refused(
        &hopperflow(&["run", file_arg, "--out", out_arg, "--quiet"]),
        &format!("run {what}"),
        fragments,
    );
    assert!(
        !out.exists(),
        "run {what}: bad input created the output directory {}",
        out.display()
    );
}

fn bad_case_directory() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../case/tests/data/bad_cases")
}

#[test]
fn shared_bad_case_files_exit_with_code_two_naming_file_key_and_line() {
    let files = bad_case_files(&bad_case_directory());
    // The brief asks for at least ten malformed files through the binary.
    assert!(files.len() >= 10, "only {} shared bad cases", files.len());
    for path in &files {
        let expected = expectations(path);
        // The fragments carry `file:line:column: key = value: message`, so matching them
        // checks that the file, the line and the key are all named.
        let fragments: Vec<&str> = expected.iter().map(String::as_str).collect();
        assert_both_commands_refuse(path, &fragments);
    }
}

/// One malformed case of this test: file name, contents and what stderr must contain
/// besides the file name.
struct BadCase {
    name: &'static str,
    contents: &'static [u8],
    fragments: &'static [&'static str],
}

const OWN_BAD_CASES: &[BadCase] = &[
    BadCase {
        name: "outlet_as_wide_as_hopper.toml",
        contents: b"version = 1\n[geometry]\nwidth = 0.05\noutlet_width = 0.05\n",
        fragments: &[":4:", "geometry.outlet_width", "must be < geometry.width"],
    },
    BadCase {
        name: "gap_plus_outlet_past_wall.toml",
        contents: b"version = 1\n[geometry]\noutlet_width = 0.03\noutlet_gap = 0.08\n",
        fragments: &[":4:", "geometry.outlet_gap", "does not fit"],
    },
    BadCase {
        name: "angle_zero_degrees.toml",
        contents: b"version = 1\n[geometry]\nhopper_angle_deg = 0.0\n",
        fragments: &[":3:", "geometry.hopper_angle_deg", "(0\u{b0}, 90\u{b0}]"],
    },
    BadCase {
        name: "angle_ninety_five_degrees.toml",
        contents: b"version = 1\n[geometry]\nhopper_angle_deg = 95.0\n",
        fragments: &[
            ":3:",
            "geometry.hopper_angle_deg = 95",
            "(0\u{b0}, 90\u{b0}]",
        ],
    },
    BadCase {
        name: "outlet_two_diameters.toml",
        contents: b"version = 1\n[geometry]\noutlet_width = 0.006\n",
        fragments: &[":3:", "geometry.outlet_width", "3 particle diameters"],
    },
    BadCase {
        name: "negative_particle_diameter.toml",
        contents: b"version = 1\n[particles]\ndiameter = -0.001\n",
        fragments: &[":3:", "particles.diameter", "> 0"],
    },
    BadCase {
        name: "count_does_not_fit_short_hopper.toml",
        contents: b"version = 1\n[geometry]\nheight = 0.1\n[particles]\ncount = 3000\n",
        fragments: &[":5:", "particles.count", "cannot fit"],
    },
    BadCase {
        name: "misspelt_protocol_key.toml",
        contents: b"version = 1\n[protocol]\nclog_time = 1.0\n",
        fragments: &[":3:", "protocol.clog_time", "unknown key"],
    },
    BadCase {
        name: "gravity_upward.toml",
        contents: b"version = 1\nseed = 1\ngravity = -9.81\n",
        fragments: &[":3:", "gravity = -9.81 m/s\u{b2}", "(0, 1000] m/s\u{b2}"],
    },
    BadCase {
        name: "gravity_of_a_neutron_star.toml",
        contents: b"version = 1\ngravity = 1.0e12\n",
        fragments: &[":2:", "gravity", "(0, 1000] m/s\u{b2}"],
    },
    BadCase {
        name: "time_step_as_string.toml",
        contents: b"version = 1\n[time]\ntime_step = \"small\"\n",
        fragments: &[":3:", "time.time_step", "expected a number"],
    },
    BadCase {
        name: "unclosed_table_header.toml",
        contents: b"version = 1\n[geometry\nwidth = 0.1\n",
        fragments: &[":2:", "invalid TOML"],
    },
    BadCase {
        name: "binary_garbage.toml",
        contents: b"\x7fELF\x02\x01\x01\x00\xff\xfe\x00\x00\x89PNG\r\n\x1a\n\xc3\x28",
        fragments: &[":1", "not valid UTF-8"],
    },
    BadCase {
        name: "ascii_garbage.toml",
        contents: b"\x01\x02 = = ]]\n[[[\n",
        fragments: &[":1:", "invalid TOML"],
    },
    BadCase {
        name: "empty_case.toml",
        contents: b"",
        fragments: &["no keys"],
    },
    BadCase {
        name: "only_comments.toml",
        contents: b"# a case file with nothing in it\n\n",
        fragments: &["no keys"],
    },
];

#[test]
fn own_malformed_case_files_exit_with_code_two_naming_file_key_and_line() {
    let dir = tempfile::tempdir().expect("temporary directory");
    for case in OWN_BAD_CASES {
        let path = dir.path().join(case.name);
        std::fs::write(&path, case.contents).expect("write test case");
        let mut fragments = vec![case.name];
        fragments.extend_from_slice(case.fragments);
        assert_both_commands_refuse(&path, &fragments);
    }
}

#[test]
fn malformed_overrides_exit_with_code_two_naming_the_key() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("base.toml");
    std::fs::write(&path, "version = 1\n").expect("write base case");
    let file = path.to_str().expect("UTF-8 test path");
    let out = dir.path().join("out");
    let out_arg = out.to_str().expect("UTF-8 test path");
    let overrides: &[(&str, &[&str])] = &[
        (
            "geometry.outlet_width=0.2",
            &["--set", "geometry.outlet_width", "must be < geometry.width"],
        ),
        (
            "geometry.widht=0.1",
            &["--set", "geometry.widht", "unknown key"],
        ),
        (
            "geometry.width=abc",
            &["--set", "geometry.width", "expected a number"],
        ),
        ("nonsense", &["--set", "nonsense", "key=value"]),
        ("=3", &["--set", "key is empty"]),
        (
            "particles.count=1e400",
            &["--set", "particles.count", "not a TOML value"],
        ),
        ("geometry=5", &["--set", "geometry", "expected a table"]),
    ];
    for (set, fragments) in overrides {
        let what = format!("--set {set}");
        assert_refused(
            &hopperflow(&["check", file, "--set", set]),
            &format!("check {what}"),
            fragments,
        );
        assert_refused(
            &hopperflow(&["run", file, "--set", set, "--out", out_arg, "--quiet"]),
            &format!("run {what}"),
            fragments,
        );
        assert!(!out.exists(), "run {what} created the output directory");
    }
    // Without a case file, overrides apply to the paper's base case and are checked too.
    assert_refused(
        &hopperflow(&[
            "run",
            "--set",
            "geometry.hopper_angle_deg=0",
            "--out",
            out_arg,
            "--quiet",
        ]),
        "run --set without file",
        &["geometry.hopper_angle_deg"],
    );
    assert!(
        !out.exists(),
        "run with a bad override and no file created the output directory"
    );
}

#[test]
fn missing_or_unreadable_case_file_exits_with_code_two() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let missing = dir.path().join("no_such_case.toml");
    assert_both_commands_refuse(&missing, &["no_such_case.toml", "cannot read"]);
    // A directory in place of a file cannot be read either.
    let folder = dir.path().join("a_folder.toml");
    std::fs::create_dir(&folder).expect("create folder");
    assert_both_commands_refuse(&folder, &["a_folder.toml", "cannot read"]);
}

#[test]
fn init_writes_a_template_that_check_accepts_and_whose_resolved_case_reads_back() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let template = dir.path().join("case.toml");
    let template_arg = template.to_str().expect("UTF-8 test path");
    let init = hopperflow(&["init", template_arg]);
    assert_eq!(
        init.status.code(),
        Some(0),
        "init failed: {}",
        stderr_of(&init)
    );
    assert!(template.is_file(), "init wrote no file");

    let check = hopperflow(&["check", template_arg]);
    assert_eq!(
        check.status.code(),
        Some(0),
        "check refused the template: {}",
        stderr_of(&check)
    );
    let resolved = String::from_utf8(check.stdout).expect("check prints UTF-8");
    assert!(
        resolved.contains("outlet_width"),
        "check printed no resolved case:\n{resolved}"
    );

    // The printed resolved case is itself a valid case file, and a fixed point: reading
    // it back prints the same text.
    let again = dir.path().join("resolved.toml");
    std::fs::write(&again, &resolved).expect("write resolved case");
    let check_again = hopperflow(&["check", again.to_str().expect("UTF-8 test path")]);
    assert_eq!(
        check_again.status.code(),
        Some(0),
        "the resolved case does not parse: {}",
        stderr_of(&check_again)
    );
    assert_eq!(
        String::from_utf8_lossy(&check_again.stdout),
        resolved,
        "the resolved case changed on reading it back"
    );

    // init never overwrites: a second init to the same path is bad input and the
    // edited file survives.
    std::fs::write(&template, "version = 1\nseed = 7\n").expect("edit case");
    let second = hopperflow(&["init", template_arg]);
    assert_refused(
        &second,
        "init over an existing file",
        &["case.toml", "exists"],
    );
    assert_eq!(
        std::fs::read_to_string(&template).expect("read case"),
        "version = 1\nseed = 7\n"
    );
}

#[test]
fn init_without_a_file_prints_a_template_that_check_accepts() {
    let init = hopperflow(&["init"]);
    assert_eq!(
        init.status.code(),
        Some(0),
        "init failed: {}",
        stderr_of(&init)
    );
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("printed.toml");
    std::fs::write(&path, &init.stdout).expect("write printed template");
    let check = hopperflow(&["check", path.to_str().expect("UTF-8 test path")]);
    assert_eq!(
        check.status.code(),
        Some(0),
        "check refused the printed template: {}",
        stderr_of(&check)
    );
}

/// `init --kind cylinder` prints a silo template that `check` accepts as a cylinder case;
/// an unknown kind is refused with the list of kinds.
#[test]
fn init_writes_a_template_per_geometry_kind() {
    let init = hopperflow(&["init", "--kind", "cylinder"]);
    assert_eq!(init.status.code(), Some(0), "{}", stderr_of(&init));
    let dir = tempfile::tempdir().expect("temporary directory");
    let path = dir.path().join("silo.toml");
    std::fs::write(&path, &init.stdout).expect("write printed template");
    let check = hopperflow(&["check", path.to_str().expect("UTF-8 test path")]);
    assert_eq!(check.status.code(), Some(0), "{}", stderr_of(&check));
    let resolved = String::from_utf8(check.stdout).expect("UTF-8");
    assert!(resolved.contains("kind = \"cylinder\""), "{resolved}");
    assert_refused(
        &hopperflow(&["init", "--kind", "hexagon"]),
        "an unknown kind",
        &["hexagon", "slab", "cylinder", "box", "mesh"],
    );
    // The box template prints and checks as it is; the mesh template names STL files, which
    // `init FILE --kind mesh` writes beside FILE, and never over existing files.
    let init = hopperflow(&["init", "--kind", "box"]);
    let path = dir.path().join("box.toml");
    std::fs::write(&path, &init.stdout).expect("write printed template");
    let check = hopperflow(&["check", path.to_str().expect("UTF-8 test path")]);
    assert_eq!(check.status.code(), Some(0), "{}", stderr_of(&check));
    assert!(String::from_utf8_lossy(&check.stdout).contains("kind = \"box\""));
    let mesh_dir = dir.path().join("mesh");
    std::fs::create_dir(&mesh_dir).unwrap();
    let case = mesh_dir.join("case.toml");
    let case_arg = case.to_str().expect("UTF-8 test path");
    let init = hopperflow(&["init", case_arg, "--kind", "mesh"]);
    assert_eq!(init.status.code(), Some(0), "{}", stderr_of(&init));
    for file in ["silo_wall.stl", "silo_cone.stl"] {
        assert!(mesh_dir.join(file).is_file(), "init did not write {file}");
    }
    let check = hopperflow(&["check", case_arg]);
    assert_eq!(check.status.code(), Some(0), "{}", stderr_of(&check));
    let resolved = String::from_utf8(check.stdout).expect("UTF-8");
    assert!(resolved.contains("kind = \"mesh\"") && resolved.contains("silo_cone.stl"));
    std::fs::remove_file(&case).unwrap();
    assert_refused(
        &hopperflow(&["init", case_arg, "--kind", "mesh"]),
        "init over an existing STL file",
        &["silo_wall.stl exists; not overwriting it"],
    );
    assert!(!case.exists(), "a refused init wrote the case file");
}

#[test]
fn unknown_subcommand_and_missing_argument_exit_with_code_two() {
    assert_refused(
        &hopperflow(&["simulate"]),
        "unknown subcommand",
        &["simulate"],
    );
    assert_refused(&hopperflow(&["check"]), "check without a file", &["CASE"]);
    assert_refused(
        &hopperflow(&["run", "--threads", "many"]),
        "non-numeric thread count",
        &["--threads"],
    );
    // A benchmark of no runs has no median: refused before anything is timed, naming the
    // option, the value and the allowed range.
    for runs in ["0", "101"] {
        assert_refused(
            &hopperflow(&["bench", "--case", "bed", "--runs", runs]),
            "bench --runs out of range",
            &["--runs", runs, "1..=100"],
        );
    }
}

#[test]
fn output_path_that_is_a_file_fails_with_a_message_instead_of_a_panic() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let case = dir.path().join("base.toml");
    std::fs::write(&case, "version = 1\n").expect("write base case");
    let blocker = dir.path().join("not_a_folder");
    std::fs::write(&blocker, "occupied").expect("write blocker");
    let output = hopperflow(&[
        "run",
        case.to_str().expect("UTF-8 test path"),
        "--out",
        blocker.to_str().expect("UTF-8 test path"),
        "--quiet",
    ]);
    let stderr = stderr_of(&output);
    assert!(
        !stderr.contains("panicked"),
        "the binary panicked:\n{stderr}"
    );
    // Not bad input but an I/O failure: any non-zero status, with the path named.
    assert!(!output.status.success(), "run into a file succeeded");
    assert!(
        stderr.contains("not_a_folder"),
        "stderr does not name the output path:\n{stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(&blocker).expect("read blocker"),
        "occupied",
        "the blocking file was changed"
    );
}

proptest! {
    // Each case starts the binary, so keep the count small; the parser itself is fuzzed
    // in-process by the study crate's own tests.
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_as_a_case_file_exit_with_code_two_without_panicking(bytes in proptest::collection::vec(any::<u8>(), 0..256)) {
        let dir = tempfile::tempdir().expect("temporary directory");
        let path = dir.path().join("random.toml");
        std::fs::write(&path, &bytes).expect("write random case");
        let output = hopperflow(&["check", path.to_str().expect("UTF-8 test path")]);
        let stderr = stderr_of(&output);
        prop_assert!(!stderr.contains("panicked"), "panic on {:?}:\n{}", bytes, stderr);
        // Random bytes are almost never a valid case (it would need e.g. `version = 1`
        // spelt out), so a refusal naming the file is the only acceptable answer.
        prop_assert_eq!(output.status.code(), Some(EXIT_BAD_INPUT), "bytes {:?}; stderr:\n{}", bytes, stderr);
        prop_assert!(stderr.contains("random.toml"), "stderr does not name the file:\n{}", stderr);
    }
}

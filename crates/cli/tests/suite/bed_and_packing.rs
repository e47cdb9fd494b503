//! `hopperflow run --save-bed`, `--from-bed` and `--packing` through the binary: a bed
//! saved by one run starts another through a wider outlet; a case that changes a key that
//! made the bed, a bed folder already taken, a folder of a run that started otherwise and a
//! bad packing file are each refused with exit 2, a message naming what is wrong, and no
//! output folder.

use crate::run_cli;
use run_cli::{hopperflow, utf8};
use std::path::Path;
use std::process::Output;

use crate::tiny;

/// Exit code the command line promises for bad input.
const EXIT_BAD_INPUT: i32 = 2;

/// The tiny hopper, its discharge cut to 20 ms: these tests exercise the start, not the
/// flow.
fn tiny_case() -> String {
    tiny::tiny_case(0.02)
}

/// Asserts exit code 2, no panic, every fragment in stderr, and that `out` was not created.
fn assert_refused(output: &Output, out: &Path, what: &str, fragments: &[&str]) {
    run_cli::assert_refused(output, what, fragments);
    assert!(!out.exists(), "{what}: bad input created {}", out.display());
}

fn assert_success(output: &Output, what: &str) {
    assert_eq!(
        output.status.code(),
        Some(0),
        "{what} failed:\n{}",
        String::from_utf8_lossy(&output.stderr)
    );
}

#[test]
fn a_saved_bed_starts_a_wider_outlet_and_refuses_a_changed_particle_key() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = |name: &str| root.path().join(name);
    let case = dir("tiny.toml");
    std::fs::write(&case, tiny_case()).unwrap();
    let bed = dir("bed");
    let first = hopperflow(&[
        "run",
        utf8(&case),
        "--save-bed",
        utf8(&bed),
        "--out",
        utf8(&dir("first")),
        "--quiet",
    ]);
    assert_success(&first, "the run that saves the bed");
    assert!(bed.join("bed.bin").is_file() && bed.join("case.toml").is_file());

    // A changed particle key: refused, both values named, nothing written.
    let out = dir("bigger");
    let refused = hopperflow(&[
        "run",
        utf8(&case),
        "--from-bed",
        utf8(&bed),
        "--set",
        "particles.diameter=0.0029",
        "--out",
        utf8(&out),
        "--quiet",
    ]);
    assert_refused(
        &refused,
        &out,
        "a changed particle diameter",
        &[
            "the bed was settled under other inputs",
            "particles.diameter: 0.003 -> 0.0029",
            &bed.join("bed.bin").display().to_string(),
        ],
    );
    // So is another seed: the seed made the fill the bed holds.
    let refused = hopperflow(&[
        "run",
        "--from-bed",
        utf8(&bed),
        "--set",
        "seed=12",
        "--out",
        utf8(&out),
    ]);
    assert_refused(&refused, &out, "another seed", &["seed: 11 -> 12"]);

    // Without a case file the bed's own case is the base: a wider, centred outlet.
    let wider = dir("wider");
    let run = hopperflow(&[
        "run",
        "--from-bed",
        utf8(&bed),
        "--set",
        "geometry.outlet_width=0.024",
        "--set",
        "geometry.outlet_offset=0",
        "--out",
        utf8(&wider),
        "--quiet",
    ]);
    assert_success(&run, "the wider outlet from the bed");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        stdout.contains("start     bed 250 particles settled"),
        "{stdout}"
    );
    let start: serde_json::Value =
        serde_json::from_slice(&std::fs::read(wider.join("start.json")).unwrap()).unwrap();
    assert_eq!(start["start"]["kind"], "bed");
    assert_eq!(
        start["walls_rebuilt"],
        serde_json::json!(["plate_left", "plate_right", "gate"])
    );

    // Resuming that folder as a run with its own fill mixes two starts: refused.
    let resumed = hopperflow(&[
        "run",
        utf8(&case),
        "--set",
        "geometry.outlet_width=0.024",
        "--out",
        utf8(&wider),
        "--resume",
        "--quiet",
    ]);
    assert_eq!(resumed.status.code(), Some(EXIT_BAD_INPUT));
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    assert!(
        stderr.contains("holds a run that started from a saved bed")
            && stderr.contains("this run starts from its own fill"),
        "{stderr}"
    );

    // The bed folder is taken: a second --save-bed into it is refused.
    let out = dir("second");
    let refused = hopperflow(&[
        "run",
        utf8(&case),
        "--save-bed",
        utf8(&bed),
        "--out",
        utf8(&out),
    ]);
    assert_refused(
        &refused,
        &out,
        "a taken bed folder",
        &[
            "holds a saved bed already (250 particles settled at t = ",
            "--restart replaces it",
        ],
    );

    // A file that is not a bed.
    let fake = dir("fake");
    std::fs::create_dir_all(&fake).unwrap();
    std::fs::write(fake.join("bed.bin"), b"HFCKPT\0\x08 not a bed").unwrap();
    let refused = hopperflow(&["run", "--from-bed", utf8(&fake), "--out", utf8(&out)]);
    assert_refused(
        &refused,
        &out,
        "a foreign bed file",
        &["is not a hopperflow bed"],
    );
}

#[test]
fn a_bad_packing_is_refused_with_exit_2_naming_file_line_and_value() {
    let root = tempfile::tempdir().expect("temporary directory");
    let dir = |name: &str| root.path().join(name);
    let case = dir("tiny.toml");
    std::fs::write(&case, tiny_case()).unwrap();
    let out = dir("out");
    let cases: [(&str, &str, &[&str]); 4] = [
        (
            "overlap.csv",
            "x,y,z,radius,material\n-0.01,0.001515,0.01,0.0015,glass\n-0.008,0.001515,0.01,0.0015,glass\n",
            &["overlap.csv line 3: overlaps the particle of line 2", "at most 1 % is allowed"],
        ),
        (
            "negative.csv",
            "x,y,z,radius,material\n0,0.001515,0.01,-0.0015,glass\n",
            &["negative.csv line 2: radius = -0.0015 must be finite and > 0 [m]"],
        ),
        (
            "columns.csv",
            "x,y,z,r,material\n",
            &["columns.csv line 1: unknown column `r`", "lacks the column(s) radius"],
        ),
        ("empty.csv", "", &["empty.csv: is empty"]),
    ];
    for (name, text, fragments) in cases {
        let file = dir(name);
        std::fs::write(&file, text).unwrap();
        let output = hopperflow(&[
            "run",
            utf8(&case),
            "--packing",
            utf8(&file),
            "--out",
            utf8(&out),
            "--quiet",
        ]);
        assert_refused(&output, &out, name, fragments);
    }
    // Exactly one start: a bed and a packing together are refused by the parser.
    let output = hopperflow(&[
        "run",
        "--from-bed",
        utf8(&dir("bed")),
        "--packing",
        utf8(&dir("empty.csv")),
        "--out",
        utf8(&out),
    ]);
    assert_refused(&output, &out, "two starts", &["cannot be used with"]);
}

/// `--no-pictures` leaves out the plots and the VTU snapshots that the case asks for and
/// writes the tables and the summary as ever.
#[test]
fn a_run_without_pictures_writes_its_tables_and_no_images() {
    let root = tempfile::tempdir().expect("temporary directory");
    let case = root.path().join("tiny.toml");
    let text = tiny_case()
        .replace("vtu_interval = 0.0", "vtu_interval = 0.01")
        .replace("plots = false", "plots = true");
    std::fs::write(&case, text).expect("case written");
    let out = root.path().join("run");
    let output = hopperflow(&[
        "run",
        utf8(&case),
        "--out",
        utf8(&out),
        "--quiet",
        "--no-pictures",
    ]);
    assert_success(&output, "a run without pictures");
    for table in ["summary.json", "crossings.csv", "remaining.csv"] {
        assert!(out.join(table).is_file(), "{table} missing");
    }
    let pictures: Vec<String> = walk(&out)
        .into_iter()
        .filter(|p| p.ends_with(".png") || p.ends_with(".svg") || p.ends_with(".vtu"))
        .collect();
    assert!(pictures.is_empty(), "pictures written: {pictures:?}");
}

/// Every file under `dir`, as paths.
fn walk(dir: &Path) -> Vec<String> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).expect("readable folder").flatten() {
        let path = entry.path();
        if path.is_dir() {
            files.extend(walk(&path));
        } else {
            files.push(path.display().to_string());
        }
    }
    files
}

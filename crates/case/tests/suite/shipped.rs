//! Every case and sweep file the repository ships passes the checks a run makes before it
//! starts: the files under `cases/`, `bench/` and `examples/` (each case file through
//! `load_case`, what `hopperflow check` and `hopperflow run` call; each sweep file through
//! `load_sweep`, what `hopperflow study` calls), the built-in sweeps, and the templates
//! `hopperflow init --kind` writes, with the files they name. Validation only: nothing runs.

use std::path::{Path, PathBuf};

use case::{
    builtin_sweep, load_case, load_sweep, parse_sweep, template, template_files,
    BUILTIN_SWEEP_NAMES,
};

/// The folders of shipped case files, relative to the repository root, searched to any depth.
const SHIPPED_FOLDERS: [&str; 3] = ["cases", "bench", "examples"];

/// How many TOML files those folders held when this test was written: 9 case files and 5
/// sweep files in `cases/`, the benchmark silo's case file in `bench/`. Fewer found means
/// the walk missed a folder (or a file was removed: then lower this number with it).
const KNOWN_FILES: usize = 15;

/// The kinds `hopperflow init --kind` takes (its clap list).
const TEMPLATE_KINDS: [&str; 6] = ["slab", "cylinder", "box", "mesh", "heap", "draw_down"];

fn repository_root() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    root.canonicalize()
        .unwrap_or_else(|e| panic!("{}: {e}", root.display()))
}

/// Every `*.toml` file under `dir`, to any depth, sorted: Cargo's manifests (the engine's
/// benchmarks under bench/ are a package) and build folders are not case files.
fn toml_files(dir: &Path, found: &mut Vec<PathBuf>) {
    let entries = std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    for entry in entries {
        let path = entry
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .path();
        let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if path.is_dir() {
            if name != "target" {
                toml_files(&path, found);
            }
        } else if path.extension().is_some_and(|e| e == "toml") && name != "Cargo.toml" {
            found.push(path);
        }
    }
}

/// Whether `text` is a sweep file: it gives its base case as a `[base]` table or as a
/// `base = "case.toml"` key. A case file has neither, so each file goes to one loader, and
/// one sent to the wrong loader would fail there on the keys it does not know.
fn is_sweep(text: &str) -> bool {
    text.lines().map(str::trim_start).any(|line| {
        line.starts_with("[base]")
            || line.starts_with("[base.")
            || line
                .strip_prefix("base")
                .is_some_and(|rest| rest.trim_start().starts_with('='))
    })
}

/// Whether `text` is a calibration file (`hopperflow calibrate`): it lists the parameters to
/// find and the targets to match, which neither a case nor a sweep file has.
fn is_calibration(text: &str) -> bool {
    let has = |header: &str| {
        text.lines()
            .any(|line| line.split('#').next().unwrap_or("").trim() == header)
    };
    has("[[parameters]]") && has("[[targets]]")
}

#[test]
fn every_shipped_case_and_sweep_file_passes_the_checks_before_a_run() {
    let root = repository_root();
    let mut files = Vec::new();
    for folder in SHIPPED_FOLDERS {
        toml_files(&root.join(folder), &mut files);
    }
    files.sort();
    let names: Vec<String> = files
        .iter()
        .map(|f| f.strip_prefix(&root).unwrap_or(f).display().to_string())
        .collect();
    assert!(
        files.len() >= KNOWN_FILES,
        "found {} shipped TOML files, at least {KNOWN_FILES} expected; found:\n{}",
        files.len(),
        names.join("\n")
    );

    let mut failures = Vec::new();
    let (mut cases, mut sweeps, mut calibrations) = (Vec::new(), Vec::new(), Vec::new());
    for (file, name) in files.iter().zip(&names) {
        let text = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{name}: {e}"));
        if is_calibration(&text) {
            match case::load_calibration(file) {
                Ok(_) => calibrations.push(name.as_str()),
                Err(e) => failures.push(format!("{name} (calibration):\n{e}")),
            }
        } else if is_sweep(&text) {
            match load_sweep(file, &[]) {
                Ok(plan) if plan.cases.is_empty() => {
                    failures.push(format!("{name}: the sweep expands to no case"));
                }
                Ok(_) => sweeps.push(name.as_str()),
                Err(e) => failures.push(format!("{name} (sweep):\n{e}")),
            }
        } else {
            match load_case(file, &[]) {
                Ok(_) => cases.push(name.as_str()),
                Err(e) => failures.push(format!("{name} (case):\n{e}")),
            }
        }
    }
    assert!(
        failures.is_empty(),
        "shipped files refused:\n{}",
        failures.join("\n\n")
    );
    // Both loaders were used: a test that sent every file to one of them would check less.
    assert!(
        !cases.is_empty() && !sweeps.is_empty(),
        "case files {cases:?}, sweep files {sweeps:?}"
    );
    eprintln!(
        "checked {} case files, {} sweep files and {} calibration files:\n{}",
        cases.len(),
        sweeps.len(),
        calibrations.len(),
        names.join("\n")
    );
}

#[test]
fn every_built_in_sweep_expands_into_valid_cases() {
    assert!(!BUILTIN_SWEEP_NAMES.is_empty(), "no built-in sweeps listed");
    for name in BUILTIN_SWEEP_NAMES {
        let text = builtin_sweep(name).unwrap_or_else(|| panic!("`{name}` has no text"));
        let plan = parse_sweep(text, name, None, &[]).unwrap_or_else(|e| panic!("{name}:\n{e}"));
        assert!(!plan.cases.is_empty(), "{name} expands to no case");
    }
}

#[test]
fn every_template_of_hopperflow_init_is_a_valid_case_with_its_files() {
    let dir = tempfile::tempdir().expect("temporary directory");
    for kind in TEMPLATE_KINDS {
        let text = template(kind).unwrap_or_else(|| panic!("no template of kind `{kind}`"));
        // As `hopperflow init --kind KIND FILE` writes it: the case, and beside it the files
        // it names.
        let folder = dir.path().join(kind);
        std::fs::create_dir(&folder).expect("a folder per kind");
        let path = folder.join("case.toml");
        std::fs::write(&path, text).expect("writable template");
        for (name, contents) in template_files(kind) {
            std::fs::write(folder.join(name), contents).expect("writable template file");
        }
        let case = load_case(&path, &[]).unwrap_or_else(|e| panic!("template `{kind}`:\n{e}"));
        assert_eq!(case.geometry.kind(), kind, "template `{kind}`");
    }
}

/// The SHA-256 of each template's text, pinned so that building the templates from shared
/// sections (in `template.rs`) cannot change a byte of what `hopperflow init` writes. A
/// deliberate change to a template's text updates its digest here.
const TEMPLATE_SHA256: [(&str, &str); 6] = [
    (
        "slab",
        "ae045793caf51a61675162e8471eb816b980b6a713cd149ce067733a313c35e0",
    ),
    (
        "cylinder",
        "ee80c73eaa24016d2785867f090539261666eeea623613f89dea52f683925bc0",
    ),
    (
        "box",
        "86756353cc1ca8d7d4c72110abf3296cd978c001260d8fc3c412a26548fca023",
    ),
    (
        "mesh",
        "184fb50a34771b34b1a34330f3b6239db3fd21aea6a0ff1833fd5c5b2ba0efd4",
    ),
    (
        "heap",
        "099ed0fb6359daa7713c49aee8f38ae58b61ec462901389eb53698cc586cd197",
    ),
    (
        "draw_down",
        "2042cc2d99a9baafd6b4f400d7c2c1b8ce6de3fa2f12682cebd18ed67d631be7",
    ),
];

#[test]
fn every_template_keeps_its_text() {
    use sha2::{Digest, Sha256};
    for (kind, expected) in TEMPLATE_SHA256 {
        let text = template(kind).unwrap_or_else(|| panic!("no template of kind `{kind}`"));
        let digest: String = Sha256::digest(text.as_bytes())
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        assert_eq!(digest, expected, "template `{kind}` changed its text");
    }
}

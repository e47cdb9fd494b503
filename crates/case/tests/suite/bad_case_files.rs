//! The shared bad-case files (`crates/case/tests/data/bad_cases/`) and what each must be
//! refused with. The case crate's tests read them through the library and the command
//! line's through the binary; the command line's tests include this file (`#[path]` in
//! crates/cli/tests/suite/main.rs), since integration tests of two crates share no module.

use std::path::{Path, PathBuf};

/// The bad cases in `dir`, sorted by name.
pub fn bad_case_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("the bad cases in {}: {e}", dir.display()))
        .map(|e| e.expect("directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// The `# expect: <fragment>` lines of a bad-case file (read lossily: one file is
/// deliberately not UTF-8, its expectation line is ASCII); a file without one fails the test.
pub fn expectations(path: &Path) -> Vec<String> {
    let bytes = std::fs::read(path).expect("readable bad case");
    let expected: Vec<String> = String::from_utf8_lossy(&bytes)
        .lines()
        .filter_map(|line| line.strip_prefix("# expect: "))
        .map(str::to_string)
        .collect();
    assert!(
        !expected.is_empty(),
        "{} has no `# expect:` line",
        path.display()
    );
    expected
}

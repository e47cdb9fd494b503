//! Every path that the repository's Markdown names exists, and no Markdown names a path of
//! one machine or a date.
//!
//! **Which files.** Every `*.md` file under the repository root, found by walking the folders
//! (no git needed), leaving out hidden folders (`.git`, virtual environments, caches) and the
//! root's `target/` and `out/`, which the root `.gitignore` ignores: they hold what builds and
//! runs write, not the repository's documents.
//!
//! **What counts as a named path.** Three places are read:
//! - *Links:* the target of `[text](target)`, `![alt](target)` and `[label]: target`, unless it
//!   is a URL (`scheme://…`, `mailto:`) or an anchor (`#…`); a `#fragment` is dropped.
//! - *Code spans:* a backquoted span without spaces that contains a `/` and either ends in
//!   `/` (a folder) or whose last part has an extension (`crates/run/src/protocol.rs`,
//!   `liggghts/in.hopper`, `wall/`).
//! - *Words in commands:* a word of a backquoted span with spaces, or of a line of a fenced
//!   code block, whose first part is an entry of the repository root (`crates/…`, `cases/…`,
//!   `bench/…`, `scripts/…`, `docs/…`, `.ci/…`), as in `hopperflow run cases/base.toml`. A
//!   whole span that starts so (`crates/verify`) is read the same way.
//!
//! **What is not a path.** A candidate is only a path when it is plain: ASCII letters, digits
//! and `_ - . /`. So a placeholder or pattern is never checked: `cases/<id>/summary.json`,
//! `snapshots/particles_*.vtu`, `config/resolve_*.rs`, `{a,b}`, `…`, `$VAR`, and formulas
//! (`W(α)/W(90°)`) fall out by their characters. A part written in capitals only (`DIR`,
//! `OUT`, `FILE`, `N`) is a placeholder too, so `DIR/report/` is not checked. Absolute
//! paths (`/proc`, `/usr/bin/time`) are the system's, not the repository's, and are not
//! checked here; the second test below refuses the paths of one machine (`/work/…`,
//! `/home/…`) and dates written YYYY-MM-DD anywhere in the Markdown. What builds and
//! runs create is left out by two rules, not by listing each file:
//! - a path under `target/` or `out/` (the build's output and the documents' example output
//!   folder, both ignored by the root `.gitignore`);
//! - a path inside a study folder's own layout, [`STUDY_OUTPUT`], written relative to the
//!   study folder (`report/report.md`); each entry says what writes it.
//!
//! **Where a path is looked for.** A link is read as Markdown reads it: from the Markdown
//! file's folder (from the repository root when it starts with `/`). A code span or a word
//! is looked for from the repository root, then from the Markdown file's folder (so
//! `bench/README.md` may name `liggghts/in.hopper`, and a crate's README `src/lib.rs`).
//! Nothing else is tried: a path that drops its crate (`run/src/protocol.rs`,
//! `forces/gather.rs`) is reported, so that the documents name files by the path a reader
//! can open. A path that leaves the repository (`../shared/…`) is reported as outside it:
//! the documents cite nothing outside the repository.
//!
//! The failure lists every missing path with its file and line.

use std::fs;
use std::path::{Component, Path, PathBuf};

/// Entries of a study folder's own layout that the documents name relative to the study
/// folder; these are created by a run or a study, never committed.
const STUDY_OUTPUT: &[(&str, &str)] = &[
    (
        "report/",
        "the report folder that `hopperflow report` writes into a study folder",
    ),
    (
        "report/report.md",
        "the report's Markdown page, written by `hopperflow report`",
    ),
    (
        "report/report.html",
        "the report's HTML page, written by `hopperflow report`",
    ),
    (
        "report/comparison.json",
        "the report's comparison table, written by `hopperflow report`",
    ),
    (
        "report/figures/",
        "the report's figures, written by `hopperflow report`",
    ),
];

/// First parts of a path that name what builds and runs create (the root `.gitignore`).
const OUTPUT_ROOTS: &[&str] = &["target", "out"];

/// Folder names that hold no documents of the repository (checked at the root only).
const SKIPPED_ROOT_FOLDERS: &[&str] = &["target", "out"];

/// Machine-specific path prefixes that no document may contain.
const MACHINE_PREFIXES: &[&str] = &[
    "/work/",
    "/home/",
    "/Users/",
    "/root/",
    "/mnt/",
    "/scratch/",
];

/// The repository root: two folders above this crate.
fn repository_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .canonicalize()
        .expect("the repository root exists")
}

/// Every Markdown file under `root`, sorted, as paths relative to `root`.
fn markdown_files(root: &Path) -> Vec<PathBuf> {
    fn walk(root: &Path, folder: &Path, found: &mut Vec<PathBuf>) {
        let entries = fs::read_dir(root.join(folder))
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", root.join(folder).display()));
        for entry in entries {
            let entry = entry.expect("a folder entry");
            let name = entry.file_name().to_string_lossy().into_owned();
            let relative = folder.join(&name);
            let kind = entry.file_type().expect("an entry's type");
            if kind.is_dir() {
                let at_root = folder.as_os_str().is_empty();
                if name.starts_with('.')
                    || (at_root && SKIPPED_ROOT_FOLDERS.contains(&name.as_str()))
                {
                    continue;
                }
                walk(root, &relative, found);
            } else if kind.is_file() && name.ends_with(".md") {
                found.push(relative);
            }
        }
    }
    let mut found = Vec::new();
    walk(root, Path::new(""), &mut found);
    found.sort();
    found
}

/// How a path was named.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// The target of a Markdown link.
    Link,
    /// A code span, or a word of a command in a span or a fenced block.
    Code,
}

/// One path a Markdown file names.
#[derive(Debug)]
struct Named {
    line: usize,
    path: String,
    kind: Kind,
}

/// Whether `word` is made only of the characters a checked path may have.
fn is_plain(word: &str) -> bool {
    !word.is_empty()
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/'))
}

/// Whether a part of a path is a placeholder written in capitals (`DIR`, `OUT`, `N`).
fn is_placeholder_part(part: &str) -> bool {
    part.chars().any(|c| c.is_ascii_uppercase())
        && part
            .chars()
            .all(|c| c.is_ascii_uppercase() || c.is_ascii_digit() || c == '_')
}

/// Whether `word` names a path in the form a code span alone must have: a `/` inside, and a
/// trailing `/` or an extension on its last part.
fn looks_like_path(word: &str) -> bool {
    if !word.contains('/') || word.starts_with('/') || word.chars().all(|c| c == '/' || c == '.') {
        return false;
    }
    if word.ends_with('/') {
        return true;
    }
    let last = word.rsplit('/').next().unwrap_or("");
    match last.rfind('.') {
        Some(dot) => dot > 0 && last[dot + 1..].chars().any(|c| c.is_ascii_alphabetic()),
        None => false,
    }
}

/// Whether `word`'s first part is an entry of the repository root.
fn starts_in_repository(word: &str, root_entries: &[String]) -> bool {
    match word.split_once('/') {
        Some((first, _)) => root_entries.iter().any(|e| e == first),
        None => false,
    }
}

/// Whether a plain candidate is left out: a placeholder, an absolute path, or output.
fn is_left_out(word: &str) -> bool {
    let trimmed = word.trim_end_matches('/');
    word.starts_with('/')
        || trimmed.split('/').any(is_placeholder_part)
        || OUTPUT_ROOTS
            .iter()
            .any(|r| trimmed == *r || trimmed.starts_with(&format!("{r}/")))
        || STUDY_OUTPUT.iter().any(|(p, _)| *p == word)
}

/// The paths a command (a span with spaces, or a code-block line) names.
fn command_paths(text: &str, root_entries: &[String]) -> Vec<String> {
    text.split_whitespace()
        .map(|w| w.trim_matches(|c: char| matches!(c, '"' | '\'' | ',' | ';' | ':' | '(' | ')')))
        .filter(|w| is_plain(w) && starts_in_repository(w, root_entries) && !is_left_out(w))
        .map(str::to_string)
        .collect()
}

/// The paths one code span names.
fn span_paths(span: &str, root_entries: &[String]) -> Vec<String> {
    let span = span.trim();
    if span.contains(char::is_whitespace) {
        return command_paths(span, root_entries);
    }
    let named = is_plain(span)
        && (looks_like_path(span) || starts_in_repository(span, root_entries))
        && !is_left_out(span);
    if named {
        vec![span.to_string()]
    } else {
        Vec::new()
    }
}

/// A link target with its fragment dropped, or `None` for URLs, anchors and empty targets.
fn link_path(target: &str) -> Option<String> {
    let target = target.trim().trim_start_matches('<').trim_end_matches('>');
    if target.is_empty() || target.starts_with('#') || target.contains("://") {
        return None;
    }
    if let Some((scheme, _)) = target.split_once(':') {
        if scheme.chars().all(|c| c.is_ascii_alphabetic()) {
            return None; // mailto:, tel:, …
        }
    }
    let path = target.split('#').next().unwrap_or("").replace("%20", " ");
    (!path.is_empty()).then_some(path)
}

/// Whether a line opens or closes a fenced code block.
fn is_fence(line: &str) -> bool {
    let indent = line.len() - line.trim_start_matches(' ').len();
    let rest = line.trim_start_matches(' ');
    indent <= 3 && (rest.starts_with("```") || rest.starts_with("~~~"))
}

/// Every path that one Markdown text names, with the line it is on (counted from 1).
fn named_paths(text: &str, root_entries: &[String]) -> Vec<Named> {
    let mut named = Vec::new();
    // The prose outside fenced blocks, with the line each byte of it comes from.
    let mut prose = String::new();
    let mut prose_line = Vec::new();
    let mut fenced = false;
    for (index, line) in text.lines().enumerate() {
        let number = index + 1;
        if is_fence(line) {
            fenced = !fenced;
            continue;
        }
        if fenced {
            for path in command_paths(line, root_entries) {
                named.push(Named {
                    line: number,
                    path,
                    kind: Kind::Code,
                });
            }
            continue;
        }
        // A reference definition: `[label]: target`.
        let trimmed = line.trim_start();
        if trimmed.starts_with('[') && !trimmed.starts_with("[^") {
            if let Some(end) = trimmed.find("]:") {
                let target = trimmed[end + 2..].split_whitespace().next().unwrap_or("");
                if let Some(path) = link_path(target) {
                    named.push(Named {
                        line: number,
                        path,
                        kind: Kind::Link,
                    });
                }
            }
        }
        prose.push_str(line);
        prose.push('\n');
        prose_line.extend(std::iter::repeat_n(number, line.len() + 1));
    }

    let bytes = prose.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'`' {
            // A code span: a run of n backquotes up to the next run of exactly n.
            let run = bytes[i..].iter().take_while(|&&b| b == b'`').count();
            let start = i + run;
            let mut j = start;
            let mut close = None;
            while j < bytes.len() {
                if bytes[j] == b'`' {
                    let other = bytes[j..].iter().take_while(|&&b| b == b'`').count();
                    if other == run {
                        close = Some(j);
                        break;
                    }
                    j += other;
                } else {
                    j += 1;
                }
            }
            match close {
                Some(end) => {
                    for path in span_paths(&prose[start..end], root_entries) {
                        named.push(Named {
                            line: prose_line[i],
                            path,
                            kind: Kind::Code,
                        });
                    }
                    i = end + run;
                }
                None => i = start,
            }
        } else if bytes[i] == b']' && bytes.get(i + 1) == Some(&b'(') {
            // A link's target, up to the closing parenthesis (one level of nesting kept).
            let start = i + 2;
            let mut depth = 0usize;
            let mut end = start;
            while end < bytes.len() {
                match bytes[end] {
                    b'(' => depth += 1,
                    b')' if depth == 0 => break,
                    b')' => depth -= 1,
                    b'\n' => break,
                    _ => {}
                }
                end += 1;
            }
            let target = prose[start..end].split_whitespace().next().unwrap_or("");
            if let Some(path) = link_path(target) {
                named.push(Named {
                    line: prose_line[i],
                    path,
                    kind: Kind::Link,
                });
            }
            i = end;
        } else {
            i += 1;
        }
    }
    named.sort_by_key(|n| n.line);
    named
}

/// `path` with `.` and `..` parts folded, or `None` when `..` climbs above its start.
fn fold(path: &Path) -> Option<PathBuf> {
    let mut parts: Vec<Component> = Vec::new();
    for part in path.components() {
        match part {
            Component::CurDir => {}
            Component::ParentDir => {
                parts.pop()?;
            }
            other => parts.push(other),
        }
    }
    Some(parts.iter().collect())
}

/// Why a named path is wrong, or `None` when it exists.
fn problem(root: &Path, markdown: &Path, named: &Named) -> Option<&'static str> {
    let folder = markdown.parent().unwrap_or(Path::new(""));
    let wants_folder = named.path.ends_with('/');
    let relative = named.path.trim_end_matches('/');
    let candidates: Vec<PathBuf> = match (named.kind, relative.strip_prefix('/')) {
        (Kind::Link, Some(from_root)) => vec![PathBuf::from(from_root)],
        (Kind::Link, None) => vec![folder.join(relative)],
        (Kind::Code, _) => vec![PathBuf::from(relative), folder.join(relative)],
    };
    let inside: Vec<PathBuf> = candidates.iter().filter_map(|c| fold(c)).collect();
    if inside.is_empty() {
        return Some("outside the repository");
    }
    let found = inside.iter().any(|c| {
        let full = root.join(c);
        if wants_folder {
            full.is_dir()
        } else {
            full.exists()
        }
    });
    (!found).then_some("missing")
}

#[test]
fn every_path_named_in_markdown_exists() {
    let root = repository_root();
    let mut root_entries: Vec<String> = fs::read_dir(&root)
        .expect("the repository root is readable")
        .map(|e| {
            e.expect("an entry")
                .file_name()
                .to_string_lossy()
                .into_owned()
        })
        .filter(|name| name != ".git" && !OUTPUT_ROOTS.contains(&name.as_str()))
        .collect();
    root_entries.sort();

    let files = markdown_files(&root);
    assert!(
        files.iter().any(|f| f == Path::new("README.md")),
        "the walk found no README.md under {}",
        root.display()
    );
    let mut checked = 0;
    let mut wrong = Vec::new();
    for file in &files {
        let text = fs::read_to_string(root.join(file))
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", file.display()));
        for named in named_paths(&text, &root_entries) {
            checked += 1;
            if let Some(why) = problem(&root, file, &named) {
                let what = match named.kind {
                    Kind::Link => "link",
                    Kind::Code => "code",
                };
                wrong.push(format!(
                    "  {}:{}: {} `{}` ({why})",
                    file.display(),
                    named.line,
                    what,
                    named.path
                ));
            }
        }
    }
    assert!(
        checked > 50,
        "only {checked} paths found in {} Markdown files",
        files.len()
    );
    assert!(
        wrong.is_empty(),
        "{} of the {checked} paths named in the repository's Markdown do not exist (a path is \
         read from the repository root or the Markdown file's folder; write it in full, as \
         crates/run/src/protocol.rs):\n{}",
        wrong.len(),
        wrong.join("\n")
    );
}

/// Whether `line` holds a calendar date written as YYYY-MM-DD.
fn has_date(line: &str) -> bool {
    let b = line.as_bytes();
    let digits = |from: usize, n: usize| b[from..from + n].iter().all(u8::is_ascii_digit);
    (0..b.len().saturating_sub(9)).any(|i| {
        (i == 0 || !b[i - 1].is_ascii_alphanumeric())
            && digits(i, 4)
            && b[i + 4] == b'-'
            && digits(i + 5, 2)
            && b[i + 7] == b'-'
            && digits(i + 8, 2)
            && matches!(&b[i..i + 2], b"19" | b"20")
    })
}

#[test]
fn no_markdown_names_a_path_of_one_machine_or_a_date() {
    let root = repository_root();
    let mut found = Vec::new();
    for file in markdown_files(&root) {
        let text = fs::read_to_string(root.join(&file)).expect("a readable Markdown file");
        for (index, line) in text.lines().enumerate() {
            let machine = MACHINE_PREFIXES.iter().any(|prefix| line.contains(prefix));
            if machine || has_date(line) {
                found.push(format!(
                    "  {}:{}: {}",
                    file.display(),
                    index + 1,
                    line.trim()
                ));
            }
        }
    }
    assert!(
        found.is_empty(),
        "Markdown names paths of one machine or dates (the documents describe the product as it \
         is; write paths from the repository root):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_rules_read_paths_as_documented() {
    let entries: Vec<String> = ["crates", "cases", "bench", "docs"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let text = "See `crates/run/src/protocol.rs` and [physics](docs/physics.md#contacts).\n\
                Outputs `cases/<id>/summary.json`, `DIR/report/`, `report/report.md`, \
                `target/release/hopperflow`, `W(α)/W(90°)`, `fix wall/gran`, [site](https://x.org).\n\
                Run `hopperflow run cases/base.toml --out out/a` or ``a `x/y.rs` b``.\n\
                ```\nhopperflow study cases/beverloo3d.toml --out DIR\n```\n\
                [ref]: ../outside/file.md\n";
    let named = named_paths(text, &entries);
    let found: Vec<(usize, &str)> = named.iter().map(|n| (n.line, n.path.as_str())).collect();
    assert_eq!(
        found,
        vec![
            (1, "crates/run/src/protocol.rs"),
            (1, "docs/physics.md"),
            (3, "cases/base.toml"),
            (5, "cases/beverloo3d.toml"),
            (7, "../outside/file.md"),
        ]
    );
    let outside = Named {
        line: 7,
        path: "../outside/file.md".into(),
        kind: Kind::Link,
    };
    assert_eq!(
        problem(Path::new("/"), Path::new("README.md"), &outside),
        Some("outside the repository")
    );
    assert!(has_date("measured 2026-11-25/26"));
    assert!(!has_date("seed 32452843, 12026-11-25x, Dosta et al. 2024"));
}

//! What the silo benchmark times (`hopperflow bench --case silo`): the built-in benchmark silo
//! or any case file, with `--set` overrides, filled by the protocol or started from a packing
//! file; and the name of the settled-bed cache of exactly those inputs.
//!
//! A case file and its overrides are read as `hopperflow run FILE --set …` reads them, and a
//! packing as `run --packing` reads it, so that a benchmark times the run those inputs start.
//! With a packing the particle count is the packing's: a benchmark that times one packing file
//! should not need its size repeated by hand, as `run` does (there it guards against running a
//! case with the wrong file).

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::{packing_count, read_packing, Packing, PackingError};
use case::{load_case, parse_case, Case, ConfigErrors, Geometry, WallSurface, CYLINDER_TEMPLATE};

/// Spheres of the built-in benchmark silo when nothing else sets their count.
pub const SILO_PARTICLES: usize = 20_000;

/// Where the silo benchmark's case comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum SiloSource {
    /// The benchmark silo of `hopperflow init --kind cylinder`; `meshed` for its triangle-mesh
    /// walls instead of the exact cylinder and cone.
    Template {
        /// Triangle-mesh walls.
        meshed: bool,
    },
    /// A case file, read as `hopperflow run FILE` reads it (relative paths from its folder).
    File(PathBuf),
}

/// How the silo benchmark's bed is made.
#[derive(Debug, Clone, PartialEq)]
pub enum SiloStart {
    /// The protocol's fill, of `particles` spheres (`None`: the case's own count, or
    /// [`SILO_PARTICLES`] for the built-in silo).
    Fill {
        /// `particles.count`, set after the overrides.
        particles: Option<usize>,
    },
    /// The particles of a packing file (CSV or VTU) at rest; `particles.count` is theirs.
    Packing(PathBuf),
}

/// What the silo benchmark is asked to time, before anything is read.
#[derive(Debug, Clone, PartialEq)]
pub struct SiloRequest {
    /// The case.
    pub source: SiloSource,
    /// `key=value` overrides, as `hopperflow run --set` takes them, applied before the
    /// particle count of `start`.
    pub sets: Vec<String>,
    /// The fill or a packing.
    pub start: SiloStart,
}

/// Why the silo benchmark's inputs cannot be used; nothing was timed.
#[derive(Debug, thiserror::Error)]
pub enum SiloInputError {
    /// The case (file, template or overrides) is not valid; the errors name the file or
    /// `--set`, the key and its line.
    #[error("{errors}")]
    Case {
        /// The case file, `None` for the built-in silo.
        file: Option<PathBuf>,
        /// Every problem found.
        errors: ConfigErrors,
    },
    /// The packing file cannot be read, or does not fit the case; the problems name the
    /// file and the line or point.
    #[error("{0}")]
    Packing(PackingError),
}

/// The silo benchmark's resolved inputs: the case, the packing it starts from, and what the
/// results are labelled with.
#[derive(Debug, Clone)]
pub struct SiloBench {
    /// The resolved case.
    pub case: Case,
    /// The checked packing, `None` for the protocol's fill.
    pub packing: Option<Packing>,
    /// The benchmark's name in its results: `silo`, `silo-meshed`, or `silo:STEM` for a
    /// case file `STEM.toml`.
    pub label: String,
}

impl SiloRequest {
    /// Reads and checks the case and the packing, everything before any simulation.
    pub fn resolve(&self) -> Result<SiloBench, SiloInputError> {
        let file = match &self.source {
            SiloSource::File(path) => Some(path.clone()),
            SiloSource::Template { .. } => None,
        };
        let case_error = |errors| SiloInputError::Case {
            file: file.clone(),
            errors,
        };
        // The built-in silo's own count first, so that an override can replace it.
        let mut sets = match self.source {
            SiloSource::Template { .. } => vec![format!("particles.count={SILO_PARTICLES}")],
            SiloSource::File(_) => Vec::new(),
        };
        sets.extend(self.sets.iter().cloned());
        if let SiloSource::Template { meshed: true } = self.source {
            sets.push("geometry.walls=\"meshed\"".into());
        }
        match &self.start {
            SiloStart::Fill { particles: Some(n) } => sets.push(format!("particles.count={n}")),
            SiloStart::Fill { particles: None } => {}
            SiloStart::Packing(path) => {
                let n = packing_count(path).map_err(SiloInputError::Packing)?;
                sets.push(format!("particles.count={n}"));
            }
        }
        let case = match &self.source {
            SiloSource::Template { .. } => parse_case(CYLINDER_TEMPLATE, "silo", &sets),
            SiloSource::File(path) => load_case(path, &sets),
        }
        .map_err(case_error)?;
        let packing = match &self.start {
            SiloStart::Packing(path) => {
                Some(read_packing(path, &case).map_err(SiloInputError::Packing)?)
            }
            SiloStart::Fill { .. } => None,
        };
        let label = match &self.source {
            SiloSource::File(path) => format!("silo:{}", stem(path)),
            SiloSource::Template { .. } => match walls_word(&case) {
                "meshed" => "silo-meshed".into(),
                _ => "silo".into(),
            },
        };
        Ok(SiloBench {
            case,
            packing,
            label,
        })
    }
}

impl SiloBench {
    /// The file name of the settled-bed cache of these inputs,
    /// `silo-n{count}-{walls}-{key}.bin`: `walls` is `smooth` or `meshed` (cylinder and box),
    /// `stl` (mesh) or `slab`, and `key` the first 16 hex digits of the SHA-256 of the resolved
    /// case text and of the packing file's SHA-256 (or of the word `fill`). Any change of a key
    /// (the STL files' SHA-256 among them), of the packing's bytes or of the start names another
    /// file, so that a cached bed is never reused for other inputs.
    pub fn cache_name(&self) -> String {
        let mut hasher = Sha256::new();
        hasher.update(b"hopperflow silo benchmark bed\n");
        hasher.update(self.case.to_toml_string().as_bytes());
        hasher.update(b"\nstart ");
        match &self.packing {
            Some(p) => hasher.update(format!("packing {}", p.sha256()).as_bytes()),
            None => hasher.update(b"fill"),
        }
        let key: String = hasher.finalize()[..8]
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        format!(
            "silo-n{}-{}-{key}.bin",
            self.case.particles.count,
            walls_word(&self.case)
        )
    }
}

/// The walls of `case` in a word, for the cache's file name.
fn walls_word(case: &Case) -> &'static str {
    let surface = |w: WallSurface| match w {
        WallSurface::Smooth => "smooth",
        WallSurface::Meshed => "meshed",
    };
    match &case.geometry {
        Geometry::Cylinder(g) => surface(g.walls),
        Geometry::Cuboid(g) | Geometry::DrawDown(case::DrawDownGeometry { container: g }) => {
            surface(g.walls)
        }
        Geometry::Heap(_) => "heap",
        Geometry::Mesh(_) => "stl",
        Geometry::Slab(_) => "slab",
    }
}

/// A file's stem for a label, `case` where it has none.
fn stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(|| "case".into(), |s| s.to_string_lossy().into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn template(sets: &[&str], start: SiloStart) -> SiloBench {
        SiloRequest {
            source: SiloSource::Template { meshed: false },
            sets: sets.iter().map(|s| s.to_string()).collect(),
            start,
        }
        .resolve()
        .expect("the built-in silo resolves")
    }

    #[test]
    fn the_cache_name_follows_every_input_and_only_the_inputs() {
        let fill = |n| SiloStart::Fill { particles: Some(n) };
        let base = template(&[], fill(5000)).cache_name();
        assert!(base.starts_with("silo-n5000-smooth-"), "{base}");
        // The same inputs name the same file: the cache is found again.
        assert_eq!(template(&[], fill(5000)).cache_name(), base);
        // Any key that changes the run names another file, the count and walls included.
        assert_ne!(template(&["seed=2"], fill(5000)).cache_name(), base);
        assert_ne!(template(&[], fill(5001)).cache_name(), base);
        let meshed = SiloRequest {
            source: SiloSource::Template { meshed: true },
            sets: Vec::new(),
            start: fill(5000),
        }
        .resolve()
        .expect("the meshed silo resolves");
        assert_eq!(meshed.label, "silo-meshed");
        assert!(meshed.cache_name().starts_with("silo-n5000-meshed-"));
    }

    #[test]
    fn the_count_flag_overrides_a_set_count_and_the_default() {
        let bench = template(
            &["particles.count=3000"],
            SiloStart::Fill { particles: None },
        );
        assert_eq!(bench.case.particles.count, 3000);
        let bench = template(
            &["particles.count=3000"],
            SiloStart::Fill {
                particles: Some(4000),
            },
        );
        assert_eq!(bench.case.particles.count, 4000);
        let bench = template(&[], SiloStart::Fill { particles: None });
        assert_eq!(bench.case.particles.count, SILO_PARTICLES);
        assert_eq!(bench.label, "silo");
    }
}

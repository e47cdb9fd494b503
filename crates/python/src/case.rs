//! `Case`: a validated hopper case, read and changed the way the command line does it.
//!
//! A case keeps the text it was read from and the overrides set on it since, exactly as
//! `hopperflow run FILE --set key=value …` would: every change is validated by the study
//! crate's reader before it is kept, so a `Case` is always valid and its errors carry the
//! command line's text, key and line.

use std::path::PathBuf;

use case::{default_case, load_case, parse_case, parse_case_in};
use pyo3::exceptions::{PyKeyError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyMapping, PyString, PyTuple};

use crate::errors::{case_error, key_error};

/// Deepest nesting of lists and tables accepted in a value (a case needs two).
const MAX_DEPTH: usize = 16;

/// Where the case came from, so that validation reads it again the same way.
#[derive(Clone)]
enum Origin {
    /// The paper's base case (no file).
    Paper,
    /// Case text, the name errors give it (a file name, or `<string>`) and the folder its
    /// relative paths (a mesh case's STL files) are taken from: the case file's, or the
    /// current folder (`None`) for text.
    Text {
        text: String,
        name: String,
        dir: Option<PathBuf>,
    },
}

/// A validated hopper case (see `hopperflow.Case`).
#[pyclass(module = "hopperflow._native", name = "Case")]
#[derive(Clone)]
pub struct Case {
    origin: Origin,
    sets: Vec<String>,
    pub(crate) case: case::Case,
}

impl Case {
    fn resolve(origin: &Origin, sets: &[String]) -> Result<case::Case, case::ConfigErrors> {
        match origin {
            Origin::Paper => default_case(sets),
            Origin::Text { text, name, dir } => parse_case_in(text, name, dir.as_deref(), sets),
        }
    }

    /// This case with `more` overrides added, validated; `self` is left unchanged on error.
    fn with_sets(&self, py: Python<'_>, more: Vec<String>) -> PyResult<Self> {
        let mut sets = self.sets.clone();
        sets.extend(more);
        let case = Self::resolve(&self.origin, &sets).map_err(|e| case_error(py, &e))?;
        Ok(Self {
            origin: self.origin.clone(),
            sets,
            case,
        })
    }

    /// The resolved case as a TOML table (every key explicit).
    fn table(&self) -> toml::Table {
        // The study crate writes text that reads back to the same case (tested there);
        // an empty table would only hide a broken invariant behind a KeyError.
        let mut table = self
            .case
            .to_toml_string()
            .parse::<toml::Table>()
            .unwrap_or_default();
        // The text leaves out a default g (so that existing cases keep their hashes); the
        // table gives it, so that `case["gravity"]` answers for every case.
        table
            .entry("gravity")
            .or_insert(toml::Value::Float(self.case.gravity));
        table
    }
}

#[pymethods]
impl Case {
    /// The paper's base case (Fan et al. 2023, Table 1: α = 90°, D = 30 mm, 3000 spheres).
    #[staticmethod]
    fn paper(py: Python<'_>) -> PyResult<Self> {
        let case = default_case(&[]).map_err(|e| case_error(py, &e))?;
        Ok(Self {
            origin: Origin::Paper,
            sets: Vec::new(),
            case,
        })
    }

    /// Reads and validates a case file (TOML), as `hopperflow check FILE` does.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        if !path.is_file() {
            return Err(pyo3::exceptions::PyFileNotFoundError::new_err(format!(
                "{}: no such case file",
                path.display()
            )));
        }
        let case = load_case(&path, &[]).map_err(|e| case_error(py, &e))?;
        // `load_case` read the file; read it again for the text only after it succeeded.
        let text = std::fs::read_to_string(&path)?;
        Ok(Self {
            origin: Origin::Text {
                text,
                name: path.display().to_string(),
                dir: path.parent().map(PathBuf::from),
            },
            sets: Vec::new(),
            case,
        })
    }

    /// Validates case text; `name` is what error messages call it.
    #[staticmethod]
    #[pyo3(signature = (text, name = "<string>".to_string()))]
    fn from_toml(py: Python<'_>, text: String, name: String) -> PyResult<Self> {
        let case = parse_case(&text, &name, &[]).map_err(|e| case_error(py, &e))?;
        Ok(Self {
            origin: Origin::Text {
                text,
                name,
                dir: None,
            },
            sets: Vec::new(),
            case,
        })
    }

    /// The paper's base case with the keys of a (nested or dotted) dict set on it.
    #[staticmethod]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyAny>) -> PyResult<Self> {
        let sets = mapping_sets(py, d)?;
        let case = default_case(&sets).map_err(|e| case_error(py, &e))?;
        Ok(Self {
            origin: Origin::Paper,
            sets,
            case,
        })
    }

    /// Sets one dotted key, e.g. `case["geometry.outlet_width"] = 0.045`.
    fn __setitem__(
        &mut self,
        py: Python<'_>,
        key: &Bound<'_, PyAny>,
        value: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let key = key_text(key)?;
        let set = set_of(py, &key, value)?;
        *self = self.with_sets(py, vec![set])?;
        Ok(())
    }

    /// Sets several keys at once (validated together, so that keys that depend on each
    /// other, such as the outlet and the hopper width, can change in one step).
    fn update(&mut self, py: Python<'_>, values: &Bound<'_, PyAny>) -> PyResult<()> {
        let sets = mapping_sets(py, values)?;
        *self = self.with_sets(py, sets)?;
        Ok(())
    }

    /// The resolved value of a dotted key, or a whole section as a dict.
    fn __getitem__(&self, py: Python<'_>, key: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let key = key_text(key)?;
        let table = self.table();
        let mut value: Option<&toml::Value> = None;
        let mut here = &table;
        for (i, part) in key.split('.').enumerate() {
            let found = here.get(part).ok_or_else(|| {
                let known: Vec<&str> = here.keys().map(String::as_str).collect();
                PyKeyError::new_err(format!(
                    "{key}: no such key in the resolved case; keys here: {}",
                    known.join(", ")
                ))
            })?;
            value = Some(found);
            match found {
                toml::Value::Table(t) => here = t,
                _ if i + 1 < key.split('.').count() => {
                    return Err(PyKeyError::new_err(format!(
                        "{key}: `{part}` holds a value, not a table"
                    )))
                }
                _ => {}
            }
        }
        match value {
            Some(v) => to_python(py, v),
            None => Err(PyKeyError::new_err(format!("{key}: no such key"))),
        }
    }

    fn __contains__(&self, py: Python<'_>, key: &Bound<'_, PyAny>) -> bool {
        self.__getitem__(py, key).is_ok()
    }

    /// Validates the case again and returns it (a `Case` is validated at every change, so
    /// this raises only if the case file it was loaded from changed meaning).
    fn check<'py>(slf: PyRef<'py, Self>, py: Python<'py>) -> PyResult<PyRef<'py, Self>> {
        Self::resolve(&slf.origin, &slf.sets).map_err(|e| case_error(py, &e))?;
        Ok(slf)
    }

    /// The resolved case as a case file: every key explicit, SI units (`hopperflow check`).
    fn to_toml(&self) -> String {
        self.case.to_toml_string()
    }

    /// The resolved case as a nested dict.
    fn to_dict(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        to_python(py, &toml::Value::Table(self.table()))
    }

    /// The overrides set on the case since it was read, as `key=value` lines of `--set`.
    #[getter]
    fn overrides(&self) -> Vec<String> {
        self.sets.clone()
    }

    /// A copy that changes independently of this case.
    fn copy(&self) -> Self {
        self.clone()
    }

    fn __copy__(&self) -> Self {
        self.clone()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        self.clone()
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        match other.cast::<Case>() {
            Ok(other) => other.borrow().case == self.case,
            Err(_) => false,
        }
    }

    fn __repr__(&self) -> String {
        let g = &self.case.geometry;
        let size = match g {
            case::Geometry::Slab(s) => format!("L={} m", s.width),
            case::Geometry::Cylinder(s) => format!("kind=cylinder, R={} m", s.radius),
            case::Geometry::Cuboid(s) => {
                format!("kind=box, W={} m, B={} m", s.width, s.depth)
            }
            case::Geometry::Mesh(s) => format!("kind=mesh, {} STL walls", s.walls.len()),
            case::Geometry::Heap(s) => format!(
                "kind=heap, R_c={} m, R_p={} m, lift={} m/s",
                s.cylinder_radius, s.plate_radius, s.lift_speed
            ),
            case::Geometry::DrawDown(s) => {
                format!("kind=draw_down, W={} m, B={} m", s.width(), s.depth())
            }
        };
        format!(
            "Case(N={}, d={} m, {size}, D={} m, alpha={}°, seed={})",
            self.case.particles.count,
            self.case.particles.mean_diameter(),
            g.outlet_size(),
            g.hopper_angle_deg(),
            self.case.seed
        )
    }
}

/// A key given from Python: a str that cannot break the `key=value` form.
fn key_text(key: &Bound<'_, PyAny>) -> PyResult<String> {
    let key: String = key.extract().map_err(|_| {
        PyTypeError::new_err(format!(
            "case keys are dotted strings such as 'geometry.outlet_width', not {}",
            key.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    })?;
    Ok(key)
}

/// The `key=value` override of one Python value; a value with no TOML form is a
/// `CaseError` naming the key.
fn set_of(py: Python<'_>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    if key.contains('=') || key.contains('\n') || key.contains('\r') {
        return Err(key_error(
            py,
            key,
            None,
            "a key is a dotted name (letters, digits, `_` and `-` separated by `.`)",
        ));
    }
    let shown = value.repr().map(|r| r.to_string()).ok();
    let toml = to_toml(value, 0).map_err(|message| key_error(py, key, shown, &message))?;
    Ok(format!("{key}={toml}"))
}

/// The overrides of a mapping, nested tables flattened to dotted keys.
fn mapping_sets(py: Python<'_>, d: &Bound<'_, PyAny>) -> PyResult<Vec<String>> {
    let mapping = d.cast::<PyMapping>().map_err(|_| {
        PyTypeError::new_err(format!(
            "expected a dict of case keys, got {}",
            d.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    })?;
    let mut sets = Vec::new();
    flatten(py, "", mapping, &mut sets, 0)?;
    Ok(sets)
}

fn flatten(
    py: Python<'_>,
    prefix: &str,
    mapping: &Bound<'_, PyMapping>,
    sets: &mut Vec<String>,
    depth: usize,
) -> PyResult<()> {
    if depth > MAX_DEPTH {
        return Err(key_error(py, prefix, None, "tables nested too deeply"));
    }
    for item in mapping.items()?.iter() {
        let (key, value): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item.extract()?;
        let key = key_text(&key)?;
        let full = if prefix.is_empty() {
            key
        } else {
            format!("{prefix}.{key}")
        };
        match value.cast::<PyDict>() {
            Ok(inner) => flatten(py, &full, inner.as_mapping(), sets, depth + 1)?,
            Err(_) => sets.push(set_of(py, &full, &value)?),
        }
    }
    Ok(())
}

/// A Python value as one line of TOML: bool, int, float (NaN and infinities included, for
/// the case reader to refuse by key), str, lists and tuples, dicts as inline tables.
fn to_toml(value: &Bound<'_, PyAny>, depth: usize) -> Result<String, String> {
    if depth > MAX_DEPTH {
        return Err("lists or tables nested too deeply".into());
    }
    let type_name = value
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_default();
    // numpy's bool scalar (`bool_`, `bool` in numpy 2) is no Python bool but means one.
    let numpy_bool =
        !value.is_instance_of::<PyBool>() && (type_name == "bool_" || type_name == "bool");
    let toml_value = if value.is_instance_of::<PyBool>() || numpy_bool {
        toml::Value::Boolean(value.is_truthy().map_err(|e| e.to_string())?)
    } else if value.is_instance_of::<PyInt>()
        || (value.hasattr("__index__").unwrap_or(false) && !value.is_instance_of::<PyFloat>())
    {
        match value.extract::<i64>() {
            Ok(i) => toml::Value::Integer(i),
            Err(_) => {
                return Err(format!(
                    "the integer does not fit a TOML integer (a signed 64-bit number, {}..={})",
                    i64::MIN,
                    i64::MAX
                ))
            }
        }
    } else if value.is_instance_of::<PyFloat>()
        || value.hasattr("__float__").unwrap_or(false) && !value.is_instance_of::<PyString>()
    {
        let x: f64 = value.extract::<f64>().map_err(|e: PyErr| e.to_string())?;
        toml::Value::Float(x)
    } else if let Ok(s) = value.cast::<PyString>() {
        toml::Value::String(s.to_string())
    } else if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for item in value.try_iter().map_err(|e| e.to_string())? {
            let item = item.map_err(|e| e.to_string())?;
            items.push(to_toml(&item, depth + 1)?);
        }
        return Ok(format!("[{}]", items.join(", ")));
    } else if let Ok(d) = value.cast::<PyDict>() {
        let mut items = Vec::new();
        for (k, v) in d.iter() {
            let k: String = k.extract::<String>().map_err(|_| {
                format!(
                    "table keys must be strings, not {}",
                    k.get_type()
                        .name()
                        .map(|n| n.to_string())
                        .unwrap_or_default()
                )
            })?;
            let key = toml::Value::String(k.clone()).to_string();
            items.push(format!("{key} = {}", to_toml(&v, depth + 1)?));
        }
        return Ok(format!("{{{}}}", items.join(", ")));
    } else {
        return Err(format!(
            "a {type_name} has no TOML form; give a number, bool, str, list or dict"
        ));
    };
    Ok(toml_value.to_string())
}

/// A TOML value as a Python object.
pub fn to_python(py: Python<'_>, value: &toml::Value) -> PyResult<Py<PyAny>> {
    Ok(match value {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any().unbind(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any().unbind(),
        toml::Value::Float(x) => x.into_pyobject(py)?.into_any().unbind(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any().unbind(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any().unbind(),
        toml::Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(to_python(py, item)?)?;
            }
            list.into_any().unbind()
        }
        toml::Value::Table(table) => {
            let dict = PyDict::new(py);
            for (k, v) in table {
                dict.set_item(k, to_python(py, v)?)?;
            }
            dict.into_any().unbind()
        }
    })
}

/// The `key=value` overrides of a dict (nested or dotted keys), each value written as TOML
/// but not validated: a study validates them against its sweep's base case.
#[pyfunction]
pub fn overrides_of(py: Python<'_>, values: &Bound<'_, PyAny>) -> PyResult<Vec<String>> {
    mapping_sets(py, values)
}

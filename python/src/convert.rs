//! Python values to a config: dicts in the TOML's shape, `set` overrides, errors.

use std::path::{Path, PathBuf};

use monoculus_experiments::{ConfigError as BadConfig, Experiment, Registry};
use pyo3::exceptions::{PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

pyo3::create_exception!(
    monoculus,
    ConfigError,
    pyo3::exceptions::PyValueError,
    "A bad config: its file, line and key, as the command line says them."
);
pyo3::create_exception!(
    monoculus,
    AlgorithmError,
    PyRuntimeError,
    "A run's algorithm failed: an exception in a Python algorithm, or a decision that breaks the model."
);

/// The label of a config given as a dict: it has no file, and no lines.
pub const DICT: &str = "<dict>";

/// `monoculus.ConfigError` with the message (and `file`, `line`, `key`) of the error,
/// said where a Python user gave it: a dict config has no file and no lines (the key
/// alone is named), and overrides come from `set=`, not `--set`.
pub fn config_error(py: Python<'_>, e: &BadConfig) -> PyErr {
    let mut e = e.clone();
    let mut file = Some(e.file.clone());
    if e.file == DICT {
        e.line = None;
        file = None;
    } else if e.file == "--set" {
        e.file = "set".into();
        file = None;
    }
    let text = match &file {
        Some(_) => e.to_string(),
        None if e.file == DICT => {
            let message = monoculus_experiments::short_quotes(&e.message);
            match &e.key {
                Some(key) => format!("{key}: {message}"),
                None => format!("the config dict: {message}"),
            }
        }
        None => e.to_string(),
    };
    let err = ConfigError::new_err(monoculus_experiments::one_line(&text));
    let value = err.value(py);
    let _ = value.setattr("file", file);
    let _ = value.setattr("line", e.line);
    let _ = value.setattr("key", e.key.clone());
    err
}

/// A Python value as a TOML value (what a config file would say).
pub fn to_toml(v: &Bound<'_, PyAny>, key: &str) -> PyResult<toml::Value> {
    let bad = || {
        PyTypeError::new_err(format!(
            "{key}: {} is not a config value (numbers, strings, booleans, lists and dicts are)",
            v.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    };
    if v.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return v
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| bad());
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(v.extract()?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(v.extract()?));
    }
    if let Ok(d) = v.cast::<PyDict>() {
        return Ok(toml::Value::Table(to_table(d, key)?));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: Vec<toml::Value> = v
            .try_iter()?
            .map(|x| to_toml(&x?, key))
            .collect::<PyResult<_>>()?;
        return Ok(toml::Value::Array(items));
    }
    // numpy scalars and the like: by their float or int value; paths by their text.
    if let Ok(i) = v.extract::<i64>()
        && v.hasattr("dtype")?
        && v.getattr("dtype")?.getattr("kind")?.extract::<String>()? != "f"
    {
        return Ok(toml::Value::Integer(i));
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(toml::Value::Float(x));
    }
    if v.hasattr("__fspath__")? {
        return Ok(toml::Value::String(
            v.call_method0("__fspath__")?.extract()?,
        ));
    }
    Err(bad())
}

/// A Python dict as a TOML table.
pub fn to_table(d: &Bound<'_, PyDict>, prefix: &str) -> PyResult<toml::Table> {
    let mut t = toml::Table::new();
    for (k, v) in d.iter() {
        let k: String = k.extract()?;
        let key = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        t.insert(k, to_toml(&v, &key)?);
    }
    Ok(t)
}

/// `set=`: a dict of dotted keys to values, or a list of `"KEY=VALUE"` strings, as the
/// `--set` overrides of the command line.
pub fn overrides(set: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<String>> {
    let Some(set) = set.filter(|s| !s.is_none()) else {
        return Ok(Vec::new());
    };
    if let Ok(d) = set.cast::<PyDict>() {
        return d
            .iter()
            .map(|(k, v)| {
                let k: String = k.extract()?;
                Ok(format!("{k}={}", to_toml(&v, &k)?))
            })
            .collect();
    }
    if let Ok(s) = set.extract::<String>() {
        return Ok(vec![s]);
    }
    set.try_iter()?.map(|x| x?.extract::<String>()).collect()
}

/// The experiment of `config` (a path, or a dict in the TOML's shape) with `set`.
pub fn experiment(
    py: Python<'_>,
    config: &Bound<'_, PyAny>,
    set: Option<&Bound<'_, PyAny>>,
    registry: &Registry,
) -> PyResult<(Experiment, Option<PathBuf>)> {
    let overrides = overrides(set)?;
    if let Ok(d) = config.cast::<PyDict>() {
        let table = to_table(d, "")?;
        let text = toml::to_string(&table)
            .map_err(|e| PyTypeError::new_err(format!("the config dict: {e}")))?;
        let base = std::env::current_dir().unwrap_or_default();
        return Experiment::parse(&text, DICT, &base, &overrides, registry)
            .map(|e| (e, None))
            .map_err(|e| config_error(py, &e));
    }
    let path: PathBuf = if config.hasattr("__fspath__")? {
        PathBuf::from(config.call_method0("__fspath__")?.extract::<String>()?)
    } else {
        PathBuf::from(config.extract::<String>().map_err(|_| {
            PyTypeError::new_err("config: a path to a TOML file, or a dict in its shape")
        })?)
    };
    Experiment::load(Path::new(&path), &overrides, registry)
        .map(|e| (e, Some(path)))
        .map_err(|e| config_error(py, &e))
}

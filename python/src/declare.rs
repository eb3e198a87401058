//! Declaring a Python algorithm: what `monoculus.algorithm` records, its parameters
//! typed by their defaults, and the registry of the paper's algorithms and the Python
//! ones.

use std::marker::PhantomData;
use std::sync::Arc;

use monoculus_core::algorithms::{Directions, Goal, Ld, Model, Ola, Positions, StopCriterion};
use monoculus_engine::AlgorithmBox;
use monoculus_experiments::Registry;
use monoculus_experiments::registry::ParamsError;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::algorithm::{Errors, PyAlgorithm, PyModel};
use crate::convert::to_table;
use crate::observation::Palette;

/// A Python algorithm as `monoculus.algorithm` declares it.
pub struct Spec {
    name: String,
    model: Model,
    func: Py<PyAny>,
    memory: Option<usize>,
    vectorized: bool,
    defaults: Py<PyDict>,
    stop: StopCriterion,
    goal: Goal,
    palette: Palette,
}

/// The one of `all` whose `name` is `given`; else an error naming the key `what` and
/// listing the names.
fn named<T: Copy>(all: &[T], name: fn(T) -> &'static str, what: &str, given: &str) -> PyResult<T> {
    all.iter()
        .copied()
        .find(|&x| name(x) == given)
        .ok_or_else(|| {
            let names: Vec<_> = all.iter().map(|&x| format!("{:?}", name(x))).collect();
            PyValueError::new_err(format!("{what} {given:?}: one of {}", names.join(", ")))
        })
}

impl Spec {
    /// Reads a declaration: a dict with name, sensing, func, memory, vectorized, params,
    /// stop, goal and lights.
    pub fn read(d: &Bound<'_, PyDict>) -> PyResult<Spec> {
        let get = |k: &str| -> PyResult<Bound<'_, PyAny>> {
            d.get_item(k)?
                .ok_or_else(|| PyValueError::new_err(format!("algorithm declaration without {k}")))
        };
        let name: String = get("name")?.extract()?;
        let model = named(
            &[Model::Directions, Model::Ld, Model::Ola, Model::Positions],
            Model::name,
            "sensing",
            &get("sensing")?.extract::<String>()?,
        )?;
        let memory: Option<usize> = get("memory")?.extract()?;
        if memory == Some(0) {
            return Err(PyValueError::new_err(
                "memory: the number of floats each robot keeps, at least 1 (or None)",
            ));
        }
        let defaults = match get("params")? {
            p if p.is_none() => PyDict::new(d.py()),
            p => p
                .cast::<PyDict>()
                .map_err(|_| PyTypeError::new_err("params: a dict of the parameters' defaults"))?
                .copy()?,
        };
        // The defaults must be config values.
        to_table(&defaults, "params")?;
        let stop = match get("stop")? {
            s if s.is_none() => StopCriterion::QuiescentOrDiameter,
            s => named(
                &[
                    StopCriterion::Quiescent,
                    StopCriterion::Diameter,
                    StopCriterion::QuiescentOrDiameter,
                    StopCriterion::Box,
                ],
                StopCriterion::name,
                "stop",
                &s.extract::<String>()?,
            )?,
        };
        let palette = match get("lights")? {
            l if l.is_none() => Palette::default(),
            l => {
                let names: Vec<String> = l
                    .extract()
                    .map_err(|_| PyTypeError::new_err("lights: a list of the colours' names"))?;
                let max = monoculus_core::algorithms::MAX_LIGHTS;
                if names.len() > max {
                    return Err(PyValueError::new_err(format!(
                        "lights: {} colours, at most {max}",
                        names.len()
                    )));
                }
                for (k, n) in names.iter().enumerate() {
                    if n.is_empty() || names[..k].contains(n) {
                        return Err(PyValueError::new_err(format!(
                            "lights: {n:?}: each colour needs a name of its own"
                        )));
                    }
                }
                Palette(names.into())
            }
        };
        let goal = match get("goal")? {
            g if g.is_none() => Goal::Diameter,
            g => named(&Goal::ALL, Goal::name, "goal", &g.extract::<String>()?)?,
        };
        Ok(Spec {
            name,
            model,
            func: get("func")?.unbind(),
            memory,
            vectorized: get("vectorized")?.extract()?,
            defaults: defaults.unbind(),
            stop,
            goal,
            palette,
        })
    }

    fn make<M: PyModel>(
        &self,
        given: &toml::Table,
        errors: &Errors,
    ) -> Result<(AlgorithmBox, toml::Table), ParamsError> {
        Python::attach(|py| {
            let params = self.defaults.bind(py).copy().map_err(|e| ParamsError {
                key: String::new(),
                message: e.to_string(),
            })?;
            for (k, v) in given {
                if !params.contains(k).unwrap_or(false) {
                    return Err(ParamsError {
                        key: k.clone(),
                        message: format!("{} has no parameter of that name", self.name),
                    });
                }
                let default = params.get_item(k).ok().flatten();
                let v = typed_like(default.as_ref(), v).map_err(|message| ParamsError {
                    key: k.clone(),
                    message,
                })?;
                let v = toml_to_py(py, &v).map_err(|e| ParamsError {
                    key: k.clone(),
                    message: e.to_string(),
                })?;
                params.set_item(k, v).map_err(|e| ParamsError {
                    key: k.clone(),
                    message: e.to_string(),
                })?;
            }
            let resolved = to_table(&params, "").map_err(|e| ParamsError {
                key: String::new(),
                message: e.to_string(),
            })?;
            let algorithm = PyAlgorithm::<M> {
                name: self.name.clone(),
                func: self.func.clone_ref(py),
                memory: self.memory,
                vectorized: self.vectorized,
                params: params.unbind(),
                errors: errors.clone(),
                stop: self.stop,
                goal: self.goal,
                palette: self.palette.clone(),
                model: PhantomData,
            };
            Ok((AlgorithmBox::new(algorithm), resolved))
        })
    }
}

/// `v` as a value of the type of a parameter's `default` (a parameter is typed by its
/// default): an integer for a float is that float; another type is refused, naming the
/// kind expected. A default of None takes any value.
fn typed_like(default: Option<&Bound<'_, PyAny>>, v: &toml::Value) -> Result<toml::Value, String> {
    use pyo3::types::{PyBool, PyFloat, PyInt, PyList, PyString, PyTuple};
    let Some(d) = default.filter(|d| !d.is_none()) else {
        return Ok(v.clone());
    };
    let expected = if d.is_instance_of::<PyBool>() {
        "a boolean"
    } else if d.is_instance_of::<PyInt>() {
        "an integer"
    } else if d.is_instance_of::<PyFloat>() {
        "a number"
    } else if d.is_instance_of::<PyString>() {
        "a string"
    } else if d.is_instance_of::<PyList>() || d.is_instance_of::<PyTuple>() {
        "a list"
    } else if d.is_instance_of::<PyDict>() {
        "a table"
    } else {
        return Ok(v.clone());
    };
    let fits = match (expected, v) {
        ("a number", toml::Value::Integer(i)) => return Ok(toml::Value::Float(*i as f64)),
        ("a boolean", toml::Value::Boolean(_))
        | ("an integer", toml::Value::Integer(_))
        | ("a number", toml::Value::Float(_))
        | ("a string", toml::Value::String(_))
        | ("a list", toml::Value::Array(_))
        | ("a table", toml::Value::Table(_)) => true,
        _ => false,
    };
    if fits {
        return Ok(v.clone());
    }
    let default_text = d.repr().map(|r| r.to_string()).unwrap_or_default();
    Err(format!(
        "{} is not {expected}, as its default {default_text} is",
        monoculus_experiments::shown(&v.to_string())
    ))
}

/// A TOML value as a Python value.
fn toml_to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(x) => x.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let items: Vec<Bound<'py, PyAny>> = a
                .iter()
                .map(|x| toml_to_py(py, x))
                .collect::<PyResult<_>>()?;
            pyo3::types::PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, toml_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// The paper's algorithms and the Python ones of the `declarations` of
/// `monoculus.algorithm`; their exceptions go to `errors`.
pub fn registry(declarations: &[Bound<'_, PyDict>], errors: &Errors) -> PyResult<Registry> {
    let mut r = Registry::builtin();
    for d in declarations {
        let spec = Arc::new(Spec::read(d)?);
        let errors = errors.clone();
        let s = spec.clone();
        let make: monoculus_experiments::registry::Make = match spec.model {
            Model::Directions => Arc::new(move |t| s.make::<Directions>(t, &errors)),
            Model::Ld => Arc::new(move |t| s.make::<Ld>(t, &errors)),
            Model::Ola => Arc::new(move |t| s.make::<Ola>(t, &errors)),
            Model::Positions => Arc::new(move |t| s.make::<Positions>(t, &errors)),
        };
        if Registry::builtin().get(&spec.name).is_some() {
            return Err(PyValueError::new_err(format!(
                "{:?} is the name of a built-in algorithm: give yours another",
                spec.name
            )));
        }
        r.try_register_with(&spec.name, spec.model, spec.stop, make)
            .map_err(PyValueError::new_err)?;
    }
    Ok(r)
}

//! Algorithms written in Python: one Rust type per sensing model, whose `decide` calls
//! the Python function with the activation's observation and stream.

use std::marker::PhantomData;
use std::sync::{Arc, Mutex};

use monoculus_core::algorithms::{
    Algorithm, Decision, Directions, Goal, Ld, Model, NoParams, Observation, Ola, Positions,
    Sensing, StopCriterion,
};
use monoculus_core::geometry::Point;
use monoculus_core::observe::Side;
use monoculus_core::rng::Stream;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::observation::{
    DirectionsObservation, Guard, LdObservation, ObsApi, OlaObservation, Palette,
    PositionsObservation, Rng,
};
use crate::threads::keep_thread_state;

/// The first exception a Python algorithm raised in a call of the package: re-raised
/// (as the cause of `monoculus.AlgorithmError`) when the call ends.
pub type Errors = Arc<Mutex<Option<PyErr>>>;

/// A sensing model as the Python package hands it over.
pub trait PyModel: Sensing + Sized {
    /// The observation as its model's queries.
    fn api<'a, V: Point>(obs: &'a Observation<'a, Self, V>) -> &'a (dyn ObsApi + 'a);
    /// The Python object of an observation.
    fn object<'py>(
        py: Python<'py>,
        guard: Guard,
        params: Py<PyDict>,
        palette: Palette,
    ) -> PyResult<Bound<'py, PyAny>>;
}

macro_rules! model {
    ($m:ty, $class:ident) => {
        impl PyModel for $m {
            fn api<'a, V: Point>(obs: &'a Observation<'a, Self, V>) -> &'a (dyn ObsApi + 'a) {
                obs
            }
            fn object<'py>(
                py: Python<'py>,
                guard: Guard,
                params: Py<PyDict>,
                palette: Palette,
            ) -> PyResult<Bound<'py, PyAny>> {
                Ok(Bound::new(
                    py,
                    $class {
                        guard,
                        params,
                        palette,
                    },
                )?
                .into_any())
            }
        }
    };
}
model!(Directions, DirectionsObservation);
model!(Ld, LdObservation);
model!(Ola, OlaObservation);
model!(Positions, PositionsObservation);

/// A Python algorithm's memory: `memory` floats per robot, zero at the start, and the
/// colour it shows (algorithms with lights; 0 at the start).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PyState(Vec<f64>, u8);

/// A robot's state as an algorithm with lights gets it: the colour it shows, by name
/// (set it by name or index), and its memory.
#[pyclass(module = "monoculus")]
pub struct State {
    light: usize,
    palette: Palette,
    memory: Py<numpy::PyArray1<f64>>,
}

#[pymethods]
impl State {
    /// The name of the colour the robot shows; set it by name or by index.
    #[getter]
    fn light(&self) -> String {
        self.palette.name(self.light).unwrap_or_default()
    }

    #[setter]
    fn set_light(&mut self, colour: &Bound<'_, PyAny>) -> PyResult<()> {
        self.light = self.palette.index(colour)?;
        Ok(())
    }

    /// The robot's memory: a numpy array of `memory` floats (empty without), changed
    /// in place.
    #[getter]
    fn memory(&self, py: Python<'_>) -> Py<numpy::PyArray1<f64>> {
        self.memory.clone_ref(py)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let memory = self
            .memory
            .bind(py)
            .repr()
            .map(|r| r.to_string())
            .unwrap_or_default();
        let light = pyo3::types::PyString::new(py, &self.light())
            .repr()
            .map(|r| r.to_string())
            .unwrap_or_default();
        format!("State(light={light}, memory={memory})")
    }
}

/// An algorithm whose `decide` is a Python function.
pub struct PyAlgorithm<M> {
    pub(crate) name: String,
    pub(crate) func: Py<PyAny>,
    pub(crate) memory: Option<usize>,
    pub(crate) vectorized: bool,
    pub(crate) params: Py<PyDict>,
    pub(crate) errors: Errors,
    pub(crate) stop: StopCriterion,
    pub(crate) goal: Goal,
    pub(crate) palette: Palette,
    pub(crate) model: PhantomData<fn() -> M>,
}

impl<M: PyModel> PyAlgorithm<M> {
    /// Records the first exception and fails the activation (a panic, which the engine
    /// turns into the run's failure, naming the robot and round).
    fn fail(&self, e: PyErr) -> ! {
        let text = e.to_string();
        let mut first = self.errors.lock().unwrap_or_else(|p| p.into_inner());
        if first.is_none() {
            *first = Some(e);
        }
        drop(first);
        panic!("{text}");
    }

    fn decision<V: Point>(&self, out: &Bound<'_, PyAny>) -> PyResult<Decision<V>> {
        if out.is_none() {
            return Ok(Decision::Stay);
        }
        // A float array is read as it is (of any strides); another sequence item by item.
        let c: Option<Vec<f64>> = match out.cast::<PyArray1<f64>>() {
            Ok(a) => Some(
                a.to_vec()
                    .unwrap_or_else(|_| a.readonly().as_array().to_vec()),
            ),
            Err(_) => out.extract().ok(),
        };
        let c = c.ok_or_else(|| {
            PyTypeError::new_err(format!(
                "{}: decide returned {}, not a direction (an array or tuple of {} numbers) or None",
                self.name,
                out.repr().map(|r| r.to_string()).unwrap_or_default(),
                V::DIM
            ))
        })?;
        if c.len() != V::DIM {
            return Err(PyValueError::new_err(format!(
                "{}: decide returned a direction of {} coordinates in dimension {}",
                self.name,
                c.len(),
                V::DIM
            )));
        }
        Ok(Decision::Step(V::from_slice(&c)))
    }

    fn call<V: Point>(
        &self,
        py: Python<'_>,
        obs: &Observation<'_, M, V>,
        state: &mut PyState,
        rng: &mut Stream,
    ) -> PyResult<Decision<V>> {
        let func = self.func.bind(py);
        let params = self.params.clone_ref(py);
        let palette = self.palette.clone();
        let out = Guard::during(M::api(obs), rng, |g| -> PyResult<Bound<'_, PyAny>> {
            let o = M::object(py, g.clone(), params, palette.clone())?;
            let r = Bound::new(py, Rng { guard: g })?;
            if !palette.0.is_empty() {
                let k = self.memory.unwrap_or(0);
                if state.0.len() != k {
                    state.0 = vec![0.0; k];
                }
                let memory = state.0.clone().into_pyarray(py);
                let st = Bound::new(
                    py,
                    State {
                        light: usize::from(state.1),
                        palette: palette.clone(),
                        memory: memory.clone().unbind(),
                    },
                )?;
                let out = func.call1((o, r, st.clone()))?;
                state.0 = memory.to_vec()?;
                state.1 = st.borrow().light as u8;
                return Ok(out);
            }
            match self.memory {
                Some(k) => {
                    if state.0.len() != k {
                        state.0 = vec![0.0; k];
                    }
                    let s = state.0.clone().into_pyarray(py);
                    let out = func.call1((o, r, s.clone()))?;
                    state.0 = s.to_vec()?;
                    Ok(out)
                }
                None => func.call1((o, r)),
            }
        })?;
        self.decision(&out)
    }

    fn call_together<V: Point>(
        &self,
        py: Python<'_>,
        obs: &[Observation<'_, M, V>],
        states: &mut [&mut PyState],
        rngs: &mut [&mut Stream],
    ) -> PyResult<Vec<Decision<V>>> {
        let m = obs.len();
        let dim = V::DIM;
        let mut offsets = vec![0i64];
        let (mut dirs, mut far) = (Vec::new(), Vec::new());
        let lit = !self.palette.0.is_empty();
        let mut colours: Vec<i64> = Vec::new();
        let mut sides = Vec::with_capacity(m * 2 * dim);
        for o in obs {
            let api = M::api(o);
            let (d, f) = api.seen();
            if lit {
                // The colours, in the order of the directions of the same look.
                let (_, lc) = api.lit();
                colours.extend(lc.into_iter().map(|c| c as i64));
            }
            dirs.extend(d);
            far.extend(f);
            offsets.push((dirs.len() / dim) as i64);
            if M::MODEL == Model::Ola {
                for k in 0..dim {
                    sides.push(api.side_occupied(k, Side::Low));
                    sides.push(api.side_occupied(k, Side::High));
                }
            }
        }
        const DRAWS: usize = 8;
        let mut random = Vec::with_capacity(m * DRAWS);
        for r in rngs.iter_mut() {
            random.extend((0..DRAWS).map(|_| r.uniform()));
        }
        let batch = PyDict::new(py);
        let total = dirs.len() / dim;
        batch.set_item("count", m)?;
        batch.set_item("dim", dim)?;
        batch.set_item("offsets", offsets.into_pyarray(py))?;
        batch.set_item(
            "directions",
            numpy::ndarray::Array2::from_shape_vec((total, dim), dirs)
                .expect("rows")
                .into_pyarray(py),
        )?;
        if M::MODEL == Model::Ld {
            batch.set_item("far", far.into_pyarray(py))?;
        }
        if M::MODEL == Model::Ola {
            batch.set_item(
                "sides",
                numpy::ndarray::Array2::from_shape_vec((m, 2 * dim), sides)
                    .expect("rows")
                    .into_pyarray(py),
            )?;
        }
        batch.set_item(
            "random",
            numpy::ndarray::Array2::from_shape_vec((m, DRAWS), random)
                .expect("rows")
                .into_pyarray(py),
        )?;
        batch.set_item("params", self.params.clone_ref(py))?;
        let own = lit.then(|| {
            let l: Vec<i64> = states.iter().map(|s| i64::from(s.1)).collect();
            l.into_pyarray(py)
        });
        if let Some(own) = &own {
            batch.set_item("colours", colours.into_pyarray(py))?;
            batch.set_item("light", own.clone())?;
            batch.set_item("lights", self.palette.0.to_vec())?;
        }
        let state = self.memory.map(|k| {
            let flat: Vec<f64> = states
                .iter_mut()
                .flat_map(|s| {
                    if s.0.len() != k {
                        s.0 = vec![0.0; k];
                    }
                    s.0.clone()
                })
                .collect();
            numpy::ndarray::Array2::from_shape_vec((m, k), flat)
                .expect("rows")
                .into_pyarray(py)
        });
        if let Some(s) = &state {
            batch.set_item("state", s.clone())?;
        }
        let ns = py
            .import("types")?
            .getattr("SimpleNamespace")?
            .call((), Some(&batch))?;
        let out = self.func.bind(py).call1((ns,))?;
        let bad = || {
            PyTypeError::new_err(format!(
                "{}: a vectorized decide returns (directions, stay): an ({m}, {dim}) array and {m} booleans",
                self.name
            ))
        };
        let out = out.cast::<PyTuple>().map_err(|_| bad())?;
        if out.len() != 2 {
            return Err(bad());
        }
        let (directions, stay) = (out.get_item(0)?, out.get_item(1)?);
        // numpy arrays are read as they are; other sequences element by element.
        let directions: Vec<f64> = match directions.cast::<PyArray2<f64>>() {
            Ok(a) if a.shape() == [m, dim] => a.readonly().as_array().iter().copied().collect(),
            Ok(_) => return Err(bad()),
            Err(_) => {
                let rows: Vec<Vec<f64>> = directions.extract().map_err(|_| bad())?;
                if rows.len() != m || rows.iter().any(|d| d.len() != dim) {
                    return Err(bad());
                }
                rows.concat()
            }
        };
        let stay: Vec<bool> = match stay.cast::<PyArray1<bool>>() {
            Ok(a) => a.readonly().as_array().to_vec(),
            Err(_) => stay.extract().map_err(|_| bad())?,
        };
        if stay.len() != m {
            return Err(bad());
        }
        if let (Some(k), Some(s)) = (self.memory, state) {
            let back = s.to_vec()?;
            for (i, st) in states.iter_mut().enumerate() {
                st.0 = back[i * k..(i + 1) * k].to_vec();
            }
        }
        if let Some(own) = own {
            let back = own.to_vec()?;
            let count = self.palette.0.len() as i64;
            for (st, l) in states.iter_mut().zip(back) {
                if !(0..count).contains(&l) {
                    return Err(PyValueError::new_err(format!(
                        "{}: batch.light holds {l}, not a light of {}",
                        self.name,
                        self.palette.0.join(", ")
                    )));
                }
                st.1 = l as u8;
            }
        }
        Ok(directions
            .chunks_exact(dim)
            .zip(stay)
            .map(|(d, s)| {
                if s {
                    Decision::Stay
                } else {
                    Decision::Step(V::from_slice(d))
                }
            })
            .collect())
    }
}

impl<M: PyModel> Algorithm for PyAlgorithm<M> {
    const NAME: &'static str = "python";
    type Sensing = M;
    type Params = NoParams;
    type State = PyState;

    fn new(_: NoParams) -> Result<Self, String> {
        Err("algorithms written in Python are made by monoculus.algorithm".into())
    }

    fn name(&self) -> &str {
        &self.name
    }

    fn keeps_state(&self) -> bool {
        self.memory.is_some() || !self.palette.0.is_empty()
    }

    fn light(state: &PyState) -> usize {
        usize::from(state.1)
    }

    fn light_names(&self) -> impl ExactSizeIterator<Item = &str> {
        self.palette.0.iter().map(String::as_str)
    }

    fn stop(&self) -> StopCriterion {
        self.stop
    }

    fn goal(&self) -> Goal {
        self.goal
    }

    fn decides_together(&self) -> bool {
        self.vectorized
    }

    fn decide<V: Point>(
        &self,
        obs: &Observation<'_, M, V>,
        state: &mut PyState,
        rng: &mut Stream,
    ) -> Decision<V> {
        keep_thread_state();
        Python::attach(|py| match self.call(py, obs, state, rng) {
            Ok(d) => d,
            Err(e) => self.fail(e),
        })
    }

    fn decide_together<V: Point>(
        &self,
        obs: &[Observation<'_, M, V>],
        states: &mut [&mut PyState],
        rngs: &mut [&mut Stream],
    ) -> Vec<Decision<V>> {
        keep_thread_state();
        Python::attach(|py| match self.call_together(py, obs, states, rngs) {
            Ok(d) => d,
            Err(e) => self.fail(e),
        })
    }
}

//! What a Python algorithm is handed in an activation: an observation of its model and
//! the robot's random stream, valid only while its `decide` runs.
//!
//! The observation borrows the engine's snapshot of the swarm, which lives only for the
//! activation; a Python object cannot hold a borrow. So the Python objects hold the
//! address of the Rust values and a flag, set while `decide` runs and cleared when it
//! returns; every method checks the flag first and raises `RuntimeError` once it is
//! cleared (an object kept past its activation). This is the only `unsafe` of
//! monoculus's Python package, and the reason it is allowed here.

#![allow(unsafe_code)]

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use monoculus_core::algorithms::{Directions, Ld, Observation, Ola, Positions};
use monoculus_core::geometry::Point;
use monoculus_core::observe::Side;
use monoculus_core::rng::Stream;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The queries of an observation, its vectors as coordinates.
pub trait ObsApi {
    fn dim(&self) -> usize;
    fn sole_visible(&self) -> Option<Vec<f64>>;
    fn count_visible_up_to(&self, limit: usize) -> usize;
    fn random_visible(&self, rng: &mut Stream) -> Option<Vec<f64>>;
    fn random_far(&self, _rng: &mut Stream) -> Option<Vec<f64>> {
        unreachable!("only LD observations have far points")
    }
    /// Every visible point's direction, flat (a full look).
    fn directions(&self) -> Vec<f64>;
    /// Every visible point: directions (flat) and far bits (false but for LD), from one
    /// full look.
    fn seen(&self) -> (Vec<f64>, Vec<bool>) {
        let d = self.directions();
        let n = d.len() / self.dim();
        (d, vec![false; n])
    }
    fn side_occupied(&self, _axis: usize, _side: Side) -> bool {
        unreachable!("only OLA observations have sides")
    }
    fn random_in_orthant(&self, _c: &[(usize, Side)], _rng: &mut Stream) -> Option<Vec<f64>> {
        unreachable!("only OLA observations have orthants")
    }
    fn relative_positions(&self) -> Vec<f64> {
        unreachable!("only positions observations have positions")
    }
    /// Every visible point's direction (flat) and the colour its robot shows, in the
    /// order of `directions`.
    fn lit(&self) -> (Vec<f64>, Vec<usize>);
    fn random_lit(&self, light: usize, rng: &mut Stream) -> Option<Vec<f64>>;
    fn sees_light(&self, light: usize) -> bool;
}

fn coords<V: Point>(v: V) -> Vec<f64> {
    (0..V::DIM).map(|k| v.axis(k)).collect()
}

fn flat<V: Point>(vs: impl IntoIterator<Item = V>) -> Vec<f64> {
    vs.into_iter().flat_map(coords).collect()
}

macro_rules! common {
    () => {
        fn dim(&self) -> usize {
            V::DIM
        }
        fn sole_visible(&self) -> Option<Vec<f64>> {
            Observation::sole_visible(self).map(coords)
        }
        fn count_visible_up_to(&self, limit: usize) -> usize {
            Observation::count_visible_up_to(self, limit)
        }
        fn random_visible(&self, rng: &mut Stream) -> Option<Vec<f64>> {
            Observation::random_visible(self, rng).map(coords)
        }
        fn directions(&self) -> Vec<f64> {
            flat(Observation::directions(self))
        }
        fn lit(&self) -> (Vec<f64>, Vec<usize>) {
            let l = Observation::lit(self);
            (
                flat(l.iter().map(|x| x.direction)),
                l.iter().map(|x| x.light).collect(),
            )
        }
        fn random_lit(&self, light: usize, rng: &mut Stream) -> Option<Vec<f64>> {
            Observation::random_lit(self, light, rng).map(coords)
        }
        fn sees_light(&self, light: usize) -> bool {
            Observation::sees_light(self, light)
        }
    };
}

impl<V: Point> ObsApi for Observation<'_, Directions, V> {
    common!();
}

impl<V: Point> ObsApi for Observation<'_, Ld, V> {
    common!();
    fn random_far(&self, rng: &mut Stream) -> Option<Vec<f64>> {
        Observation::random_far(self, rng).map(coords)
    }
    fn seen(&self) -> (Vec<f64>, Vec<bool>) {
        let s = Observation::seen(self);
        (
            flat(s.iter().map(|x| x.direction)),
            s.iter().map(|x| x.far).collect(),
        )
    }
}

impl<V: Point> ObsApi for Observation<'_, Ola, V> {
    common!();
    fn side_occupied(&self, axis: usize, side: Side) -> bool {
        Observation::side_occupied(self, axis, side)
    }
    fn random_in_orthant(&self, c: &[(usize, Side)], rng: &mut Stream) -> Option<Vec<f64>> {
        Observation::random_in_orthant(self, c, rng).map(coords)
    }
}

impl<V: Point> ObsApi for Observation<'_, Positions, V> {
    common!();
    fn relative_positions(&self) -> Vec<f64> {
        flat(Observation::relative_positions(self))
    }
}

/// The addresses of an activation's observation and stream, and whether they are still
/// valid (shared with the activation, which clears it when `decide` returns).
#[derive(Clone)]
pub struct Guard {
    obs: *const (dyn ObsApi + 'static),
    rng: *mut Stream,
    alive: Arc<AtomicBool>,
}

// SAFETY: the addresses are dereferenced only while `alive` is set, that is while the
// activation's `decide` runs, holding the GIL: Python runs one thread at a time, so no
// two threads reach them at once (the package is built for Pythons with a GIL: abi3).
// Afterwards every access raises; an object may then be dropped on any thread (a
// traceback keeps the frames of `decide`, with their observation, after the call).
unsafe impl Send for Guard {}
unsafe impl Sync for Guard {}

impl Guard {
    /// Guards `obs` and `rng` for the duration of `f` (which hands the guard to Python).
    pub fn during<'a, T>(
        obs: &'a (dyn ObsApi + 'a),
        rng: &'a mut Stream,
        f: impl FnOnce(Guard) -> T,
    ) -> T {
        let alive = Arc::new(AtomicBool::new(true));
        // SAFETY: the addresses are used only while `alive` is set; it is cleared below,
        // before `obs` and `rng` go out of scope, however `f` ends (a drop guard).
        let obs: *const (dyn ObsApi + 'static) = unsafe {
            std::mem::transmute::<*const (dyn ObsApi + 'a), *const (dyn ObsApi + 'static)>(obs)
        };
        struct Clear(Arc<AtomicBool>);
        impl Drop for Clear {
            fn drop(&mut self) {
                self.0.store(false, Ordering::SeqCst);
            }
        }
        let _clear = Clear(alive.clone());
        f(Guard {
            obs,
            rng: rng as *mut Stream,
            alive,
        })
    }

    fn obs(&self) -> PyResult<&dyn ObsApi> {
        if !self.alive.load(Ordering::SeqCst) {
            return Err(ended());
        }
        // SAFETY: `alive` is set, so `during` has not returned: the observation lives.
        Ok(unsafe { &*self.obs })
    }

    #[expect(
        clippy::mut_from_ref,
        reason = "the stream is the activation's, reached by one call at a time"
    )]
    fn rng(&self) -> PyResult<&mut Stream> {
        if !self.alive.load(Ordering::SeqCst) {
            return Err(ended());
        }
        // SAFETY: as for `obs`; the stream is the activation's own, reached by one call
        // at a time (Python holds the GIL for each, and the activation waits for
        // `decide` to return).
        Ok(unsafe { &mut *self.rng })
    }
}

fn ended() -> PyErr {
    PyRuntimeError::new_err(
        "this observation (or rng) belonged to an activation that has ended: use it only inside decide",
    )
}

/// The names of a Python algorithm's lights (empty: none), shared by its observations
/// and states.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Palette(pub Arc<[String]>);

impl Palette {
    /// The name of colour `k` (None without lights).
    pub fn name(&self, k: usize) -> Option<String> {
        self.0.get(k).cloned()
    }

    /// The index of `colour`: a name of the palette, or an index into it.
    pub fn index(&self, colour: &Bound<'_, PyAny>) -> PyResult<usize> {
        let listed = || {
            if self.0.is_empty() {
                "the algorithm declares no lights (monoculus.algorithm(..., lights=[...]))"
                    .to_string()
            } else {
                format!("its lights are {}", self.0.join(", "))
            }
        };
        if let Ok(name) = colour.extract::<String>() {
            return self
                .0
                .iter()
                .position(|n| *n == name)
                .ok_or_else(|| PyValueError::new_err(format!("light {name:?}: {}", listed())));
        }
        match colour.extract::<usize>() {
            Ok(k) if k < self.0.len().max(1) => Ok(k),
            Ok(k) => Err(PyValueError::new_err(format!(
                "light {k}: out of range; {}",
                listed()
            ))),
            Err(_) => Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "a light is a name or an index, not {}",
                colour.repr().map(|r| r.to_string()).unwrap_or_default()
            ))),
        }
    }
}

/// The robot's random stream: draw from it, and runs are reproducible whatever the
/// thread count.
#[pyclass(module = "monoculus")]
pub struct Rng {
    pub guard: Guard,
}

#[pymethods]
impl Rng {
    /// A uniform float in [0, 1).
    fn uniform(&self) -> PyResult<f64> {
        Ok(self.guard.rng()?.uniform())
    }

    /// A uniform integer in [0, n).
    fn below(&self, n: usize) -> PyResult<usize> {
        if n == 0 {
            return Err(PyValueError::new_err("below(n): n must be at least 1"));
        }
        Ok(self.guard.rng()?.below(n))
    }

    /// A standard normal float.
    fn normal(&self) -> PyResult<f64> {
        Ok(self.guard.rng()?.normal())
    }
}

fn vector<'py>(py: Python<'py>, v: Option<Vec<f64>>) -> Option<Bound<'py, PyArray1<f64>>> {
    v.map(|v| v.into_pyarray(py))
}

/// The guard of a Python `Rng` (its stream is reached through `Guard::rng`).
fn rng_of(rng: &Bound<'_, Rng>) -> Guard {
    rng.borrow().guard.clone()
}

fn directions<'py>(py: Python<'py>, g: &Guard) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let o = g.obs()?;
    let d = o.directions();
    let dim = o.dim();
    let k = d.len() / dim;
    Ok(numpy::ndarray::Array2::from_shape_vec((k, dim), d)
        .expect("k rows of dim")
        .into_pyarray(py))
}

fn side(s: &str) -> PyResult<Side> {
    match s {
        "low" | "-" => Ok(Side::Low),
        "high" | "+" => Ok(Side::High),
        _ => Err(PyValueError::new_err(format!(
            "side {s:?}: \"low\" or \"high\""
        ))),
    }
}

/// The queries every model has, generated for each class.
macro_rules! observation_class {
    ($name:ident, $doc:literal, { $($extra:tt)* }) => {
        #[doc = $doc]
        #[pyclass(module = "monoculus")]
        pub struct $name {
            pub guard: Guard,
            pub params: Py<PyDict>,
            pub palette: Palette,
        }

        #[pymethods]
        impl $name {
            /// The dimension (2 or 3).
            #[getter]
            fn dim(&self) -> PyResult<usize> {
                Ok(self.guard.obs()?.dim())
            }

            /// The algorithm's parameters (a dict).
            #[getter]
            fn params(&self, py: Python<'_>) -> Py<PyDict> {
                self.params.clone_ref(py)
            }

            /// If exactly one point is visible, its direction; else None.
            fn sole_visible<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
                Ok(vector(py, self.guard.obs()?.sole_visible()))
            }

            /// The number of visible points, counted up to `limit`.
            fn count_visible_up_to(&self, limit: usize) -> PyResult<usize> {
                Ok(self.guard.obs()?.count_visible_up_to(limit))
            }

            /// The direction of a uniformly random visible point (or None), drawn from `rng`.
            fn random_visible<'py>(&self, py: Python<'py>, rng: &Bound<'_, Rng>) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
                Ok(vector(py, self.guard.obs()?.random_visible(rng_of(rng).rng()?)))
            }

            /// Every visible point's direction, a (k, dim) array (a full look).
            #[getter]
            fn directions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
                directions(py, &self.guard)
            }

            /// The colour each visible point's robot shows (an index into the
            /// algorithm's lights; 0 without lights), in the order of `directions`.
            #[getter]
            fn colours<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<i64>>> {
                let (_, l) = self.guard.obs()?.lit();
                Ok(l.into_iter().map(|c| c as i64).collect::<Vec<_>>().into_pyarray(py))
            }

            /// Every visible point as (direction, the name of the colour its robot
            /// shows), in the order of `directions` (None for names without lights).
            fn lit<'py>(&self, py: Python<'py>) -> PyResult<Vec<(Bound<'py, PyArray1<f64>>, Option<String>)>> {
                let o = self.guard.obs()?;
                let (d, l) = o.lit();
                Ok(d.chunks(o.dim())
                    .zip(l)
                    .map(|(d, c)| (d.to_vec().into_pyarray(py), self.palette.name(c)))
                    .collect())
            }

            /// The direction of a uniformly random visible point whose robot shows
            /// `colour` (a name of the algorithm's lights, or its index), or None.
            fn random_lit<'py>(
                &self,
                py: Python<'py>,
                colour: &Bound<'_, PyAny>,
                rng: &Bound<'_, Rng>,
            ) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
                let c = self.palette.index(colour)?;
                Ok(vector(py, self.guard.obs()?.random_lit(c, rng_of(rng).rng()?)))
            }

            /// Whether a visible point's robot shows `colour` (a name or an index).
            fn sees_light(&self, colour: &Bound<'_, PyAny>) -> PyResult<bool> {
                let c = self.palette.index(colour)?;
                Ok(self.guard.obs()?.sees_light(c))
            }

            /// The names of the algorithm's lights.
            #[getter]
            fn lights(&self) -> Vec<String> {
                self.palette.0.to_vec()
            }

            $($extra)*
        }
    };
}

observation_class!(
    DirectionsObservation,
    "What a robot of the `directions` model senses: directions only.",
    {}
);

observation_class!(
    LdObservation,
    "What a robot of the `ld` model senses: directions and far bits.",
    {
        /// The direction of a uniformly random visible point farther than c (or None).
        fn random_far<'py>(
            &self,
            py: Python<'py>,
            rng: &Bound<'_, Rng>,
        ) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
            Ok(vector(py, self.guard.obs()?.random_far(rng_of(rng).rng()?)))
        }

        /// Every visible point's far bit, in the order of `directions` (a full look).
        #[getter]
        fn far<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<bool>>> {
            Ok(self.guard.obs()?.seen().1.into_pyarray(py))
        }
    }
);

observation_class!(
    OlaObservation,
    "What a robot of the `ola` model senses: directions in the agreed axes, and the sides occupied.",
    {
        /// Whether a visible robot lies beyond the robot on `side` ("low" or "high") of local axis `axis`.
        fn side_occupied(&self, axis: usize, side: &str) -> PyResult<bool> {
            let o = self.guard.obs()?;
            if axis >= o.dim() {
                return Err(PyValueError::new_err(format!(
                    "axis {axis}: the axes are 0..{}",
                    o.dim()
                )));
            }
            Ok(o.side_occupied(axis, self::side(side)?))
        }

        /// For each local axis, [low occupied, high occupied].
        fn sides_occupied(&self) -> PyResult<Vec<[bool; 2]>> {
            let o = self.guard.obs()?;
            Ok((0..o.dim())
                .map(|k| {
                    [
                        o.side_occupied(k, Side::Low),
                        o.side_occupied(k, Side::High),
                    ]
                })
                .collect())
        }

        /// The direction of a uniformly random visible point in the closed orthant of
        /// `constraints` (pairs of local axis and "low"/"high"), or None.
        fn random_in_orthant<'py>(
            &self,
            py: Python<'py>,
            constraints: Vec<(usize, String)>,
            rng: &Bound<'_, Rng>,
        ) -> PyResult<Option<Bound<'py, PyArray1<f64>>>> {
            let o = self.guard.obs()?;
            let c: Vec<(usize, Side)> = constraints
                .iter()
                .map(|(a, s)| {
                    if *a >= o.dim() {
                        return Err(PyValueError::new_err(format!(
                            "axis {a}: the axes are 0..{}",
                            o.dim()
                        )));
                    }
                    Ok((*a, side(s)?))
                })
                .collect::<PyResult<_>>()?;
            Ok(vector(py, o.random_in_orthant(&c, rng_of(rng).rng()?)))
        }
    }
);

observation_class!(
    PositionsObservation,
    "What a robot of the `positions` model senses (baselines): the visible robots' positions.",
    {
        /// The visible points relative to the robot, a (k, dim) array.
        #[getter]
        fn relative_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
            let o = self.guard.obs()?;
            let p = o.relative_positions();
            let dim = o.dim();
            Ok(
                numpy::ndarray::Array2::from_shape_vec((p.len() / dim, dim), p)
                    .expect("rows")
                    .into_pyarray(py),
            )
        }
    }
);

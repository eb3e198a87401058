//! `monoculus.Simulation`: one run, stepped from Python.

use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use glam::{DVec2, DVec3};
use monoculus_core::geometry::Point;
use monoculus_engine::{EngineError, IndexPoint, RunOutcome, StoppedBy};
use monoculus_experiments::Experiment;
use monoculus_experiments::results::{param_values, run_row, runs_header};
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::{PyIndexError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::algorithm::Errors;
use crate::replay::{ReplayData, Start, limits, record_again};
use crate::{algorithm_error, interruptible};
use monoculus_experiments::replay::title;
use monoculus_experiments::replay::{Advance, advance};

enum Sim {
    Plane(monoculus_engine::Simulation<DVec2>),
    Space(monoculus_engine::Simulation<DVec3>),
}

macro_rules! each {
    ($sim:expr, $s:ident => $body:expr) => {
        match $sim {
            Sim::Plane($s) => $body,
            Sim::Space($s) => $body,
        }
    };
}

fn engine_error(e: EngineError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn points<P: IndexPoint>(positions: &PyReadonlyArray2<'_, f64>) -> PyResult<Vec<P>> {
    let a = positions.as_array();
    if a.ncols() != P::DIM {
        return Err(PyValueError::new_err(format!(
            "positions: an (n, {}) array for dim = {}, got {} columns",
            P::DIM,
            P::DIM,
            a.ncols()
        )));
    }
    Ok(a.rows()
        .into_iter()
        .map(|r| P::from_slice(&r.to_vec()))
        .collect())
}

/// One run of a config's cell and seed, stepped from Python.
#[pyclass(module = "monoculus")]
pub struct Simulation {
    sim: Option<Sim>,
    /// Where it started, and every call that advanced it since: what `replay` records
    /// again (a run is determined by its config, seed and start).
    start: Start,
    advances: Vec<Advance>,
    exp: Experiment,
    cell: usize,
    seed: u64,
    errors: Errors,
    started: Instant,
}

impl Simulation {
    fn sim(&mut self) -> PyResult<&mut Sim> {
        self.sim
            .as_mut()
            .ok_or_else(|| PyRuntimeError::new_err("this simulation stopped on an error"))
    }

    fn failed(&self, py: Python<'_>, outcome: &RunOutcome) -> PyResult<()> {
        match &outcome.failure {
            Some(f) => Err(algorithm_error(
                py,
                format!("the run failed: {f}"),
                &self.errors,
            )),
            None => Ok(()),
        }
    }
}

#[pymethods]
impl Simulation {
    #[new]
    #[pyo3(signature = (config, seed=0, cell=0, set=None, positions=None, algorithms=Vec::new()))]
    fn new(
        py: Python<'_>,
        config: &Bound<'_, PyAny>,
        seed: u64,
        cell: usize,
        set: Option<&Bound<'_, PyAny>>,
        positions: Option<PyReadonlyArray2<'_, f64>>,
        algorithms: Vec<Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let errors: Errors = Arc::new(Mutex::new(None));
        let registry = crate::declare::registry(&algorithms, &errors)?;
        let (exp, _) = crate::convert::experiment(py, config, set, &registry)?;
        let Some(c) = exp.cells.get(cell) else {
            return Err(PyIndexError::new_err(format!(
                "cell {cell}: the config has {} cells",
                exp.cells.len()
            )));
        };
        let config = c.sim_config(seed);
        let (sim, start) = match c.dim() {
            3 => {
                let start = match &positions {
                    Some(p) => points::<DVec3>(p)?,
                    None => c.initial_positions(seed),
                };
                let sim = monoculus_engine::Simulation::new(config, start.clone())
                    .map_err(engine_error)?;
                (Sim::Space(sim), Start::Space(start))
            }
            _ => {
                let start = match &positions {
                    Some(p) => points::<DVec2>(p)?,
                    None => c.initial_positions(seed),
                };
                let sim = monoculus_engine::Simulation::new(config, start.clone())
                    .map_err(engine_error)?;
                (Sim::Plane(sim), Start::Plane(start))
            }
        };
        Ok(Simulation {
            sim: Some(sim),
            start,
            advances: Vec::new(),
            exp,
            cell,
            seed,
            errors,
            started: Instant::now(),
        })
    }

    /// Advances one round (ASYNC: one epoch).
    fn step(&mut self, py: Python<'_>) -> PyResult<()> {
        let sim = self.sim()?;
        py.detach(|| each!(sim, s => advance(s, Advance::Step, |_| {})));
        self.advances.push(Advance::Step);
        let failure = each!(self.sim()?, s => s.failure());
        if let Some(f) = failure {
            return Err(algorithm_error(
                py,
                format!("the run failed: {f}"),
                &self.errors,
            ));
        }
        Ok(())
    }

    /// Runs to the stop criterion (or `max_rounds`, else the config's cap); the outcome
    /// as a dict of the runs.csv fields.
    #[pyo3(signature = (max_rounds=None))]
    fn run(&mut self, py: Python<'_>, max_rounds: Option<u64>) -> PyResult<Py<PyDict>> {
        let mut sim = self
            .sim
            .take()
            .ok_or_else(|| PyRuntimeError::new_err("this simulation stopped on an error"))?;
        let interrupt = Arc::new(AtomicBool::new(false));
        let flag = interrupt.clone();
        let result = interruptible(py, interrupt, move || {
            let outcome = each!(&mut sim, s => {
                if let Some(m) = max_rounds {
                    s.set_max_rounds(m);
                }
                s.set_interrupt(flag);
                s.run()
            });
            (sim, outcome)
        });
        let (sim, outcome) = result?;
        self.sim = Some(sim);
        self.advances.push(Advance::Run(max_rounds));
        self.failed(py, &outcome)?;
        let cell = &self.exp.cells[self.cell];
        let ms = self.started.elapsed().as_secs_f64() * 1e3;
        let params = param_values(&self.exp, cell);
        let row = run_row(&params, &self.exp, cell, self.seed, &outcome, ms);
        let d = PyDict::new(py);
        for (k, v) in runs_header(&self.exp).iter().zip(&row) {
            d.set_item(k, v)?;
        }
        Ok(d.unbind())
    }

    /// Every robot's position, an (n, dim) array (a copy; ASYNC: movers where they are).
    #[getter]
    fn positions<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (flat, dim) = each!(self.sim()?, s => {
            let pts = s.positions_now();
            (pts.iter().flat_map(|p| (0..p_dim(p)).map(|k| p.axis(k)).collect::<Vec<_>>()).collect::<Vec<f64>>(), s.positions().first().map_or(2, p_dim))
        });
        Ok(
            numpy::ndarray::Array2::from_shape_vec((flat.len() / dim, dim), flat)
                .expect("rows")
                .into_pyarray(py),
        )
    }

    /// The colour each robot shows now, by robot: indices into `light_names` (empty
    /// when the algorithm has no lights; ASYNC: the colour the others see).
    #[getter]
    fn lights<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, numpy::PyArray1<i64>>> {
        let l = each!(self.sim()?, s => s.lights_now());
        Ok(l.into_iter()
            .map(i64::from)
            .collect::<Vec<_>>()
            .into_pyarray(py))
    }

    /// The names of the algorithm's lights (empty: it has none).
    #[getter]
    fn light_names(&self) -> Vec<String> {
        self.exp.cells[self.cell].algorithm().lights().to_vec()
    }

    /// Rounds completed (ASYNC: epochs).
    #[getter]
    fn round(&mut self) -> PyResult<u64> {
        Ok(each!(self.sim()?, s => s.rounds_done()))
    }

    /// Whether a run ending now would have converged: its stop criterion holds and its
    /// goal holds.
    #[getter]
    fn converged(&mut self) -> PyResult<bool> {
        Ok(each!(self.sim()?, s => s.criterion_met_now().is_some() && s.goal_holds_now()))
    }

    /// Whether the swarm is stuck now: quiescent (the stop criterion holds by
    /// quiescence) short of its goal.
    #[getter]
    fn stuck(&mut self) -> PyResult<bool> {
        Ok(each!(self.sim()?, s => {
            s.criterion_met_now() == Some(StoppedBy::Quiescent) && !s.goal_holds_now()
        }))
    }

    /// What would end a run now (`quiescent`, `diameter`, `box`), or None.
    #[getter]
    fn stopped_by(&mut self) -> PyResult<Option<&'static str>> {
        Ok(each!(self.sim()?, s => s.criterion_met_now().map(StoppedBy::name)))
    }

    /// Whether the goal holds now.
    #[getter]
    fn goal_met(&mut self) -> PyResult<bool> {
        Ok(each!(self.sim()?, s => s.goal_holds_now()))
    }

    /// The goal the run is judged by: `diameter`, `disc` or `box`.
    #[getter]
    fn goal(&mut self) -> PyResult<&'static str> {
        Ok(each!(self.sim()?, s => s.config().stop.goal.name()))
    }

    /// The radius of the smallest disc (ball) holding the correct robots now.
    #[getter]
    fn radius(&mut self) -> PyResult<f64> {
        Ok(each!(self.sim()?, s => s.enclosing_radius()))
    }

    /// The swarm's diameter now (correct robots).
    #[getter]
    fn diameter(&mut self) -> PyResult<f64> {
        Ok(each!(self.sim()?, s => s.shape().1))
    }

    /// The area (3D: volume) of the swarm's convex hull now (correct robots).
    #[getter]
    fn hull_area(&mut self) -> PyResult<f64> {
        Ok(each!(self.sim()?, s => s.shape().0))
    }

    /// The replay of this simulation so far: the run recorded again from its start
    /// through the same steps and runs (the same run, bit for bit); Ctrl-C stops it.
    #[pyo3(signature = (max_drawn, max_mb))]
    fn replay(&mut self, py: Python<'_>, max_drawn: usize, max_mb: usize) -> PyResult<ReplayData> {
        self.sim()?;
        let limits = limits(max_drawn, max_mb)?;
        let cell = self.exp.cells[self.cell].clone();
        let heading = format!(
            "{}, stepped from Python",
            title(&self.exp.name, &cell, self.seed)
        );
        let (seed, advances) = (self.seed, self.advances.clone());
        let start = self.start.clone();
        let interrupt = Arc::new(AtomicBool::new(false));
        let flag = interrupt.clone();
        let recorded = interruptible(py, interrupt, move || {
            record_again(&cell, seed, start, &advances, heading, limits, flag)
        })?;
        Ok(ReplayData::new(recorded.map_err(engine_error)?))
    }

    /// What robot `robot` sees now, as `monoculus look` prints it (CSV text).
    fn look(&mut self, robot: usize) -> PyResult<String> {
        let cell = &self.exp.cells[self.cell];
        let model = cell.algorithm().model();
        let locality = cell.spec.algorithm.locality;
        let sim = self
            .sim
            .as_mut()
            .ok_or_else(|| PyRuntimeError::new_err("this simulation stopped on an error"))?;
        each!(sim, s => {
            let pts = s.positions_now();
            if robot >= pts.len() {
                return Err(PyIndexError::new_err(format!("robot {robot}: the swarm has {} robots", pts.len())));
            }
            Ok(monoculus_experiments::look::look_csv(pts, robot, model, locality))
        })
    }
}

fn p_dim<P: Point>(_: &P) -> usize {
    P::DIM
}

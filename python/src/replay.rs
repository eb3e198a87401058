//! `monoculus.replay` and `Simulation.replay()`: a recorded run, as the replay page
//! (`monoculus replay`'s HTML) and its GIF.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::sync::{Arc, Mutex};

use glam::{DVec2, DVec3};

use monoculus_experiments::replay::{Advance, Limits, Replay as Recorded, record_advances, title};
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::{PyIndexError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::algorithm::Errors;

/// The limits of a replay: `max_drawn` robots drawn, `max_mb` megabytes of frames.
pub(crate) fn limits(max_drawn: usize, max_mb: usize) -> PyResult<Limits> {
    if max_drawn == 0 || max_mb == 0 {
        return Err(PyValueError::new_err(
            "max_drawn and max_mb: at least 1 each",
        ));
    }
    Ok(Limits {
        max_drawn,
        max_bytes: max_mb << 20,
        ..Limits::default()
    })
}

/// A recorded run: its page (`html`), its GIF (`gif`), what it shows.
#[pyclass(module = "monoculus", frozen)]
pub struct ReplayData {
    replay: Recorded,
}

impl ReplayData {
    pub(crate) fn new(replay: Recorded) -> Self {
        ReplayData { replay }
    }
}

#[pymethods]
impl ReplayData {
    /// The self-contained replay page (HTML), as `monoculus replay --out` writes it.
    fn html(&self) -> String {
        monoculus_plot::replay_html(&self.replay)
    }

    /// Writes the animation as a GIF of `width` x `height` pixels.
    fn gif(&self, py: Python<'_>, path: PathBuf, width: u32, height: u32) -> PyResult<()> {
        if !(64..=4096).contains(&width) || !(64..=4096).contains(&height) {
            return Err(PyValueError::new_err(format!(
                "size ({width}, {height}): each side 64 to 4096 pixels"
            )));
        }
        py.detach(|| monoculus_plot::write_replay_gif(&self.replay, &path, (width, height)))
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }

    /// The title: experiment, cell, seed.
    #[getter]
    fn title(&self) -> &str {
        &self.replay.title
    }

    /// Algorithm, scheduler, robots: one line.
    #[getter]
    fn subtitle(&self) -> &str {
        &self.replay.subtitle
    }

    /// How the run ended (or where a stepped run is), one line.
    #[getter]
    fn outcome(&self) -> &str {
        &self.replay.outcome
    }

    /// `converged`, `stuck` or `not converged`.
    #[getter]
    fn verdict(&self) -> &str {
        self.replay.verdict
    }

    /// Frames kept.
    #[getter]
    fn frames(&self) -> usize {
        self.replay.frames.len()
    }

    /// The drawn robots' positions in frame `k` (negative from the end), an (m, dim)
    /// array of the single-precision coordinates the page draws.
    fn frame_positions<'py>(
        &self,
        py: Python<'py>,
        k: isize,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let frames = &self.replay.frames;
        let i = if k < 0 {
            frames.len().checked_sub(k.unsigned_abs())
        } else {
            Some(k as usize).filter(|&i| i < frames.len())
        };
        let Some(i) = i else {
            return Err(PyIndexError::new_err(format!(
                "frame {k}: the replay has {} frames",
                frames.len()
            )));
        };
        let dim = self.replay.dim;
        let flat = frames[i].positions.clone();
        Ok(
            numpy::ndarray::Array2::from_shape_vec((flat.len() / dim, dim), flat)
                .expect("rows of dim coordinates")
                .into_pyarray(py),
        )
    }
}

/// Records one run of `config`'s cell `cell` with `seed` (default: the config's first),
/// as `monoculus replay` does; Ctrl-C stops it (`KeyboardInterrupt`).
#[pyfunction]
#[pyo3(signature = (config, seed, cell, set, algorithms, max_drawn, max_mb))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn replay(
    py: Python<'_>,
    config: &Bound<'_, PyAny>,
    seed: Option<u64>,
    cell: usize,
    set: Option<&Bound<'_, PyAny>>,
    algorithms: Vec<Bound<'_, PyDict>>,
    max_drawn: usize,
    max_mb: usize,
) -> PyResult<ReplayData> {
    let errors: Errors = Arc::new(Mutex::new(None));
    let registry = crate::declare::registry(&algorithms, &errors)?;
    let (exp, _) = crate::convert::experiment(py, config, set, &registry)?;
    let limits = limits(max_drawn, max_mb)?;
    let Some(c) = exp.cells.get(cell) else {
        return Err(PyIndexError::new_err(format!(
            "cell {cell}: the config has {} cells",
            exp.cells.len()
        )));
    };
    let seed = seed.unwrap_or(exp.seeds[0]);
    let heading = title(&exp.name, c, seed);
    let start = Start::of(c, seed);
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = interrupt.clone();
    let recorded = crate::interruptible(py, interrupt, move || {
        let whole = [Advance::Run(None)];
        record_again(&exp.cells[cell], seed, start, &whole, heading, limits, flag)
    })?
    .map_err(|e| PyValueError::new_err(e.to_string()))?;
    if let Some(cause) = errors.lock().unwrap_or_else(|p| p.into_inner()).take() {
        let err = crate::convert::AlgorithmError::new_err(format!(
            "the run failed: {}",
            recorded.outcome
        ));
        err.set_cause(py, Some(cause));
        return Err(err);
    }
    Ok(ReplayData::new(recorded))
}

/// Where a simulation starts: the plane's points or space's.
#[derive(Clone)]
pub(crate) enum Start {
    Plane(Vec<DVec2>),
    Space(Vec<DVec3>),
}

impl Start {
    /// The start the config gives `cell` with `seed`.
    pub(crate) fn of(cell: &monoculus_experiments::Cell, seed: u64) -> Start {
        match cell.dim() {
            3 => Start::Space(cell.initial_positions(seed)),
            _ => Start::Plane(cell.initial_positions(seed)),
        }
    }
}

/// Records a simulation again: from `start`, the `advances` it was given, in order
/// (`[Advance::Run(None)]`: a whole run, as `record` makes it). Setting `interrupt`
/// stops it at the end of a round.
pub(crate) fn record_again(
    cell: &monoculus_experiments::Cell,
    seed: u64,
    start: Start,
    advances: &[Advance],
    title: String,
    limits: Limits,
    interrupt: Arc<AtomicBool>,
) -> Result<Recorded, monoculus_engine::EngineError> {
    match start {
        Start::Plane(p) => record_advances(cell, seed, p, advances, title, limits, interrupt),
        Start::Space(p) => record_advances(cell, seed, p, advances, title, limits, interrupt),
    }
}

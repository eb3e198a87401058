//! `monoculus._native`: the Rust engine under the `monoculus` Python package. The
//! package's Python layer (`monoculus/__init__.py`) is the public face; this module
//! runs sweeps ([`run`]), steps simulations ([`simulation::Simulation`]) and turns
//! Python functions into algorithms ([`algorithm`]).

mod algorithm;
mod convert;
mod declare;
mod observation;
mod replay;
mod simulation;
mod threads;

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::RecvTimeoutError;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use monoculus_experiments::results::ResultsError;
use monoculus_experiments::{RunOptions, SweepError, SweepReport, run_experiment};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::algorithm::Errors;
use crate::convert::{AlgorithmError, ConfigError};
use crate::declare::Spec;

/// Runs `work` on a thread of its own while this one, detached from Python, checks for
/// Ctrl-C every 50 ms: then `interrupt` is set (the work stops at the end of its current
/// round) and, once the work has stopped, `KeyboardInterrupt` is raised.
pub(crate) fn interruptible<T: Send + 'static>(
    py: Python<'_>,
    interrupt: Arc<AtomicBool>,
    work: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let (tx, rx) = std::sync::mpsc::channel();
    let rx = Mutex::new(rx);
    let handle = std::thread::spawn(move || {
        let out = work();
        threads::release_thread_state();
        let _ = tx.send(out);
    });
    loop {
        let got = py.detach(|| {
            rx.lock()
                .unwrap_or_else(|p| p.into_inner())
                .recv_timeout(Duration::from_millis(50))
        });
        match got {
            Ok(v) => {
                let _ = handle.join();
                return Ok(v);
            }
            Err(RecvTimeoutError::Timeout) => {
                if let Err(e) = py.check_signals() {
                    interrupt.store(true, Ordering::Relaxed);
                    let _ = py.detach(|| rx.lock().unwrap_or_else(|p| p.into_inner()).recv());
                    let _ = handle.join();
                    return Err(e);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                let _ = handle.join();
                return Err(PyRuntimeError::new_err(
                    "monoculus stopped on an internal error (a bug: please report it)",
                ));
            }
        }
    }
}

/// `monoculus.AlgorithmError` for runs that failed, with the Python exception of the
/// first (if a Python algorithm raised one) as its cause.
pub(crate) fn algorithm_error(py: Python<'_>, message: String, errors: &Errors) -> PyErr {
    let err = AlgorithmError::new_err(message);
    if let Some(cause) = errors.lock().unwrap_or_else(|p| p.into_inner()).take() {
        err.set_cause(py, Some(cause));
    }
    err
}

fn results_error(e: SweepError) -> PyErr {
    match e {
        // The command line's "use --force" is `force=True` here.
        SweepError::Results(r @ (ResultsError::Mismatch { .. } | ResultsError::Corrupt { .. })) => {
            ConfigError::new_err(
                r.to_string()
                    .replace("another --out", "another out= folder")
                    .replace("--force", "force=True"),
            )
        }
        other => PyRuntimeError::new_err(other.to_string()),
    }
}

/// Runs every cell x seed of `config` into the results folder `out` (resuming it), as
/// `monoculus run` does; `algorithms` are the Python algorithms declared so far.
#[pyfunction]
#[pyo3(signature = (config, set, out, threads, algorithms, force=false))]
fn run(
    py: Python<'_>,
    config: &Bound<'_, PyAny>,
    set: Option<&Bound<'_, PyAny>>,
    out: PathBuf,
    threads: Option<usize>,
    algorithms: Vec<Bound<'_, PyDict>>,
    force: bool,
) -> PyResult<()> {
    let errors: Errors = Arc::new(Mutex::new(None));
    let registry = declare::registry(&algorithms, &errors)?;
    let (exp, _) = convert::experiment(py, config, set, &registry)?;
    if threads == Some(0) {
        return Err(PyValueError::new_err("threads: at least 1"));
    }
    let pool = threads::pool(threads).map_err(PyRuntimeError::new_err)?;
    let interrupt = Arc::new(AtomicBool::new(false));
    let options = RunOptions {
        interrupt: Some(interrupt.clone()),
        force,
        ..RunOptions::default()
    };
    let report: Result<SweepReport, SweepError> = interruptible(py, interrupt, move || {
        pool.install(|| run_experiment(&exp, &out, options, &()))
    })?;
    let report = report.map_err(results_error)?;
    if let Some((cell, seed, message)) = report.failed.first() {
        let cell = if cell.is_empty() { "-" } else { cell };
        // The Python layer adds where the failures are (a DataFrame on the exception,
        // and the results folder's failures.csv when it is kept).
        return Err(algorithm_error(
            py,
            format!(
                "{} of {} runs failed: cell {cell}, seed {seed}: {message}",
                report.failed.len(),
                report.total,
            ),
            &errors,
        ));
    }
    Ok(())
}

/// Hunts with the `[hunt]` section of `config` (one cell, or `cell`), as `monoculus
/// hunt` does, writing the folder `out`; returns summary.json's text.
#[pyfunction]
#[pyo3(signature = (config, set, out, threads, algorithms, cell=None))]
fn hunt(
    py: Python<'_>,
    config: &Bound<'_, PyAny>,
    set: Option<&Bound<'_, PyAny>>,
    out: PathBuf,
    threads: Option<usize>,
    algorithms: Vec<Bound<'_, PyDict>>,
    cell: Option<usize>,
) -> PyResult<String> {
    use monoculus_experiments::hunt::{FolderWriter, Hunt, HuntOptions, HuntReport};
    let errors: Errors = Arc::new(Mutex::new(None));
    let registry = declare::registry(&algorithms, &errors)?;
    let (exp, path) = convert::experiment(py, config, set, &registry)?;
    let label = path.map_or_else(|| convert::DICT.to_string(), |p| p.display().to_string());
    let picked = match (cell, exp.cells.len()) {
        (Some(k), n) if k < n => k,
        (None, 1) => 0,
        (Some(k), n) => {
            return Err(PyValueError::new_err(format!(
                "cell {k}: the config has {n} cells"
            )));
        }
        (None, n) => {
            let whose = if label == convert::DICT {
                "the config dict".to_string()
            } else {
                label
            };
            return Err(ConfigError::new_err(format!(
                "{whose}: the config has {n} cells; choose one with cell=K or fix the swept keys with set"
            )));
        }
    };
    let hunt =
        Hunt::new(&exp, &exp.cells[picked], &label).map_err(|e| convert::config_error(py, &e))?;
    if threads == Some(0) {
        return Err(PyValueError::new_err("threads: at least 1"));
    }
    let pool = threads::pool(threads).map_err(PyRuntimeError::new_err)?;
    let interrupt = Arc::new(AtomicBool::new(false));
    let flag = interrupt.clone();
    let written: Result<String, String> = interruptible(py, interrupt, move || {
        let html = |replay: &monoculus_experiments::replay::Replay, path: &std::path::Path| {
            monoculus_plot::write_replay_html(replay, path).map_err(|e| e.to_string())
        };
        let writer = FolderWriter::new(&out, &hunt, &registry, Some(&html));
        let report = pool.install(|| {
            hunt.run(&HuntOptions {
                interrupt: Some(flag),
                on_progress: Some(&|_| writer.on_progress()),
                on_best: Some(&|r: &HuntReport| writer.on_best(r)),
            })
        });
        writer.finish(&report)?;
        Ok(monoculus_experiments::hunt::summary_json(&hunt, &report))
    })?;
    written.map_err(PyRuntimeError::new_err)
}

/// Checks a declaration of `monoculus.algorithm` (its name, sensing, memory, params,
/// stop, goal, lights): a name a built-in algorithm has, or that is not a plain
/// snake-case name, is refused here, at the decorator.
#[pyfunction]
fn check_algorithm(declaration: &Bound<'_, PyDict>) -> PyResult<()> {
    Spec::read(declaration)?;
    let errors: Errors = Arc::new(Mutex::new(None));
    declare::registry(std::slice::from_ref(declaration), &errors).map(|_| ())
}

/// A row of `monoculus.algorithms()`: name, source, sensing, stop, goal, lights.
type AlgorithmRow = (String, String, String, String, String, Vec<String>);

/// Every algorithm a sweep may name: the built-ins, then the Python `declarations`.
#[pyfunction]
fn algorithm_table(declarations: Vec<Bound<'_, PyDict>>) -> PyResult<Vec<AlgorithmRow>> {
    let errors: Errors = Arc::new(Mutex::new(None));
    let registry = declare::registry(&declarations, &errors)?;
    let builtin = monoculus_experiments::Registry::builtin();
    registry
        .names()
        .into_iter()
        .map(|name| {
            let entry = registry.get(name).expect("a registered name");
            let (algorithm, _) = entry
                .make(&toml::Table::new())
                .map_err(|e| PyValueError::new_err(format!("{name}: {}", e.message)))?;
            let source = if builtin.get(name).is_some() {
                "built-in"
            } else {
                "python"
            };
            Ok((
                name.to_string(),
                source.to_string(),
                entry.model().name().to_string(),
                algorithm.default_stop().name().to_string(),
                algorithm.goal().name().to_string(),
                algorithm.lights().to_vec(),
            ))
        })
        .collect()
}

/// Silences the default panic message of an algorithm's panic (it becomes the run's
/// failure, reported with the run); other panics are reported as usual.
fn quiet_algorithm_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !monoculus_core::algorithms::in_algorithm() {
                default(info);
            }
        }));
    });
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    quiet_algorithm_panics();
    // The package's version is the crate's (pyproject.toml takes it from Cargo.toml).
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(check_algorithm, m)?)?;
    m.add_function(wrap_pyfunction!(algorithm_table, m)?)?;
    m.add_function(wrap_pyfunction!(hunt, m)?)?;
    m.add_function(wrap_pyfunction!(replay::replay, m)?)?;
    m.add_class::<replay::ReplayData>()?;
    m.add_class::<simulation::Simulation>()?;
    m.add_class::<observation::Rng>()?;
    m.add_class::<algorithm::State>()?;
    m.add_class::<observation::DirectionsObservation>()?;
    m.add_class::<observation::LdObservation>()?;
    m.add_class::<observation::OlaObservation>()?;
    m.add_class::<observation::PositionsObservation>()?;
    m.add("ConfigError", m.py().get_type::<ConfigError>())?;
    m.add("AlgorithmError", m.py().get_type::<AlgorithmError>())?;
    Ok(())
}

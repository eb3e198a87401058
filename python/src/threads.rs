//! The threads that call Python algorithms, made cheap to enter Python from.
//!
//! Python algorithms are called from the engine's worker threads, which Python does not
//! know. Entering Python from such a thread creates a Python thread state, and leaving it
//! destroys the state again: a few microseconds per call, more than the rest of an
//! activation. So each such thread keeps one state from its first call on
//! ([`keep_thread_state`]), and entering Python is then taking the GIL.
//!
//! A state is kept for as long as its thread lives: the worker threads belong to pools
//! that live as long as the process ([`pool`]), a few threads per thread count asked
//! for; a thread that ends sooner (the thread a sweep's work starts on) gives its state
//! back first ([`release_thread_state`]).

use std::cell::Cell;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use pyo3::ffi;

thread_local! {
    static KEPT: Cell<Option<(ffi::PyGILState_STATE, *mut ffi::PyThreadState)>> =
        const { Cell::new(None) };
}

/// Gives this thread a Python thread state it keeps, if it has none: call it, not
/// attached to Python, before entering Python.
pub fn keep_thread_state() {
    KEPT.with(|kept| {
        if kept.get().is_some() {
            return;
        }
        // SAFETY: the interpreter is running (a Python call of the package is under
        // way); the thread has no thread state, so it does not hold the GIL: `Ensure`
        // creates its state and takes the GIL, which `SaveThread` releases at once.
        unsafe {
            if !ffi::PyGILState_GetThisThreadState().is_null() {
                return;
            }
            let gil = ffi::PyGILState_Ensure();
            let state = ffi::PyEval_SaveThread();
            kept.set(Some((gil, state)));
        }
    });
}

/// Gives back this thread's kept state (if it keeps one): call it, not attached to
/// Python, before a thread that may have called Python ends.
pub fn release_thread_state() {
    KEPT.with(|kept| {
        if let Some((gil, state)) = kept.take() {
            // SAFETY: `state` is this thread's, saved by `keep_thread_state`, and the
            // thread is not attached: restoring it takes the GIL, and `Release` balances
            // the `Ensure`, deleting the state and releasing the GIL.
            unsafe {
                ffi::PyEval_RestoreThread(state);
                ffi::PyGILState_Release(gil);
            }
        }
    });
}

/// The pool of `threads` worker threads (all cores if `None`), made on first use and
/// kept, so that its threads' Python states are made once.
pub fn pool(threads: Option<usize>) -> Result<Arc<rayon::ThreadPool>, String> {
    static POOLS: OnceLock<Mutex<HashMap<Option<usize>, Arc<rayon::ThreadPool>>>> = OnceLock::new();
    let mut pools = POOLS
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|p| p.into_inner());
    if let Some(p) = pools.get(&threads) {
        return Ok(p.clone());
    }
    let p = Arc::new(
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads.unwrap_or(0))
            .thread_name(|i| format!("monoculus-{i}"))
            .build()
            .map_err(|e| e.to_string())?,
    );
    pools.insert(threads, p.clone());
    Ok(p)
}

//! A run driven from outside (the Python package's `Simulation`, `monoculus explore`):
//! the calls that advanced it, and recording it again from its start through them.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use monoculus_engine::{EngineError, IndexPoint, RunOutcome, Simulation};

use super::{Limits, Recording, Replay};
use crate::Cell;

/// One call that advanced a run driven from outside.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Advance {
    /// One round (ASYNC: the event ticks up to the end of the epoch in progress).
    Step,
    /// To the stop criterion, or to `Some(max_rounds)` rounds (epochs) in all.
    Run(Option<u64>),
}

/// Advances `sim` as `advance` says, `on_step` seeing it after every step it takes;
/// the outcome of an [`Advance::Run`].
///
/// ```
/// use glam::DVec2;
/// use monoculus_core::algorithms::ConvergeLocality;
/// use monoculus_engine::prelude::*;
/// use monoculus_experiments::replay::{Advance, advance};
///
/// let config = SimConfig::paper(AlgorithmBox::new(ConvergeLocality), 1, 100);
/// let mut sim = Simulation::new(config, vec![DVec2::ZERO, DVec2::new(3.0, 0.0)]).unwrap();
/// let mut steps = 0;
/// assert!(advance(&mut sim, Advance::Step, |_| steps += 1).is_none());
/// let outcome = advance(&mut sim, Advance::Run(None), |_| steps += 1).unwrap();
/// assert!(outcome.converged);
/// assert_eq!(steps as u64, outcome.rounds);
/// ```
pub fn advance<P: IndexPoint>(
    sim: &mut Simulation<P>,
    advance: Advance,
    mut on_step: impl FnMut(&Simulation<P>),
) -> Option<RunOutcome> {
    match advance {
        Advance::Step => {
            match sim.async_progress() {
                None => {
                    sim.step();
                    on_step(sim);
                }
                Some((_, epochs)) => {
                    while sim.async_progress().is_some_and(|(_, e)| e == epochs)
                        && sim.failure().is_none()
                    {
                        sim.step();
                        on_step(sim);
                    }
                }
            }
            None
        }
        Advance::Run(max_rounds) => {
            if let Some(m) = max_rounds {
                sim.set_max_rounds(m);
            }
            // `run_observed` first shows the state it starts from, seen already.
            let mut started = false;
            Some(sim.run_observed(|s| {
                if started {
                    on_step(s);
                }
                started = true;
            }))
        }
    }
}

/// Records a run of `cell` with `seed` again: from `start`, through the `advances` it
/// was given, in order (`[Advance::Run(None)]`: a whole run, as [`record`](super::record)
/// makes it). A run is determined by its config, seed and start, so this is the run
/// that was driven, bit for bit. Setting `interrupt` stops it at the end of a round.
///
/// ```
/// use std::path::Path;
/// use std::sync::Arc;
/// use std::sync::atomic::AtomicBool;
///
/// use glam::DVec2;
/// use monoculus_experiments::replay::{Advance, Limits, record_advances};
/// use monoculus_experiments::{Experiment, Registry};
///
/// let text = "name = \"doc\"\n[swarm]\nn = 5\ninit = \"square\"\nside = 3.0\n\
///             [algorithm]\nname = \"converge_locality\"\n";
/// let exp = Experiment::parse(text, "doc", Path::new("."), &[], &Registry::builtin()).unwrap();
/// let start: Vec<DVec2> = exp.cells[0].initial_positions(0);
/// let stop = Arc::new(AtomicBool::new(false));
/// let steps = [Advance::Step, Advance::Step];
/// let replay = record_advances(&exp.cells[0], 0, start, &steps, "doc".into(), Limits::default(), stop)
///     .unwrap();
/// assert_eq!(replay.frames.len(), 3);
/// ```
pub fn record_advances<P: IndexPoint>(
    cell: &Cell,
    seed: u64,
    start: Vec<P>,
    advances: &[Advance],
    title: String,
    limits: Limits,
    interrupt: Arc<AtomicBool>,
) -> Result<Replay, EngineError> {
    let mut recording = Recording::new(cell, seed, &start, title, limits);
    let mut sim = Simulation::new(cell.sim_config(seed), start)?;
    sim.set_interrupt(interrupt.clone());
    recording.observe(&sim);
    let mut outcome = None;
    for &a in advances {
        outcome = advance(&mut sim, a, |s| recording.observe(s));
        if sim.failure().is_some() || interrupt.load(Ordering::Relaxed) {
            break;
        }
    }
    Ok(recording.finish(&mut sim, outcome.as_ref()))
}

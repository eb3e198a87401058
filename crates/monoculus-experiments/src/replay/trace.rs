//! A replay of a trace of positions (`monoculus trace --positions`).

use glam::{DVec2, DVec3};
use monoculus_engine::IndexPoint;
use monoculus_engine::resources::Shape;

use super::{Drawn, Frame, Limits, Replay, State, frame_bytes, hull_of, ordinal};
use crate::positions::TracePositions;

/// A replay of a `monoculus trace --positions` file: a frame per round, robots that move
/// in the next round coloured moving; no Looks (a trace holds positions only).
pub fn from_trace(trace: &TracePositions, title: String, limits: Limits) -> Replay {
    if trace.has_z {
        from_trace_in::<DVec3>(trace, title, limits)
    } else {
        from_trace_in::<DVec2>(trace, title, limits)
    }
}

fn from_trace_in<P: IndexPoint>(trace: &TracePositions, title: String, limits: Limits) -> Replay {
    let rounds: Vec<Vec<P>> = trace
        .rounds
        .iter()
        .map(|r| r.iter().map(|c| P::from_slice(c)).collect())
        .collect();
    let n = rounds[0].len();
    let drawn = Drawn::of(n, &limits);
    let mut replay = Replay {
        outcome: format!("{} rounds traced", rounds.len() - 1),
        lights: trace.light_names.clone(),
        looks_note: Some("a trace holds positions only: no Looks to show".to_string()),
        ..Replay::begin(
            title,
            format!("{n} robots in {}D, from a trace", P::DIM),
            &rounds[0],
            &drawn,
        )
    };
    let mut bytes = 0;
    for (k, now) in rounds.iter().enumerate() {
        let next = rounds.get(k + 1);
        let moves = |i: usize| next.is_some_and(|next| next[i] != now[i]);
        let shape = Shape::of(now);
        let m = &mut replay.metrics;
        m.step.push(k);
        m.time.push(k as u64);
        m.hull.push(shape.hull);
        m.diameter.push(shape.diameter);
        m.moving.push((0..n).filter(|&i| moves(i)).count() as u64);
        if k.is_multiple_of(replay.stride) || k + 1 == rounds.len() {
            let frame = Frame {
                step: k,
                row: k,
                positions: drawn.coords(now),
                states: drawn
                    .robots
                    .iter()
                    .map(|&i| {
                        if moves(i) {
                            State::Moving as u8
                        } else {
                            State::Idle as u8
                        }
                    })
                    .collect(),
                bits: Vec::new(),
                lights: trace.lights.get(k).map_or(Vec::new(), |l| drawn.lights(l)),
                hull: hull_of(now),
            };
            bytes += frame_bytes(&frame);
            replay.frames.push(frame);
            if bytes > limits.max_bytes && k + 1 < rounds.len() {
                replay.thin();
                bytes = replay.bytes();
            }
        }
    }
    replay.notes.extend(drawn.note(n));
    if replay.stride > 1 {
        replay.notes.push(format!(
            "every {} round kept as a frame (and the last); metrics for every one",
            ordinal(replay.stride)
        ));
    }
    replay
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::positions::parse_trace_positions;

    #[test]
    fn a_trace_file_replays_its_rounds() {
        let text = "round,robot,x,y\n0,0,0,0\n0,1,4,0\n0,2,0,3\n1,0,1,0\n1,1,4,0\n1,2,0,3\n";
        let trace = parse_trace_positions(text, "t.positions.csv").unwrap();
        let r = from_trace(&trace, "t".into(), Limits::default());
        assert_eq!(r.frames.len(), 2);
        assert_eq!(r.metrics.moving, vec![1, 0]);
        assert_eq!(r.frames[0].states, vec![State::Moving as u8, 0, 0]);
        assert_eq!(r.metrics.hull[0], 6.0);
        assert_eq!(r.metrics.diameter[0], 5.0);
        assert_eq!(r.frames[1].positions, vec![1.0, 0.0, 4.0, 0.0, 0.0, 3.0]);
        assert!(r.looks.is_empty() && r.looks_note.is_some());
    }
}

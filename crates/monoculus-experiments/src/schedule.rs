//! Schedule CSV (`scheduler.kind = "file"`, SPEC 9.4): header `round,robot`, one
//! activation per row, rounds 1-based and in increasing order, robots 0-based.

use std::path::Path;
use std::sync::Arc;

use monoculus_engine::{ActivationError, ActivationList};

use crate::positions::{Csv, PositionsError, parse_error};

/// A schedule read from a file, with where its largest robot index was written (so that
/// a swarm too small for it is reported at that line).
#[derive(Clone, Debug, PartialEq)]
pub struct ScheduleFile {
    /// The rounds and their robots.
    pub list: Arc<ActivationList>,
    /// The largest robot listed and the 1-based line of its first row.
    pub max_robot: (u32, usize),
}

impl ScheduleFile {
    /// Why the schedule cannot run on `n` robots, if it cannot: `file:line: ...`.
    pub fn check_robots(&self, n: usize, name: &str) -> Result<(), String> {
        within_swarm(self.max_robot, n, name)
    }
}

/// Why a file whose largest robot is `robot` (first on `line`) cannot run on `n` robots,
/// if it cannot: `file:line: ...`.
pub(crate) fn within_swarm(
    (robot, line): (u32, usize),
    n: usize,
    name: &str,
) -> Result<(), String> {
    if robot as usize >= n {
        return Err(format!(
            "{}:{line}: robot {robot}, but the swarm has {n} robots (numbered from 0)",
            crate::one_line(name)
        ));
    }
    Ok(())
}

/// The robot index of a CSV field (0-based, below [`monoculus_engine::MAX_ROBOTS`]), or
/// the message for row `line` of `name`.
pub(crate) fn robot_field(text: &str, name: &str, line: usize) -> Result<u32, PositionsError> {
    text.parse()
        .ok()
        .filter(|&r: &u32| (r as usize) < monoculus_engine::MAX_ROBOTS)
        .ok_or_else(|| {
            parse_error(
                name,
                line,
                format!("column robot: `{text}` is not a robot index (0, 1, ...)"),
            )
        })
}

/// Reads a schedule CSV (columns `round` and `robot`, in any order, and no others).
pub fn read_schedule(path: &Path) -> Result<ScheduleFile, PositionsError> {
    parse_schedule(
        &crate::positions::read_text(path)?,
        &path.display().to_string(),
    )
}

/// Parses a schedule CSV from text; `name` labels errors.
pub fn parse_schedule(text: &str, name: &str) -> Result<ScheduleFile, PositionsError> {
    let mut csv = Csv::new(text, name)?;
    csv.exact(&["round", "robot"], &[])?;
    let [ri, bi] = csv.columns(["round", "robot"])?;
    let perr = |line: usize, message: String| parse_error(name, line, message);
    let mut rounds: Vec<(u64, Vec<u32>)> = Vec::new();
    let mut in_round = std::collections::HashSet::new();
    let mut max_robot: Option<(u32, usize)> = None;
    for row in csv.rows() {
        let (line, record) = row?;
        let field = |i: usize| record.get(i).unwrap_or("");
        let round: u64 = field(ri).parse().map_err(|_| {
            perr(
                line,
                format!(
                    "column round: `{}` is not a round number (1, 2, ...)",
                    field(ri)
                ),
            )
        })?;
        let robot = robot_field(field(bi), name, line)?;
        let problem = match rounds.last_mut() {
            _ if round == 0 => Some(ActivationError::RoundZero),
            Some((last, _)) if *last == round && !in_round.insert(robot) => {
                Some(ActivationError::Twice { round, robot })
            }
            Some((last, robots)) if *last == round => {
                robots.push(robot);
                None
            }
            Some((last, _)) if *last > round => Some(ActivationError::NotIncreasing {
                round,
                previous: *last,
            }),
            _ => {
                in_round.clear();
                in_round.insert(robot);
                rounds.push((round, vec![robot]));
                None
            }
        };
        if let Some(problem) = problem {
            return Err(perr(line, problem.to_string()));
        }
        if max_robot.is_none_or(|(m, _)| robot > m) {
            max_robot = Some((robot, line));
        }
    }
    let Some(max_robot) = max_robot else {
        return Err(perr(1, "no rows: the schedule activates nobody".into()));
    };
    let list = ActivationList::new(rounds).map_err(|e| perr(0, e.to_string()))?;
    Ok(ScheduleFile {
        list: Arc::new(list),
        max_robot,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse_schedule(text, "s.csv").unwrap_err().to_string()
    }

    #[test]
    fn reads_rounds_and_gaps() {
        let s = parse_schedule("round,robot\n1,0\n1,2\n3,1\n", "s.csv").unwrap();
        assert_eq!(s.list.rounds(), 3);
        assert_eq!(s.list.round(1), &[0, 2]);
        assert!(s.list.round(2).is_empty());
        assert_eq!(s.list.round(3), &[1]);
        assert_eq!(s.max_robot, (2, 3));
        assert!(s.check_robots(3, "s.csv").is_ok());
        assert_eq!(
            s.check_robots(2, "s.csv").unwrap_err(),
            "s.csv:3: robot 2, but the swarm has 2 robots (numbered from 0)"
        );
    }

    #[test]
    fn names_the_line_of_each_mistake() {
        assert_eq!(
            err("round,robot\n2,0\n1,1\n"),
            "s.csv:3: round 1 after round 2: rounds must increase"
        );
        assert_eq!(
            err("round,robot\n1,0\n1,4\n1,0\n"),
            "s.csv:4: robot 0 is listed twice in round 1"
        );
        assert_eq!(
            err("round,robot\n0,1\n"),
            "s.csv:2: round 0: rounds are numbered from 1"
        );
        assert!(err("round,robot\n1,-1\n").starts_with("s.csv:2: column robot"));
        assert!(err("round,robot\nx,1\n").starts_with("s.csv:2: column round"));
        assert!(err("step,robot\n1,1\n").starts_with("s.csv:1: header must name"));
        assert_eq!(
            err("round,robot\n"),
            "s.csv:1: no rows: the schedule activates nobody"
        );
    }
}

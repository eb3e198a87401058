//! Durations CSV (`scheduler.durations`, ASYNC): header `robot,cycle,phase,ticks`, one
//! given phase length per row: phase `idle`, `compute` or `move` of the robot's cycle
//! (both 0-based) lasts `ticks` instead of a draw from its distribution.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use monoculus_engine::asynchrony::{Durations, GivenDuration, Phase, phase_name};

use crate::positions::{Csv, PositionsError, parse_error};

/// Durations read from a file, with the lines that checks against the run need.
#[derive(Clone, Debug, PartialEq)]
pub struct DurationsFile {
    /// The durations.
    pub durations: Arc<Durations>,
    /// The largest robot given and the 1-based line of its first row.
    pub max_robot: (u32, usize),
    /// The first row giving cycle 0 an Idle phase (robot, line), if any: that phase
    /// exists only when the robots start at random.
    pub start_row: Option<(u32, usize)>,
}

impl DurationsFile {
    /// Why the durations cannot apply to a run of `n` robots whose robots start
    /// together (`together`) or at random, if they cannot: `file:line: ...`.
    ///
    /// ```
    /// use monoculus_experiments::durations::parse_durations;
    ///
    /// let f = parse_durations("robot,cycle,phase,ticks\n4,0,idle,2\n", "d.csv").unwrap();
    /// assert!(f.check(5, false, "d.csv").is_ok());
    /// assert!(f.check(4, false, "d.csv").unwrap_err().starts_with("d.csv:2: robot 4"));
    /// assert!(f.check(5, true, "d.csv").is_err()); // no idle phase in cycle 0
    /// ```
    pub fn check(&self, n: usize, together: bool, name: &str) -> Result<(), String> {
        crate::schedule::within_swarm(self.max_robot, n, name)?;
        let name = crate::one_line(name);
        if let (true, Some((robot, line))) = (together, self.start_row) {
            return Err(format!(
                "{name}:{line}: robot {robot}'s cycle 0 has no idle phase: with scheduler.start = \"together\" every robot Looks at tick 0 (give cycle 0 an idle phase only with start = \"random\")"
            ));
        }
        Ok(())
    }
}

/// Reads a durations CSV (columns `robot`, `cycle`, `phase`, `ticks`, in any order, and
/// no others).
pub fn read_durations(path: &Path) -> Result<DurationsFile, PositionsError> {
    parse_durations(
        &crate::positions::read_text(path)?,
        &path.display().to_string(),
    )
}

/// Parses a durations CSV from text; `name` labels errors.
///
/// ```
/// use monoculus_engine::asynchrony::Phase;
/// use monoculus_experiments::durations::parse_durations;
///
/// let f = parse_durations("robot,cycle,phase,ticks\n0,3,move,20\n", "d.csv").unwrap();
/// assert_eq!(f.durations.get(0, 3, Phase::Move), Some(20));
/// let bad = parse_durations("robot,cycle,phase,ticks\n0,3,walk,20\n", "d.csv");
/// assert!(bad.unwrap_err().to_string().starts_with("d.csv:2: column phase"));
/// ```
pub fn parse_durations(text: &str, name: &str) -> Result<DurationsFile, PositionsError> {
    let mut csv = Csv::new(text, name)?;
    csv.exact(&["robot", "cycle", "phase", "ticks"], &[])?;
    let [ri, ci, pi, ti] = csv.columns(["robot", "cycle", "phase", "ticks"])?;
    let perr = |line: usize, message: String| parse_error(name, line, message);
    let mut given = Vec::new();
    let mut lines: HashMap<(u32, u64, Phase), usize> = HashMap::new();
    let mut max_robot: Option<(u32, usize)> = None;
    let mut start_row = None;
    for row in csv.rows() {
        let (line, record) = row?;
        let field = |i: usize| record.get(i).unwrap_or("").trim().to_string();
        let robot = crate::schedule::robot_field(&field(ri), name, line)?;
        let cycle: u64 = field(ci).parse().map_err(|_| {
            perr(
                line,
                format!(
                    "column cycle: `{}` is not a cycle number (0, 1, ...)",
                    field(ci)
                ),
            )
        })?;
        let phase = match field(pi).as_str() {
            "idle" => Phase::Idle,
            "compute" => Phase::Compute,
            "move" => Phase::Move,
            other => {
                return Err(perr(
                    line,
                    format!("column phase: `{other}` is not idle, compute or move"),
                ));
            }
        };
        let ticks: u64 = field(ti)
            .parse()
            .ok()
            .filter(|&t| (1..=monoculus_engine::asynchrony::MAX_PHASE_TICKS).contains(&t))
            .ok_or_else(|| {
                perr(
                    line,
                    format!(
                        "column ticks: `{}` is not a whole number of ticks from 1 to 2^40",
                        field(ti)
                    ),
                )
            })?;
        if let Some(first) = lines.insert((robot, cycle, phase), line) {
            return Err(perr(
                line,
                format!(
                    "the {} phase of robot {robot}'s cycle {cycle} is given twice (first on line {first})",
                    phase_name(phase)
                ),
            ));
        }
        if max_robot.is_none_or(|(m, _)| robot > m) {
            max_robot = Some((robot, line));
        }
        if cycle == 0 && phase == Phase::Idle && start_row.is_none() {
            start_row = Some((robot, line));
        }
        given.push(GivenDuration {
            robot,
            cycle,
            phase,
            ticks,
        });
    }
    let Some(max_robot) = max_robot else {
        return Err(perr(1, "no rows: the file gives no duration".into()));
    };
    let durations = Durations::new(given).map_err(|e| perr(0, e.to_string()))?;
    Ok(DurationsFile {
        durations: Arc::new(durations),
        max_robot,
        start_row,
    })
}

/// The CSV of `durations` (header `robot,cycle,phase,ticks`, by robot, cycle and phase):
/// what [`parse_durations`] reads back.
///
/// ```
/// use monoculus_experiments::durations::{durations_csv, parse_durations};
///
/// let text = "robot,cycle,phase,ticks\n2,0,move,9\n0,1,idle,3\n";
/// let read = parse_durations(text, "d.csv").unwrap();
/// assert_eq!(
///     durations_csv(&read.durations),
///     "robot,cycle,phase,ticks\n0,1,idle,3\n2,0,move,9\n"
/// );
/// ```
pub fn durations_csv(durations: &Durations) -> String {
    let mut out = String::from("robot,cycle,phase,ticks\n");
    for g in durations.iter() {
        out.push_str(&format!(
            "{},{},{},{}\n",
            g.robot,
            g.cycle,
            phase_name(g.phase),
            g.ticks
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse_durations(text, "d.csv").unwrap_err().to_string()
    }

    #[test]
    fn reads_rows_in_any_column_order_and_writes_them_back() {
        let f = parse_durations(
            "phase,ticks,robot,cycle\ncompute,5,2,0\nidle,3,0,0\nmove,7,2,4\n",
            "d.csv",
        )
        .unwrap();
        assert_eq!(f.durations.get(2, 0, Phase::Compute), Some(5));
        assert_eq!(f.durations.get(0, 0, Phase::Idle), Some(3));
        assert_eq!(f.durations.get(2, 4, Phase::Move), Some(7));
        assert_eq!(f.max_robot, (2, 2));
        assert_eq!(f.start_row, Some((0, 3)));
        let text = durations_csv(&f.durations);
        assert_eq!(
            text,
            "robot,cycle,phase,ticks\n0,0,idle,3\n2,0,compute,5\n2,4,move,7\n"
        );
        assert_eq!(
            parse_durations(&text, "d.csv").unwrap().durations,
            f.durations
        );
        assert!(f.check(3, false, "d.csv").is_ok());
        assert_eq!(
            f.check(2, false, "d.csv").unwrap_err(),
            "d.csv:2: robot 2, but the swarm has 2 robots (numbered from 0)"
        );
        assert!(
            f.check(3, true, "d.csv")
                .unwrap_err()
                .starts_with("d.csv:3: robot 0's cycle 0 has no idle phase")
        );
    }

    #[test]
    fn names_the_line_of_each_mistake() {
        let h = "robot,cycle,phase,ticks\n";
        assert_eq!(
            err(&format!("{h}0,1,move,2\n0,1,move,3\n")),
            "d.csv:3: the move phase of robot 0's cycle 1 is given twice (first on line 2)"
        );
        assert!(err(&format!("{h}0,1,move,0\n")).starts_with("d.csv:2: column ticks: `0`"));
        assert!(err(&format!("{h}0,1,move,1099511627777\n")).starts_with("d.csv:2: column ticks"));
        assert!(err(&format!("{h}0,1,look,2\n")).starts_with("d.csv:2: column phase: `look`"));
        assert!(err(&format!("{h}-1,1,move,2\n")).starts_with("d.csv:2: column robot"));
        assert!(err(&format!("{h}0,x,move,2\n")).starts_with("d.csv:2: column cycle"));
        assert!(err("robot,cycle,phase\n0,1,move\n").starts_with("d.csv:1: header must name"));
        assert_eq!(err(h), "d.csv:1: no rows: the file gives no duration");
    }
}

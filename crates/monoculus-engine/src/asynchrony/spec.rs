//! [`AsyncSpec`]: the timing of the ASYNC scheduler.

use monoculus_core::rng::Stream;

/// A distribution of phase durations in whole ticks (every draw is at least 1); in
/// configs `{ kind = "fixed", ticks = 3 }`, `{ kind = "uniform", min = 1, max = 10 }` or
/// `{ kind = "exponential", mean = 5 }`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TickDist {
    /// Always this many ticks.
    Fixed {
        /// Ticks.
        ticks: u64,
    },
    /// Uniform on min..=max.
    Uniform {
        /// Shortest.
        min: u64,
        /// Longest.
        max: u64,
    },
    /// Exponential with this mean, rounded up to whole ticks.
    Exponential {
        /// Mean in ticks.
        mean: f64,
    },
}

impl TickDist {
    /// One tick.
    pub const ONE: TickDist = TickDist::Fixed { ticks: 1 };

    /// Reads `fixed:T`, `uniform:MIN:MAX` or `exp:MEAN` (the command line's form).
    pub fn parse(text: &str) -> Result<TickDist, String> {
        let bad = || {
            format!("`{text}`: expected fixed:T, uniform:MIN:MAX or exp:MEAN (ticks, at least 1)")
        };
        let parts: Vec<&str> = text.split(':').collect();
        let whole = |s: &str| s.trim().parse::<u64>().ok().filter(|&t| t >= 1);
        let d = match parts.as_slice() {
            ["fixed", t] => TickDist::Fixed {
                ticks: whole(t).ok_or_else(bad)?,
            },
            ["uniform", a, b] => {
                let (min, max) = (whole(a).ok_or_else(bad)?, whole(b).ok_or_else(bad)?);
                if max < min {
                    return Err(bad());
                }
                TickDist::Uniform { min, max }
            }
            ["exp", m] => {
                let mean: f64 = m.trim().parse().map_err(|_| bad())?;
                if !(mean > 0.0 && mean <= 1e12) {
                    return Err(bad());
                }
                TickDist::Exponential { mean }
            }
            _ => return Err(bad()),
        };
        Ok(d)
    }

    /// The command line's form of the distribution.
    pub fn label(&self) -> String {
        match *self {
            TickDist::Fixed { ticks } => format!("fixed:{ticks}"),
            TickDist::Uniform { min, max } => format!("uniform:{min}:{max}"),
            TickDist::Exponential { mean } => format!("exp:{mean}"),
        }
    }

    /// One draw, at least 1 tick.
    pub fn sample(&self, stream: &mut Stream) -> u64 {
        let t = match *self {
            TickDist::Fixed { ticks } => ticks,
            TickDist::Uniform { min, max } => min + stream.below((max - min + 1) as usize) as u64,
            TickDist::Exponential { mean } => (-mean * (1.0 - stream.uniform()).ln()).ceil() as u64,
        };
        t.max(1)
    }
}

/// How the robots start (`scheduler.start = "together" | "random"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AsyncStart {
    /// Every robot Looks at tick 0.
    #[default]
    Together,
    /// Every robot starts Idle for one draw of the idle distribution.
    Random,
}

/// The ASYNC scheduler's timing.
#[derive(Clone, Debug, PartialEq)]
pub struct AsyncSpec {
    /// Idle phase durations.
    pub idle: TickDist,
    /// Compute phase durations (between the Look and the start of the Move).
    pub compute: TickDist,
    /// Move phase durations (the robot moves linearly along its segment).
    pub motion: TickDist,
    /// Start offsets.
    pub start: AsyncStart,
    /// Durations given for single phases of single robots, in place of draws
    /// (`scheduler.durations`); `None`: every phase is drawn.
    pub durations: Option<std::sync::Arc<super::Durations>>,
}

/// The longest phase a duration distribution may draw, ticks (2^40, about 10^12): with
/// it, no clock of a run of [`AsyncSpec::MAX_TICKS`] can overflow.
pub const MAX_PHASE_TICKS: u64 = 1 << 40;

impl TickDist {
    /// The shortest duration a draw can give, ticks (a draw is at least 1).
    ///
    /// ```
    /// use monoculus_engine::TickDist;
    ///
    /// assert_eq!(TickDist::Uniform { min: 100, max: 500 }.shortest(), 100);
    /// assert_eq!(TickDist::Exponential { mean: 400.0 }.shortest(), 1);
    /// ```
    pub fn shortest(&self) -> u64 {
        match *self {
            TickDist::Fixed { ticks } => ticks,
            TickDist::Uniform { min, .. } => min,
            TickDist::Exponential { .. } => 1,
        }
        .max(1)
    }

    /// The longest duration a draw can give, ticks: an exponential draw is
    /// `ceil(-mean ln(1 - u))` with `u` of 53 bits, so at most 36.8 times the mean.
    pub fn longest(&self) -> f64 {
        match *self {
            TickDist::Fixed { ticks } => ticks as f64,
            TickDist::Uniform { max, .. } => max as f64,
            TickDist::Exponential { mean } => (mean * 36.8).ceil(),
        }
    }
}

impl AsyncSpec {
    /// The most ticks a run may reach (2^62): its clock, and every phase end it
    /// schedules, stay far from overflow.
    pub const MAX_TICKS: u64 = 1 << 62;

    /// Why a run of at most `max_epochs` epochs could overflow its clock, if it could:
    /// the phase (`idle`, `compute`, `move`) or `max_epochs` at fault, and what is
    /// wrong (`durations`: an Idle phase given to a cycle 0 that has none). A phase may
    /// last at most [`MAX_PHASE_TICKS`]; an epoch lasts at most two
    /// cycles, so `(max_epochs + 2)` twice-cycles must stay under [`AsyncSpec::MAX_TICKS`].
    ///
    /// ```
    /// use monoculus_engine::{AsyncSpec, TickDist};
    ///
    /// let fine = AsyncSpec::default();
    /// assert!(fine.check(100_000).is_ok());
    /// let huge = AsyncSpec { idle: TickDist::Fixed { ticks: 1 << 62 }, ..fine.clone() };
    /// assert_eq!(huge.check(100_000).unwrap_err().0, "idle");
    /// let far = AsyncSpec { idle: TickDist::Exponential { mean: 1e300 }, ..fine.clone() };
    /// assert_eq!(far.check(10).unwrap_err().0, "idle");
    /// ```
    pub fn check(&self, max_epochs: u64) -> Result<(), (&'static str, String)> {
        use super::Phase;
        let given = |phase: Phase| self.durations.as_ref().map_or(0, |d| d.longest(phase)) as f64;
        let mut cycle = 0.0;
        for (name, phase, d) in [
            ("idle", Phase::Idle, self.idle),
            ("compute", Phase::Compute, self.compute),
            ("move", Phase::Move, self.motion),
        ] {
            let longest = d.longest();
            if longest.is_nan() || longest > MAX_PHASE_TICKS as f64 {
                return Err((
                    name,
                    format!(
                        "durations of up to {longest:e} ticks: at most 2^40 = {MAX_PHASE_TICKS} ticks a phase (an exponential draw reaches 36.8 times its mean), so that no clock overflows"
                    ),
                ));
            }
            cycle += longest.max(given(phase));
        }
        if self.start == AsyncStart::Together
            && let Some(robot) = self.durations.as_ref().and_then(|d| d.first_start())
        {
            return Err((
                "durations",
                format!(
                    "robot {robot}'s cycle 0 is given an idle phase, but with start = \"together\" every robot Looks at tick 0 (cycle 0 has an idle phase only with start = \"random\")"
                ),
            ));
        }
        let worst = (max_epochs as f64 + 2.0) * 2.0 * cycle;
        if worst > Self::MAX_TICKS as f64 {
            return Err((
                "max_epochs",
                format!(
                    "{max_epochs} epochs of cycles up to {cycle} ticks could last {worst:e} ticks: at most 2^62; lower the cap or the durations"
                ),
            ));
        }
        Ok(())
    }
}

impl Default for AsyncSpec {
    /// One tick per phase, starting together: the same runs as FSYNC.
    fn default() -> Self {
        AsyncSpec {
            idle: TickDist::ONE,
            compute: TickDist::ONE,
            motion: TickDist::ONE,
            start: AsyncStart::Together,
            durations: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_are_whole_positive_ticks_with_the_right_means() {
        let mut s = Stream::new(4, 4, 4, 4);
        let n = 20_000;
        let u: Vec<u64> = (0..n)
            .map(|_| TickDist::Uniform { min: 2, max: 6 }.sample(&mut s))
            .collect();
        assert!(u.iter().all(|&t| (2..=6).contains(&t)));
        assert!(((u.iter().sum::<u64>() as f64 / n as f64) - 4.0).abs() < 0.05);
        let e: Vec<u64> = (0..n)
            .map(|_| TickDist::Exponential { mean: 5.0 }.sample(&mut s))
            .collect();
        assert!(e.iter().all(|&t| t >= 1));
        let mean = e.iter().sum::<u64>() as f64 / n as f64;
        assert!(
            (mean - 5.5).abs() < 0.2,
            "ceil of an exponential of mean 5 has mean about 5.5: {mean}"
        );
        assert_eq!(TickDist::Fixed { ticks: 0 }.sample(&mut s), 1);
    }
}

//! One row of `runs.csv`.

use monoculus_engine::RunOutcome;

use crate::config::{Cell, Experiment};

/// Parameter columns that every results file has, with the dotted config key each one
/// shows (a swept key listed here gets no extra column).
pub const PARAM_COLUMNS: [(&str, &str); 9] = [
    ("algorithm", "algorithm.name"),
    ("scheduler", "scheduler.kind"),
    ("init", "swarm.init"),
    ("n", "swarm.n"),
    ("dim", "swarm.dim"),
    ("side", "swarm.side"),
    ("step", "algorithm.step"),
    ("locality", "algorithm.locality"),
    ("max_rounds", "stop.max_rounds"),
];

/// Metric columns of `runs.csv`, after the parameters and the seed.
pub const METRIC_COLUMNS: [&str; 29] = [
    "rounds",
    "activations",
    "moves",
    "d_opt",
    "d_max",
    "rho",
    "tau",
    "converged",
    "stuck",
    "stopped_by",
    "goal",
    "final_diameter",
    "final_radius",
    "final_extent_x",
    "final_extent_y",
    "final_extent_z",
    "hull_area_initial",
    "hull_area_final",
    "hull_area_max",
    "hull_growth_rounds",
    "hull_grew",
    "hull_growth_max",
    "committed_hull_growth",
    "terminated",
    "distance",
    "stop_criterion",
    "ticks",
    "faulty",
    "wall_ms",
];

/// The last column of `runs.csv`: the hash of the resolved config, so that every row
/// says which experiment it belongs to.
pub const CONFIG_HASH_COLUMN: &str = "config_hash";

/// Swept keys that are not among [`PARAM_COLUMNS`]: each gets a column named by its
/// dotted key.
pub fn extra_axes(exp: &Experiment) -> Vec<String> {
    exp.axes
        .iter()
        .map(|a| a.path.clone())
        .filter(|p| !PARAM_COLUMNS.iter().any(|(_, k)| k == p) && p != "name")
        .collect()
}

/// The parameter part of the header: name, cell, the fixed parameters, extra axes.
pub fn param_header(exp: &Experiment) -> Vec<String> {
    let mut h = vec!["name".to_string(), "cell".to_string()];
    h.extend(PARAM_COLUMNS.iter().map(|(c, _)| c.to_string()));
    h.extend(extra_axes(exp));
    h
}

/// The header of `runs.csv`.
pub fn runs_header(exp: &Experiment) -> Vec<String> {
    let mut h = param_header(exp);
    h.push("seed".into());
    h.extend(METRIC_COLUMNS.iter().map(|c| c.to_string()));
    h.push(CONFIG_HASH_COLUMN.into());
    h
}

/// A float as written to CSV: shortest round-trip form.
pub fn num(x: f64) -> String {
    format!("{x}")
}

/// The parameter values of a cell, matching [`param_header`].
pub fn param_values(exp: &Experiment, cell: &Cell) -> Vec<String> {
    let s = &cell.spec;
    let mut v = vec![
        s.name.clone(),
        cell.key.clone(),
        cell.algorithm().name().to_string(),
        cell.sim_config(0).scheduler.name().to_string(),
        serde_name(&s.swarm.init),
        cell.n().to_string(),
        s.swarm.dim.to_string(),
        num(s.swarm.side),
        num(s.algorithm.step),
        num(s.algorithm.locality),
        s.stop.max_rounds.to_string(),
    ];
    for path in extra_axes(exp) {
        let value = cell
            .values
            .iter()
            .find(|(k, _)| *k == path)
            .map(|(_, v)| v.clone())
            .unwrap_or_default();
        v.push(value);
    }
    v
}

fn serde_name<T: serde::Serialize>(value: &T) -> String {
    match toml::Value::try_from(value) {
        Ok(toml::Value::String(s)) => s,
        Ok(other) => other.to_string(),
        Err(_) => String::new(),
    }
}

/// The outcome part of a row of `runs.csv`, from `seed` to `config_hash`: the schema of
/// those columns, used by the writer and by every reader (summaries, tables, figures),
/// so that a renamed column is a compile error. Numbers are written in their shortest
/// round-trip form (`0.1`, `100`, `inf`); `wall_ms` to the microsecond.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunMetrics {
    /// The seed.
    pub seed: u64,
    /// Rounds (ASYNC: epochs) when the run stopped (the criterion first held, or the cap).
    pub rounds: u64,
    /// Activations.
    pub activations: u64,
    /// Activations that moved.
    pub moves: u64,
    /// Sum of max(0, d_i - c/2).
    #[serde(with = "plain")]
    pub d_opt: f64,
    /// Largest distance to the initial centroid.
    #[serde(with = "plain")]
    pub d_max: f64,
    /// moves * b / d_opt.
    #[serde(with = "plain")]
    pub rho: f64,
    /// rounds / d_max.
    #[serde(with = "plain")]
    pub tau: f64,
    /// Whether the run converged: its stop criterion ended it and its goal holds at the
    /// end.
    pub converged: bool,
    /// Whether it fell quiescent without its goal. Absent (false) in folders written
    /// before 0.3.
    #[serde(default)]
    pub stuck: bool,
    /// What ended the run: `quiescent`, `diameter`, `box`, `max_rounds`,
    /// `schedule_end` (empty in folders written before 0.3).
    #[serde(default)]
    pub stopped_by: String,
    /// The goal the run was judged by: `diameter`, `disc` or `box` (empty before 0.3).
    #[serde(default)]
    pub goal: String,
    /// Diameter at the end.
    #[serde(with = "plain")]
    pub final_diameter: f64,
    /// Radius of the smallest disc (ball) holding the robots at the end (NaN before 0.3).
    #[serde(with = "plain", default = "nan")]
    pub final_radius: f64,
    /// Extent on x at the end.
    #[serde(with = "plain_opt")]
    pub final_extent_x: Option<f64>,
    /// Extent on y at the end.
    #[serde(with = "plain_opt")]
    pub final_extent_y: Option<f64>,
    /// Extent on z at the end (empty in the plane).
    #[serde(with = "plain_opt")]
    pub final_extent_z: Option<f64>,
    /// Hull area (volume) at the start.
    #[serde(with = "plain")]
    pub hull_area_initial: f64,
    /// Hull area (volume) at the end.
    #[serde(with = "plain")]
    pub hull_area_final: f64,
    /// Largest hull area (volume) during the run.
    #[serde(with = "plain")]
    pub hull_area_max: f64,
    /// Rounds (ASYNC: ticks) in which the hull grew.
    pub hull_growth_rounds: u64,
    /// Whether the hull ever grew.
    pub hull_grew: bool,
    /// Largest relative growth of the hull in one round.
    #[serde(with = "plain")]
    pub hull_growth_max: f64,
    /// Rounds in which the hull of positions and decided destinations grew.
    pub committed_hull_growth: u64,
    /// Robots with every termination bit set (the termination algorithm only).
    pub terminated: Option<u64>,
    /// Total distance travelled.
    #[serde(with = "plain")]
    pub distance: f64,
    /// The stop criterion in force.
    pub stop_criterion: String,
    /// ASYNC: the tick at which the run stopped.
    pub ticks: Option<u64>,
    /// Faulty robots (SPEC 9.1); the metrics are the correct robots'.
    pub faulty: u64,
    /// Wall time of the run, ms.
    #[serde(with = "millis")]
    pub wall_ms: f64,
    /// [`crate::results::config_hash`] of the experiment's `config.toml`.
    pub config_hash: String,
}

fn nan() -> f64 {
    f64::NAN
}

/// Floats as `{}` prints them (the shortest form that reads back to the same bits).
pub(crate) mod plain {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        super::super::text::with_plain(*x, |text| s.serialize_str(text))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        let text = <std::borrow::Cow<'de, str>>::deserialize(d)?;
        text.parse()
            .map_err(|_| serde::de::Error::custom(format!("`{text}` is not a number")))
    }
}

/// Optional floats: empty when absent.
mod plain_opt {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
        match x {
            Some(x) => super::super::text::with_plain(*x, |text| s.serialize_str(text)),
            None => s.serialize_str(""),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
        let text = <std::borrow::Cow<'de, str>>::deserialize(d)?;
        if text.is_empty() {
            return Ok(None);
        }
        text.parse()
            .map(Some)
            .map_err(|_| serde::de::Error::custom(format!("`{text}` is not a number")))
    }
}

/// Milliseconds to the microsecond.
mod millis {
    use serde::{Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&format!("{x:.3}"))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        super::plain::deserialize(d)
    }
}

impl RunMetrics {
    /// The metrics of one finished run of `cell`.
    pub fn of(exp: &Experiment, cell: &Cell, seed: u64, o: &RunOutcome, wall_ms: f64) -> Self {
        RunMetrics {
            seed,
            rounds: o.rounds,
            activations: o.activations,
            moves: o.moves,
            d_opt: o.d_opt,
            d_max: o.d_max,
            rho: o.rho(cell.spec.algorithm.step),
            tau: o.tau(),
            converged: o.converged,
            stuck: o.stuck(),
            stopped_by: o.stopped_by.name().to_string(),
            goal: o.goal.name().to_string(),
            final_diameter: o.final_diameter,
            final_radius: o.final_radius,
            final_extent_x: o.final_extents.first().copied(),
            final_extent_y: o.final_extents.get(1).copied(),
            final_extent_z: o.final_extents.get(2).copied(),
            hull_area_initial: o.hull_initial,
            hull_area_final: o.hull_final,
            hull_area_max: o.hull_max,
            hull_growth_rounds: o.hull_growth_rounds,
            hull_grew: o.hull_growth_rounds > 0,
            hull_growth_max: o.hull_growth_max,
            committed_hull_growth: o.committed_hull_growth,
            terminated: o.terminated,
            distance: o.distance,
            stop_criterion: cell.criterion().name().to_string(),
            ticks: o.ticks,
            faulty: o.faulty,
            wall_ms,
            config_hash: exp.hash.clone(),
        }
    }

    /// The fields as written, in column order.
    pub fn fields(&self) -> Vec<String> {
        fields_of(self)
    }

    /// The schema of the metric columns of rows whose columns are `header`.
    pub fn schema(header: &[String]) -> Result<RowSchema, String> {
        RowSchema::new(header, "seed")
    }
}

pub(crate) use super::fields::fields_of;

/// The columns of a typed part of a row (from a first column on), found once per file
/// and then used for every row.
pub struct RowSchema {
    from: usize,
    header: Vec<String>,
    /// The header with the columns before `from` renamed to names no field has (a
    /// control character and the column's number), so that a whole record is read as
    /// its typed part with no copy.
    whole: csv::StringRecord,
}

impl RowSchema {
    /// The part of rows with columns `header` that starts at column `first`.
    pub fn new(header: &[String], first: &str) -> Result<RowSchema, String> {
        let from = header
            .iter()
            .position(|h| h == first)
            .ok_or_else(|| format!("no column {first}"))?;
        let whole = (header.iter().enumerate())
            .map(|(k, h)| {
                if k < from {
                    format!("\u{1}{k}")
                } else {
                    h.clone()
                }
            })
            .collect();
        Ok(RowSchema {
            from,
            header: header.to_vec(),
            whole,
        })
    }

    /// Reads that part of `row` as a `T`; an error names the column.
    pub fn read<T: serde::de::DeserializeOwned, S: AsRef<str>>(
        &self,
        row: &[S],
    ) -> Result<T, String> {
        self.read_record(&row.iter().map(AsRef::as_ref).collect())
    }

    /// [`RowSchema::read`] of a record as read from a file, with no copy of it.
    pub fn read_record<T: serde::de::DeserializeOwned>(
        &self,
        row: &csv::StringRecord,
    ) -> Result<T, String> {
        if row.len() != self.header.len() {
            return Err(format!(
                "{} fields for {} columns",
                row.len(),
                self.header.len()
            ));
        }
        row.deserialize(Some(&self.whole))
            .map_err(|e| self.message(e, row))
    }

    /// The message of a failed read of `row`, naming the column.
    fn message(&self, e: csv::Error, row: &csv::StringRecord) -> String {
        let csv::ErrorKind::Deserialize { err, .. } = e.kind() else {
            return e.to_string();
        };
        let message = err.kind().to_string();
        // The column: as serde reports it, or the one of the typed part holding the
        // quoted value.
        let quoted = message.split('`').nth(1);
        let from = self.from;
        let column = err.field().map(|k| k as usize).or_else(|| {
            quoted.and_then(|v| row.iter().skip(from).position(|c| c == v).map(|k| from + k))
        });
        match column.and_then(|c| self.header.get(c)) {
            Some(name) => format!("column {name}: {message}"),
            None => message,
        }
    }
}

/// The full row of one finished run, its fields in column order (`runs_header`):
/// `params` (its cell's [`param_values`], the same for every run of the cell), then its
/// metrics.
///
/// ```no_run
/// # fn row(exp: &monoculus_experiments::Experiment, outcome: &monoculus_engine::RunOutcome) {
/// use monoculus_experiments::results::{param_values, run_row, runs_header};
/// let cell = &exp.cells[0];
/// let row = run_row(&param_values(exp, cell), exp, cell, 7, outcome, 1.5);
/// assert_eq!(row.len(), runs_header(exp).len());
/// # }
/// ```
pub fn run_row(
    params: &[String],
    exp: &Experiment,
    cell: &Cell,
    seed: u64,
    o: &RunOutcome,
    wall_ms: f64,
) -> csv::StringRecord {
    let mut row = csv::StringRecord::with_capacity(512, 48);
    for value in params {
        row.push_field(value);
    }
    super::fields::push_fields(&RunMetrics::of(exp, cell, seed, o, wall_ms), &mut row);
    row
}

#[cfg(test)]
mod tests {
    /// The fields as the CSV writer writes the record, split again by a CSV reader:
    /// what `fields_of` must give without the CSV text between.
    fn fields_by_a_fresh_reader<T: serde::Serialize>(value: &T) -> Vec<String> {
        let mut w = csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(vec![]);
        w.serialize(value).unwrap();
        let bytes = w.into_inner().unwrap();
        let mut r = csv::ReaderBuilder::new()
            .has_headers(false)
            .from_reader(bytes.as_slice());
        r.records()
            .next()
            .unwrap()
            .unwrap()
            .iter()
            .map(String::from)
            .collect()
    }

    #[test]
    fn fields_are_split_as_a_fresh_reader_splits_them() {
        #[derive(serde::Serialize)]
        struct Row<'a> {
            name: &'a str,
            x: f64,
            n: u64,
            flag: Option<bool>,
            empty: &'a str,
            #[serde(with = "super::plain")]
            plain: f64,
            count: Option<u64>,
            small: f32,
            negative: i64,
        }
        for name in ["plain", "a,b", "quote \"q\"", "line\nbreak", "", "é,\"\r\n"] {
            for x in [0.0, -1.5, 1e300, f64::NAN, 1.0 / 3.0] {
                let row = Row {
                    name,
                    x,
                    n: 42,
                    flag: (x > 0.0).then_some(x > 1.0),
                    empty: "",
                    plain: x,
                    count: (x < 0.0).then_some(7),
                    small: x as f32,
                    negative: -3,
                };
                assert_eq!(fields_of(&row), fields_by_a_fresh_reader(&row));
                // A record of another length.
                assert_eq!(fields_of(&(1, "a")), ["1", "a"]);
            }
        }
    }

    use super::*;

    #[test]
    fn the_schema_is_the_header() {
        let mut w = csv::Writer::from_writer(vec![]);
        let m = RunMetrics {
            seed: 3,
            rounds: 12,
            activations: 100,
            moves: 40,
            d_opt: 0.1,
            d_max: 1e-7,
            rho: f64::INFINITY,
            tau: 100.0,
            converged: true,
            stuck: false,
            stopped_by: "box".into(),
            goal: "box".into(),
            final_diameter: 1.5,
            final_radius: 0.75,
            final_extent_x: Some(1.0),
            final_extent_y: Some(0.25),
            final_extent_z: None,
            hull_area_initial: 2.0,
            hull_area_final: 1.0,
            hull_area_max: 2.0,
            hull_growth_rounds: 0,
            hull_grew: false,
            hull_growth_max: 0.0,
            committed_hull_growth: 0,
            terminated: None,
            distance: 40.0,
            stop_criterion: "box".into(),
            ticks: Some(9),
            faulty: 0,
            wall_ms: 1.23456,
            config_hash: "00ff".into(),
        };
        w.serialize(&m).unwrap();
        let text = String::from_utf8(w.into_inner().unwrap()).unwrap();
        let mut lines = text.lines();
        let mut want = vec!["seed".to_string()];
        want.extend(METRIC_COLUMNS.iter().map(|c| c.to_string()));
        want.push(CONFIG_HASH_COLUMN.into());
        assert_eq!(lines.next().unwrap(), want.join(","));
        assert_eq!(
            lines.next().unwrap(),
            "3,12,100,40,0.1,0.0000001,inf,100,true,false,box,box,1.5,0.75,1,0.25,,2,1,2,0,false,0,0,,40,box,9,0,1.235,00ff"
        );
        assert_eq!(m.fields(), fields_by_a_fresh_reader(&m));
        let header: Vec<String> = want.clone();
        let schema = RunMetrics::schema(&header).unwrap();
        let back: RunMetrics = schema.read(&m.fields()).unwrap();
        assert_eq!(back.seed, 3);
        assert_eq!(back.rho, f64::INFINITY);
        assert_eq!(back.final_extent_z, None);
        // A whole record as read from a file, parameter columns first.
        let mut whole_header = vec!["name".to_string(), "rho".to_string()];
        whole_header.extend(header.iter().cloned());
        let whole = RunMetrics::schema(&whole_header).unwrap();
        let mut fields = vec!["x".to_string(), "not a number".to_string()];
        fields.extend(m.fields());
        let record = csv::StringRecord::from(fields.clone());
        let written = RunMetrics {
            wall_ms: 1.235,
            ..m.clone()
        };
        assert_eq!(whole.read_record::<RunMetrics>(&record).unwrap(), written);
        for (column, value) in [(8, "1.2.3"), (10, "maybe"), (2, "-1")] {
            let mut bad = fields.clone();
            bad[column] = value.into();
            let message = whole
                .read_record::<RunMetrics>(&csv::StringRecord::from(bad))
                .unwrap_err();
            let name = &whole_header[column];
            assert!(
                message.starts_with(&format!("column {name}: ")),
                "{message}"
            );
        }
        let short = csv::StringRecord::from(fields[..5].to_vec());
        assert_eq!(
            whole.read_record::<RunMetrics>(&short).unwrap_err(),
            "5 fields for 33 columns"
        );
        let mut bad = m.fields();
        bad[6] = "1.2.3".into();
        assert_eq!(
            schema.read::<RunMetrics, _>(&bad).unwrap_err(),
            "column rho: `1.2.3` is not a number"
        );
    }
}

//! Shards: a split of an experiment's runs into N parts of about equal cost, and the shard
//! a batch-array task is, read from its environment.

use std::fmt;

use crate::config::{Experiment, RunId};

/// Shard `index` of `count` (0 <= index < count).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Shard {
    /// 0-based index.
    pub index: usize,
    /// How many shards the runs are split into.
    pub count: usize,
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// The most shards an experiment may be split into.
pub const MAX_SHARDS: usize = 1 << 20;

impl Shard {
    /// A shard, checked.
    pub fn new(index: usize, count: usize) -> Result<Shard, String> {
        if count == 0 || count > MAX_SHARDS || index >= count {
            return Err(format!(
                "shard {index}/{count}: expected I/N with 0 <= I < N <= {MAX_SHARDS}"
            ));
        }
        Ok(Shard { index, count })
    }

    /// Parses `I/N`.
    pub fn parse(s: &str) -> Result<Shard, String> {
        let bad = || format!("--shard {s}: expected I/N with 0 <= I < N, or auto");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let i: usize = i.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        Shard::new(i, n).map_err(|_| bad())
    }

    /// The file stem of this shard's files in `shards/`: `I-of-N`, I zero-padded to the
    /// width of N - 1 so that the files sort by index.
    pub fn stem(&self) -> String {
        let width = (self.count - 1).to_string().len();
        format!("{:0width$}-of-{}", self.index, self.count)
    }

    /// Reads a stem back (`03-of-16` -> 3/16).
    pub fn from_stem(stem: &str) -> Option<Shard> {
        let (i, n) = stem.split_once("-of-")?;
        let shard = Shard::new(i.parse().ok()?, n.parse().ok()?).ok()?;
        (shard.stem() == stem).then_some(shard)
    }

    /// The shard a job-array task is, from its environment (`get` reads a variable):
    /// Slurm, SGE, LSF; an error naming the variables otherwise.
    pub fn from_env(get: &dyn Fn(&str) -> Option<String>) -> Result<Shard, String> {
        let num = |name: &str| -> Result<Option<usize>, String> {
            match get(name) {
                None => Ok(None),
                Some(v) => v
                    .trim()
                    .parse()
                    .map(Some)
                    .map_err(|_| format!("--shard auto: {name}={v} is not a whole number")),
            }
        };
        let need = |name: &str| -> Result<usize, String> {
            num(name)?.ok_or_else(|| format!("--shard auto: {name} is not set"))
        };
        // Slurm: --array=MIN-MAX:STEP. A list of indices that is not one range with one
        // step cannot be numbered from the environment alone.
        if let Some(id) = num("SLURM_ARRAY_TASK_ID")? {
            let min = need("SLURM_ARRAY_TASK_MIN")?;
            let count = need("SLURM_ARRAY_TASK_COUNT")?;
            let step = num("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1).max(1);
            let max = num("SLURM_ARRAY_TASK_MAX")?;
            let regular = id >= min
                && (id - min) % step == 0
                && count > 0
                && max.is_none_or(|m| m == min + (count - 1) * step);
            if !regular {
                return Err(format!(
                    "--shard auto: the Slurm array (task {id}, min {min}, step {step}, {count} tasks) is not one range MIN-MAX:STEP; submit --array=0-{} or pass --shard $SLURM_ARRAY_TASK_ID/N",
                    count.saturating_sub(1)
                ));
            }
            return Shard::new((id - min) / step, count).map_err(|e| format!("--shard auto: {e}"));
        }
        // SGE: qsub -t FIRST-LAST:STEP.
        if let Some(id) = num("SGE_TASK_ID")? {
            let first = need("SGE_TASK_FIRST")?;
            let last = need("SGE_TASK_LAST")?;
            let step = num("SGE_TASK_STEPSIZE")?.unwrap_or(1).max(1);
            if id < first || last < first || (id - first) % step != 0 {
                return Err(format!(
                    "--shard auto: SGE task {id} is not in {first}-{last}:{step}"
                ));
            }
            return Shard::new((id - first) / step, (last - first) / step + 1)
                .map_err(|e| format!("--shard auto: {e}"));
        }
        // LSF: bsub -J "name[1-N:STEP]" (LSF numbers tasks from 1; the start is not in the
        // environment, so the array must start at 1).
        if let Some(id) = num("LSB_JOBINDEX")?.filter(|&i| i > 0) {
            let end = need("LSB_JOBINDEX_END")?;
            let step = num("LSB_JOBINDEX_STEP")?.unwrap_or(1).max(1);
            if (id - 1) % step != 0 || end < id {
                return Err(format!(
                    "--shard auto: LSF task {id} is not in 1-{end}:{step} (arrays must start at 1)"
                ));
            }
            return Shard::new((id - 1) / step, (end - 1) / step + 1)
                .map_err(|e| format!("--shard auto: {e}"));
        }
        if get("PBS_ARRAY_INDEX").is_some() || get("PBS_ARRAYID").is_some() {
            return Err(
                "--shard auto: PBS does not tell a task how many tasks its array has; pass --shard $PBS_ARRAY_INDEX/N"
                    .into(),
            );
        }
        Err("--shard auto: not in a job array (none of SLURM_ARRAY_TASK_ID, SGE_TASK_ID, LSB_JOBINDEX is set); pass --shard I/N".into())
    }
}

/// The batch job this process runs in, for provenance: Slurm `ARRAYJOB_TASK` (or the job
/// id), SGE `JOB.TASK`, LSF `JOB[INDEX]`, PBS's job id.
pub fn job_id(get: &dyn Fn(&str) -> Option<String>) -> Option<String> {
    if let (Some(j), Some(t)) = (get("SLURM_ARRAY_JOB_ID"), get("SLURM_ARRAY_TASK_ID")) {
        return Some(format!("{j}_{t}"));
    }
    if let Some(j) = get("SLURM_JOB_ID") {
        return Some(j);
    }
    if let Some(j) = get("JOB_ID") {
        return Some(match get("SGE_TASK_ID").filter(|t| t != "undefined") {
            Some(t) => format!("{j}.{t}"),
            None => j,
        });
    }
    if let Some(j) = get("LSB_JOBID") {
        return Some(match get("LSB_JOBINDEX").filter(|t| t != "0") {
            Some(t) => format!("{j}[{t}]"),
            None => j,
        });
    }
    get("PBS_JOBID")
}

/// The CPUs Slurm gave this task (`SLURM_CPUS_PER_TASK`), if set.
pub fn cpus_from_env(get: &dyn Fn(&str) -> Option<String>) -> Result<Option<usize>, String> {
    match get("SLURM_CPUS_PER_TASK") {
        None => Ok(None),
        Some(v) => match v.trim().parse::<usize>() {
            Ok(n) if n > 0 => Ok(Some(n)),
            _ => Err(format!(
                "SLURM_CPUS_PER_TASK={v}: expected a whole number of CPUs, at least 1"
            )),
        },
    }
}

/// The estimated cost of one run of `cell`: n^1.5 per round (every robot walks lines of
/// about sqrt n bins of the grid) times side / step rounds (the swarm's width in steps).
fn run_cost(exp: &Experiment, cell: usize) -> f64 {
    let c = &exp.cells[cell];
    let n = c.n() as f64;
    let steps = (c.spec.swarm.side / c.spec.algorithm.step).max(1.0);
    n.powf(1.5) * if steps.is_finite() { steps } else { 1.0 }
}

/// The shard of each of a list of jobs with these estimated costs: costliest first (ties
/// in list order), each to the shard with the least cost so far (ties: lowest index).
/// Jobs of equal cost go round-robin; the costliest are spread over all shards first.
pub fn balance(costs: &[f64], count: usize) -> Vec<usize> {
    let mut order: Vec<usize> = (0..costs.len()).collect();
    order.sort_by(|&a, &b| costs[b].total_cmp(&costs[a]).then(a.cmp(&b)));
    let mut load = vec![0.0f64; count];
    let mut shard_of = vec![0; costs.len()];
    for k in order {
        let s = (0..count)
            .min_by(|&a, &b| load[a].total_cmp(&load[b]).then(a.cmp(&b)))
            .expect("at least one shard");
        load[s] += costs[k];
        shard_of[k] = s;
    }
    shard_of
}

/// The shard of every run of `exp.runs()`, balanced by [`balance`] over the estimated
/// cost of each run.
pub fn assign(exp: &Experiment, count: usize) -> Vec<usize> {
    let cost: Vec<f64> = exp.cells.iter().map(|c| run_cost(exp, c.index)).collect();
    let costs: Vec<f64> = exp.runs().iter().map(|r| cost[r.cell]).collect();
    balance(&costs, count)
}

/// The runs of `shard` (all runs without one), in run order.
pub fn shard_runs(exp: &Experiment, shard: Option<Shard>) -> Vec<RunId> {
    let runs = exp.runs();
    match shard {
        None => runs,
        Some(s) => {
            let of = assign(exp, s.count);
            runs.into_iter()
                .zip(of)
                .filter(|&(_, k)| k == s.index)
                .map(|(r, _)| r)
                .collect()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn env(vars: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> + use<> {
        let m: HashMap<String, String> = vars
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        move |k| m.get(k).cloned()
    }

    #[test]
    fn slurm_arrays_with_and_without_a_step() {
        let plain = env(&[
            ("SLURM_ARRAY_TASK_ID", "2"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "3"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]);
        assert_eq!(Shard::from_env(&plain), Ok(Shard { index: 2, count: 4 }));
        // --array=1-7:2 -> tasks 1, 3, 5, 7 are shards 0..3 of 4.
        for (id, index) in [("1", 0), ("3", 1), ("5", 2), ("7", 3)] {
            let stepped = env(&[
                ("SLURM_ARRAY_TASK_ID", id),
                ("SLURM_ARRAY_TASK_MIN", "1"),
                ("SLURM_ARRAY_TASK_MAX", "7"),
                ("SLURM_ARRAY_TASK_STEP", "2"),
                ("SLURM_ARRAY_TASK_COUNT", "4"),
            ]);
            assert_eq!(Shard::from_env(&stepped), Ok(Shard { index, count: 4 }));
        }
        // --array=1,2,7: not one range.
        let list = env(&[
            ("SLURM_ARRAY_TASK_ID", "7"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_MAX", "7"),
            ("SLURM_ARRAY_TASK_STEP", "1"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
        ]);
        assert!(
            Shard::from_env(&list)
                .unwrap_err()
                .contains("not one range")
        );
        let bad = env(&[("SLURM_ARRAY_TASK_ID", "x")]);
        assert!(
            Shard::from_env(&bad)
                .unwrap_err()
                .contains("SLURM_ARRAY_TASK_ID=x")
        );
    }

    #[test]
    fn other_batch_systems_and_none() {
        let sge = env(&[
            ("SGE_TASK_ID", "5"),
            ("SGE_TASK_FIRST", "1"),
            ("SGE_TASK_LAST", "9"),
            ("SGE_TASK_STEPSIZE", "2"),
        ]);
        assert_eq!(Shard::from_env(&sge), Ok(Shard { index: 2, count: 5 }));
        let lsf = env(&[("LSB_JOBINDEX", "4"), ("LSB_JOBINDEX_END", "8")]);
        assert_eq!(Shard::from_env(&lsf), Ok(Shard { index: 3, count: 8 }));
        let pbs = env(&[("PBS_ARRAY_INDEX", "4")]);
        assert!(Shard::from_env(&pbs).unwrap_err().contains("PBS"));
        assert!(
            Shard::from_env(&env(&[]))
                .unwrap_err()
                .contains("not in a job array")
        );
    }

    #[test]
    fn job_ids_and_cpus() {
        let e = env(&[
            ("SLURM_ARRAY_JOB_ID", "40"),
            ("SLURM_ARRAY_TASK_ID", "3"),
            ("SLURM_JOB_ID", "43"),
            ("SLURM_CPUS_PER_TASK", "8"),
        ]);
        assert_eq!(job_id(&e).as_deref(), Some("40_3"));
        assert_eq!(cpus_from_env(&e), Ok(Some(8)));
        assert_eq!(job_id(&env(&[])), None);
        assert!(cpus_from_env(&env(&[("SLURM_CPUS_PER_TASK", "0")])).is_err());
    }

    #[test]
    fn balance_spreads_the_costliest_first() {
        assert_eq!(balance(&[1.0; 5], 2), vec![0, 1, 0, 1, 0]);
        // Cells of growing cost, one run each: k mod N would put both costly ones on
        // shard 1.
        let of = balance(&[1.0, 100.0, 2.0, 200.0], 2);
        assert_ne!(of[1], of[3]);
        let load = |s: usize| -> f64 {
            [1.0, 100.0, 2.0, 200.0]
                .iter()
                .zip(&of)
                .filter(|&(_, &k)| k == s)
                .map(|(c, _)| c)
                .sum()
        };
        assert!(load(0).max(load(1)) <= 200.0 + 2.0);
    }

    #[test]
    fn stems_sort_and_read_back() {
        let s = Shard::new(3, 16).unwrap();
        assert_eq!(s.stem(), "03-of-16");
        assert_eq!(Shard::from_stem("03-of-16"), Some(s));
        assert_eq!(Shard::from_stem("3-of-16"), None);
        assert_eq!(Shard::parse("3/16"), Ok(s));
        assert!(Shard::parse("16/16").is_err());
        assert!(Shard::parse("0/0").is_err());
    }
}

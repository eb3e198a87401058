//! `monoculus slurm`: a job-array script that runs the shards of a sweep (or of a stress
//! sweep), and a merge job that runs once every task has succeeded.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Parser;

use super::stress::StressArgs;
use super::{ConfigArgs, Failure};

#[derive(clap::Args, Debug)]
pub struct SlurmArgs {
    /// The experiment config (TOML); omitted with --stress.
    config: Option<PathBuf>,
    /// Override a config key by its dotted path (repeatable), as for `run`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Array tasks: the runs are split into this many shards of about equal cost.
    #[arg(long)]
    shards: usize,
    /// The results folder (the scripts go to DIR/slurm, the task logs to DIR/slurm/logs).
    #[arg(long)]
    out: PathBuf,
    /// Slurm partition (`#SBATCH --partition`).
    #[arg(long)]
    partition: Option<String>,
    /// Time limit of each task (`#SBATCH --time`, e.g. 02:00:00).
    #[arg(long)]
    time: Option<String>,
    /// CPUs of each task (`#SBATCH --cpus-per-task`; each task runs that many threads).
    #[arg(long, default_value_t = 1)]
    cpus_per_task: usize,
    /// Memory of each task (`#SBATCH --mem`, e.g. 4G).
    #[arg(long)]
    mem: Option<String>,
    /// Account to charge (`#SBATCH --account`).
    #[arg(long)]
    account: Option<String>,
    /// Job name (default: monoculus-<experiment name>, or monoculus-stress).
    #[arg(long)]
    job_name: Option<String>,
    /// Another `#SBATCH` line for both scripts, without the prefix, e.g.
    /// `--sbatch "--qos=long"` (repeatable).
    #[arg(long = "sbatch", value_name = "OPTION", allow_hyphen_values = true)]
    sbatch: Vec<String>,
    /// The monoculus the tasks run (default: this one).
    #[arg(long)]
    binary: Option<PathBuf>,
    /// Submit both jobs (sbatch) and print their ids.
    #[arg(long)]
    submit: bool,
    /// Each task prints a progress line per running run to its log at most every
    /// SECONDS (`monoculus run --progress`). Not with --stress.
    #[arg(long, value_name = "SECONDS", value_parser = super::run::parse_seconds)]
    progress: Option<std::time::Duration>,
    /// A stress sweep instead: the `monoculus stress` options after `--`, e.g.
    /// `--stress -- --n 100000,1000000 --threads 1,2 --rounds 5`.
    #[arg(long)]
    stress: bool,
    /// With --stress: the stress options.
    #[arg(last = true, value_name = "STRESS OPTIONS")]
    stress_args: Vec<String>,
}

#[derive(Parser, Debug)]
#[command(name = "monoculus stress")]
struct StressOnly {
    #[command(flatten)]
    args: StressArgs,
}

/// `s` quoted for a POSIX shell.
fn quote(s: &str) -> String {
    if !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c))
    {
        return s.to_string();
    }
    format!("'{}'", s.replace('\'', r"'\''"))
}

fn absolute(p: &Path) -> Result<PathBuf, Failure> {
    std::path::absolute(p).map_err(|e| Failure::Input(format!("{}: {e}", p.display())))
}

/// The job's options shared by both scripts.
struct Options<'a> {
    args: &'a SlurmArgs,
    name: String,
    logs: PathBuf,
}

impl Options<'_> {
    fn header(&self, out: &mut String, name: &str, log: &str, cpus: usize) {
        let a = self.args;
        out.push_str("#!/bin/bash\n");
        let _ = writeln!(out, "#SBATCH --job-name={}", quote(name));
        let _ = writeln!(
            out,
            "#SBATCH --output={}",
            quote(&self.logs.join(log).display().to_string())
        );
        let _ = writeln!(out, "#SBATCH --cpus-per-task={cpus}");
        for (key, value) in [
            ("partition", &a.partition),
            ("time", &a.time),
            ("mem", &a.mem),
            ("account", &a.account),
        ] {
            if let Some(v) = value {
                let _ = writeln!(out, "#SBATCH --{key}={}", quote(v));
            }
        }
        for line in &a.sbatch {
            let _ = writeln!(out, "#SBATCH {line}");
        }
    }
}

/// The two scripts: (array, merge).
fn scripts(
    args: &SlurmArgs,
    binary: &Path,
    task: &[String],
    merge: &[String],
    name: &str,
    logs: &Path,
    what: &str,
) -> (String, String) {
    let o = Options {
        args,
        name: name.to_string(),
        logs: logs.to_path_buf(),
    };
    let n = args.shards;
    let bin = quote(&binary.display().to_string());
    let mut array = String::new();
    o.header(&mut array, &o.name, "%x-%A_%a.out", args.cpus_per_task);
    let _ = writeln!(array, "#SBATCH --array=0-{}", n - 1);
    let _ = writeln!(
        array,
        "# {what}: shard $SLURM_ARRAY_TASK_ID of {n}, written by `monoculus slurm`.\n\
         # A shard resumes where it stopped; to rerun shard K alone: sbatch --array=K {}\n\
         set -euo pipefail\n\
         exec {bin} {} --shard \"${{SLURM_ARRAY_TASK_ID}}/{n}\"",
        quote(
            &logs
                .parent()
                .unwrap_or(logs)
                .join("array.sh")
                .display()
                .to_string()
        ),
        task.iter().map(|s| quote(s)).collect::<Vec<_>>().join(" ")
    );
    let mut merge_script = String::new();
    o.header(
        &mut merge_script,
        &format!("{}-merge", o.name),
        "%x-%j.out",
        1,
    );
    let _ = writeln!(
        merge_script,
        "# {what}: merges the {n} shards once every array task has succeeded.\n\
         set -euo pipefail\n\
         exec {bin} {}",
        merge.iter().map(|s| quote(s)).collect::<Vec<_>>().join(" ")
    );
    (array, merge_script)
}

fn sbatch(args: &[&str]) -> Result<String, Failure> {
    let out = Command::new("sbatch").args(args).output().map_err(|e| {
        Failure::Other(anyhow::anyhow!(
            "sbatch: {e} (is Slurm installed and on PATH?)"
        ))
    })?;
    if !out.status.success() {
        return Err(Failure::Other(anyhow::anyhow!(
            "sbatch {}: {}",
            args.join(" "),
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    // --parsable prints `ID` or `ID;CLUSTER`.
    text.trim()
        .split(';')
        .next()
        .filter(|id| !id.is_empty() && id.chars().all(|c| c.is_ascii_digit()))
        .map(str::to_string)
        .ok_or_else(|| Failure::Other(anyhow::anyhow!("sbatch printed no job id: {text}")))
}

pub fn slurm(args: SlurmArgs) -> Result<(), Failure> {
    if args.shards == 0 || args.shards > monoculus_experiments::shard::MAX_SHARDS {
        return Err(Failure::Input(format!(
            "--shards {}: expected 1 to {}",
            args.shards,
            monoculus_experiments::shard::MAX_SHARDS
        )));
    }
    if args.cpus_per_task == 0 {
        return Err(Failure::Input("--cpus-per-task: must be at least 1".into()));
    }
    if let Some(bad) = args.sbatch.iter().find(|l| l.contains('\n')) {
        return Err(Failure::Input(format!("--sbatch {bad:?}: one line only")));
    }
    let out = absolute(&args.out)?;
    let binary = match &args.binary {
        Some(b) => absolute(b)?,
        None => std::env::current_exe().map_err(|e| Failure::Other(e.into()))?,
    };
    let (task, merge, name, what) = if args.stress {
        if args.config.is_some() {
            return Err(Failure::Input(
                "--stress: takes no config; give the stress options after `--`".into(),
            ));
        }
        if args.progress.is_some() {
            return Err(Failure::Input(
                "--progress: for experiments only (stress prints each measurement)".into(),
            ));
        }
        StressOnly::try_parse_from(
            std::iter::once("monoculus stress".to_string()).chain(args.stress_args.iter().cloned()),
        )
        .map_err(|e| {
            Failure::Input(format!(
                "--stress options: {}",
                e.to_string()
                    .lines()
                    .next()
                    .unwrap_or("invalid")
                    .trim_start_matches("error: ")
            ))
        })?;
        if args.stress_args.iter().any(|a| a.starts_with("--shard")) {
            return Err(Failure::Input(
                "--stress options: leave out --shard (each task gets its own)".into(),
            ));
        }
        let mut task: Vec<String> = vec!["stress".into()];
        let mut rest = args.stress_args.iter();
        let mut csv = None;
        while let Some(a) = rest.next() {
            if a == "--csv" {
                csv = rest.next().cloned();
            } else if let Some(v) = a.strip_prefix("--csv=") {
                csv = Some(v.to_string());
            } else {
                task.push(a.clone());
            }
        }
        let csv = match csv {
            Some(c) => absolute(Path::new(&c))?,
            None => out.join("stress.csv"),
        };
        task.extend(["--csv".into(), csv.display().to_string()]);
        let merge = vec!["merge".into(), csv.display().to_string()];
        (
            task,
            merge,
            "monoculus-stress".to_string(),
            "stress sweep".to_string(),
        )
    } else {
        let Some(config) = &args.config else {
            return Err(Failure::Input(
                "slurm: needs a CONFIG (or --stress with stress options)".into(),
            ));
        };
        if !args.stress_args.is_empty() {
            return Err(Failure::Input(
                "options after `--` are for --stress only".into(),
            ));
        }
        let exp = ConfigArgs {
            config: config.clone(),
            set: args.set.clone(),
        }
        .load()?;
        let existing = out.join("config.toml");
        if let Ok(old) = std::fs::read_to_string(&existing)
            && old != exp.resolved
        {
            return Err(Failure::Input(format!(
                "{}: holds a different experiment; use another --out",
                existing.display()
            )));
        }
        let runs = exp.cells.len() * exp.seeds.len();
        if args.shards > runs {
            eprintln!(
                "warning: --shards {}: the experiment has only {runs} runs; some shards will have none",
                args.shards
            );
        }
        let mut task = vec!["run".into(), absolute(config)?.display().to_string()];
        for s in &args.set {
            task.extend(["--set".into(), s.clone()]);
        }
        task.extend(["--out".into(), out.display().to_string()]);
        if let Some(every) = args.progress {
            task.extend(["--progress".into(), every.as_secs_f64().to_string()]);
        }
        let merge = vec!["merge".into(), out.display().to_string()];
        (
            task,
            merge,
            format!("monoculus-{}", exp.name),
            format!("experiment {} ({runs} runs)", exp.name),
        )
    };
    let name = args.job_name.clone().unwrap_or(name);
    let dir = out.join("slurm");
    let logs = dir.join("logs");
    std::fs::create_dir_all(&logs)
        .map_err(|e| Failure::Other(anyhow::anyhow!("{}: {e}", logs.display())))?;
    let (array, merge_script) = scripts(&args, &binary, &task, &merge, &name, &logs, &what);
    let (array_path, merge_path) = (dir.join("array.sh"), dir.join("merge.sh"));
    for (path, text) in [(&array_path, &array), (&merge_path, &merge_script)] {
        monoculus_experiments::results::write_atomic(path, text.as_bytes())?;
    }
    outln!(
        "wrote {} ({} array tasks) and {}",
        array_path.display(),
        args.shards,
        merge_path.display()
    );
    let (a, m) = (
        array_path.display().to_string(),
        merge_path.display().to_string(),
    );
    if !args.submit {
        outln!("submit with:");
        outln!("  jid=$(sbatch --parsable {})", quote(&a));
        outln!("  sbatch --dependency=afterok:${{jid%%;*}} {}", quote(&m));
        return Ok(());
    }
    let array_job = sbatch(&["--parsable", &a])?;
    let merge_job = sbatch(&[
        "--parsable",
        &format!("--dependency=afterok:{array_job}"),
        &m,
    ])?;
    outln!("array_job={array_job}");
    outln!("merge_job={merge_job}");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::quote;

    #[test]
    fn quoting_survives_a_shell() {
        assert_eq!(quote("/a/b.toml"), "/a/b.toml");
        assert_eq!(quote("swarm.n=[10, 20]"), "'swarm.n=[10, 20]'");
        assert_eq!(quote("it's"), r"'it'\''s'");
        assert_eq!(quote(""), "''");
    }
}

//! `monoculus slurm`: a job-array script that runs the shards of a sweep (or of a stress
//! sweep), and a merge job that runs once every task has succeeded.

use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Parser;

use super::stress::StressArgs;
use monoculus_experiments::output::Paths;

use super::slurm_script::{Header, Syntax, Value, checked, script};
use super::{ConfigArgs, Failure, check_paths};

/// A fixed word of a script's command.
fn word(w: &str) -> (String, String) {
    (w.to_string(), w.to_string())
}

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

fn absolute(p: &Path) -> Result<PathBuf, Failure> {
    std::path::absolute(p).map_err(|e| Failure::Input(format!("{}: {e}", p.display())))
}

/// A path as a checked script value.
fn path_value(option: &str, p: &Path, syntax: Syntax) -> Result<Value, Failure> {
    let text = p.to_str().ok_or_else(|| {
        Failure::Input(format!(
            "{option} {}: not valid UTF-8, which a script cannot hold",
            p.display()
        ))
    })?;
    checked(option, text, syntax)
}

/// The two scripts: (array, merge). Every value in them is checked ([`checked`]).
#[expect(clippy::too_many_arguments, reason = "the parts of two scripts")]
fn scripts(
    args: &SlurmArgs,
    binary: &Path,
    task: &[(String, String)],
    merge: &[(String, String)],
    name: &str,
    logs: &Path,
    what: &str,
    name_option: &str,
) -> Result<(String, String), Failure> {
    let n = args.shards;
    let mut options = Vec::new();
    for (key, value, syntax) in [
        ("partition", &args.partition, Syntax::Partitions),
        ("time", &args.time, Syntax::Time),
        ("mem", &args.mem, Syntax::Memory),
        ("account", &args.account, Syntax::Account),
    ] {
        if let Some(v) = value {
            options.push((key, checked(&format!("--{key}"), v, syntax)?));
        }
    }
    let extra: Vec<Value> = args
        .sbatch
        .iter()
        .map(|l| checked("--sbatch", l, Syntax::Option))
        .collect::<Result<_, _>>()?;
    let words = |list: &[(String, String)]| -> Result<Vec<Value>, Failure> {
        let mut v = vec![path_value("--binary", binary, Syntax::Word)?];
        for (option, word) in list {
            v.push(checked(option, word, Syntax::Word)?);
        }
        Ok(v)
    };
    let array_name = checked(name_option, name, Syntax::JobName)?;
    let merge_name = checked(name_option, &format!("{name}-merge"), Syntax::JobName)?;
    let array_log = path_value("--out", &logs.join("%x-%A_%a.out"), Syntax::Word)?;
    let merge_log = path_value("--out", &logs.join("%x-%j.out"), Syntax::Word)?;
    path_value("--out", logs, Syntax::SlurmPath)?;
    let array_path = path_value(
        "--out",
        &logs.parent().unwrap_or(logs).join("array.sh"),
        Syntax::Word,
    )?;
    let comment = |text: String| checked("the config's name", &text, Syntax::Comment);
    let array = script(
        &Header {
            job_name: &array_name,
            output: &array_log,
            cpus: args.cpus_per_task,
            options: &options,
            extra: &extra,
            array: Some(n),
        },
        &[
            comment(format!(
                "{what}: shard $SLURM_ARRAY_TASK_ID of {n}, written by `monoculus slurm`."
            ))?,
            comment(format!(
                "A shard resumes where it stopped; to rerun shard K alone: sbatch --array=K {}",
                array_path.quoted()
            ))?,
        ],
        &words(task)?,
        &format!(" --shard \"${{SLURM_ARRAY_TASK_ID}}/{n}\""),
    );
    let merge_script = script(
        &Header {
            job_name: &merge_name,
            output: &merge_log,
            cpus: 1,
            options: &options,
            extra: &extra,
            array: None,
        },
        &[comment(format!(
            "{what}: merges the {n} shards once every array task has succeeded."
        ))?],
        &words(merge)?,
        "",
    );
    Ok((array, merge_script))
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

pub fn slurm(args: SlurmArgs, registry: &monoculus_experiments::Registry) -> Result<(), Failure> {
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
    let out = absolute(&args.out)?;
    let binary = match &args.binary {
        Some(b) => absolute(b)?,
        None => std::env::current_exe().map_err(|e| Failure::Other(e.into()))?,
    };
    let mut inputs = Paths::default();
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
        let mut task = vec![word("stress")];
        let mut rest = args.stress_args.iter();
        let mut csv = None;
        while let Some(a) = rest.next() {
            if a == "--csv" {
                csv = rest.next().cloned();
            } else if let Some(v) = a.strip_prefix("--csv=") {
                csv = Some(v.to_string());
            } else {
                task.push(("the stress options".into(), a.clone()));
            }
        }
        let csv = match csv {
            Some(c) => absolute(Path::new(&c))?,
            None => out.join("stress.csv"),
        };
        let csv = csv.display().to_string();
        task.extend([word("--csv"), ("--csv".into(), csv.clone())]);
        let merge = vec![word("merge"), ("--csv".into(), csv)];
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
        let config_args = ConfigArgs {
            config: config.clone(),
            set: args.set.clone(),
        };
        let exp = config_args.load(registry)?;
        inputs = config_args.paths(&exp);
        let existing = out.join("config.toml");
        if let Ok(old) = std::fs::read_to_string(&existing)
            && old != exp.resolved
        {
            return Err(Failure::Input(format!(
                "{}: {}",
                existing.display(),
                exp.changed_input(&old)
                    .unwrap_or_else(|| "holds a different experiment; use another --out".into())
            )));
        }
        let runs = exp.cells.len() * exp.seeds.len();
        if args.shards > runs {
            eprintln!(
                "warning: --shards {}: the experiment has only {runs} runs; some shards will have none",
                args.shards
            );
        }
        let mut task = vec![
            word("run"),
            ("CONFIG".into(), absolute(config)?.display().to_string()),
        ];
        for s in &args.set {
            task.extend([word("--set"), ("--set".into(), s.clone())]);
        }
        task.extend([word("--out"), ("--out".into(), out.display().to_string())]);
        if let Some(every) = args.progress {
            task.extend([word("--progress"), word(&every.as_secs_f64().to_string())]);
        }
        let merge = vec![word("merge"), ("--out".into(), out.display().to_string())];
        (
            task,
            merge,
            // The default job name keeps the characters a job name may have.
            format!("monoculus-{}", exp.name)
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || "_-.+=:,@".contains(c) {
                        c
                    } else {
                        '_'
                    }
                })
                .collect(),
            format!("experiment {} ({runs} runs)", exp.name),
        )
    };
    let (name, name_option) = match &args.job_name {
        Some(n) => (n.clone(), "--job-name"),
        None => (name, "the default job name"),
    };
    let dir = out.join("slurm");
    let logs = dir.join("logs");
    // Every value checked before anything is made.
    let (array, merge_script) = scripts(
        &args,
        &binary,
        &task,
        &merge,
        &name,
        &logs,
        &what,
        name_option,
    )?;
    std::fs::create_dir_all(&logs)
        .map_err(|e| Failure::Other(anyhow::anyhow!("{}: {e}", logs.display())))?;
    let (array_path, merge_path) = (dir.join("array.sh"), dir.join("merge.sh"));
    let mut paths = inputs;
    paths
        .output("the array script", &array_path)
        .output("the merge script", &merge_path);
    check_paths(&paths)?;
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
        let q = |p: &str| checked("--out", p, Syntax::Word).map(|v| v.quoted());
        outln!("submit with:");
        outln!("  jid=$(sbatch --parsable {})", q(&a)?);
        outln!("  sbatch --dependency=afterok:${{jid%%;*}} {}", q(&m)?);
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

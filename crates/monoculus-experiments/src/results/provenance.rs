//! Where results come from: the monoculus build, the config's hash, and each process that
//! wrote into the folder (host, pid, batch job).

use std::path::Path;
use std::time::{SystemTime, UNIX_EPOCH};

use serde::{Deserialize, Serialize};

use super::ResultsError;
use super::fsio::{io, write_atomic};
use crate::config::Experiment;

/// The monoculus version that writes results.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
/// The git commit this monoculus was built from (`unknown` outside a git checkout).
pub const GIT_COMMIT: &str = env!("MONOCULUS_GIT_COMMIT");

/// A 64-bit FNV-1a hash of `text`, as 16 hex digits: what identifies an experiment's
/// resolved config in every row it wrote.
pub fn config_hash(text: &str) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

fn is_zero(x: &u64) -> bool {
    *x == 0
}

/// "monoculus 0.1.0 (commit abc)" of this build.
pub fn this_build() -> String {
    format!("monoculus {VERSION} (commit {GIT_COMMIT})")
}

/// This machine's host name.
pub fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "unknown".into())
}

/// One process that wrote into a results folder or shard.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Attempt {
    /// `I/N` for a shard, absent for a whole run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<String>,
    /// Host name.
    pub host: String,
    /// Process id.
    pub pid: u32,
    /// The batch job (`SLURM_ARRAY_JOB_ID_SLURM_ARRAY_TASK_ID`, ...), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub job: Option<String>,
    /// Seconds since 1970 when it started.
    pub started_unix: u64,
}

impl Attempt {
    /// This process, now.
    pub fn this_process(shard: Option<String>, job: Option<String>) -> Attempt {
        Attempt {
            shard,
            host: host_name(),
            pid: std::process::id(),
            job,
            started_unix: SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
        }
    }

    /// "pid 12 on host h (job 7_3)": who holds a lock.
    pub fn describe(&self) -> String {
        let mut s = format!("pid {} on host {}", self.pid, self.host);
        if let Some(j) = &self.job {
            s.push_str(&format!(" (job {j})"));
        }
        s
    }
}

/// `provenance.toml` of a results folder, or `shards/I-of-N.toml` of a shard.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Provenance {
    /// The monoculus version that wrote the rows.
    pub monoculus_version: String,
    /// The git commit it was built from.
    pub git_commit: String,
    /// [`config_hash`] of `config.toml`.
    pub config_hash: String,
    /// The folder relative file paths of the config (`swarm.file`) are read from.
    pub config_base: String,
    /// The config file's text as given, before `--set` (what `merge` rebuilds the
    /// experiment from: `config.toml` orders swept keys by the schema, not as written,
    /// and cells are named in the order written).
    #[serde(default)]
    pub config_source: String,
    /// The `--set` overrides, in order.
    #[serde(default)]
    pub config_overrides: Vec<String>,
    /// Runs of the experiment not in the results: a merge with `--partial` that lacked
    /// some (0, not written, for complete results).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub missing_runs: u64,
    /// Every process that wrote, oldest first.
    #[serde(default, rename = "attempt")]
    pub attempts: Vec<Attempt>,
}

impl Provenance {
    /// A record for this build and experiment.
    pub fn new(exp: &Experiment) -> Provenance {
        Provenance {
            monoculus_version: VERSION.into(),
            git_commit: GIT_COMMIT.into(),
            config_hash: exp.hash.clone(),
            config_base: exp.base.display().to_string(),
            config_source: exp.source.clone(),
            config_overrides: exp.overrides.clone(),
            missing_runs: 0,
            attempts: Vec::new(),
        }
    }

    /// Rebuilds the experiment the record was written for (its algorithms resolved
    /// through `registry`).
    pub fn experiment(
        &self,
        label: &str,
        registry: &crate::Registry,
    ) -> Result<Experiment, crate::ConfigError> {
        Experiment::parse(
            &self.config_source,
            label,
            Path::new(&self.config_base),
            &self.config_overrides,
            registry,
        )
    }

    /// Reads a record, `Ok(None)` if there is none.
    pub fn read(path: &Path) -> Result<Option<Provenance>, ResultsError> {
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(io(path)(e)),
        };
        toml::from_str(&text)
            .map(Some)
            .map_err(|e| ResultsError::Corrupt {
                path: path.display().to_string(),
                line: e
                    .span()
                    .map_or(0, |s| text[..s.start].matches('\n').count() + 1),
                message: e.message().trim().to_string(),
            })
    }

    /// Writes the record atomically.
    pub fn write(&self, path: &Path) -> Result<(), ResultsError> {
        let text = toml::to_string(self).expect("a provenance record serialises");
        write_atomic(path, text.as_bytes())
    }

    /// Whether the rows `self` describes were written by this build (and so may be
    /// continued or merged by it).
    pub fn is_this_build(&self) -> bool {
        self.monoculus_version == VERSION && self.git_commit == GIT_COMMIT
    }

    /// "monoculus 0.1.0 (commit abc)".
    pub fn build(&self) -> String {
        format!(
            "monoculus {} (commit {})",
            self.monoculus_version, self.git_commit
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hash_is_fnv1a() {
        // Published FNV-1a 64 test vectors.
        assert_eq!(config_hash(""), "cbf29ce484222325");
        assert_eq!(config_hash("a"), "af63dc4c8601ec8c");
        assert_eq!(config_hash("foobar"), "85944171f73967e8");
    }

    #[test]
    fn record_round_trips() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("p.toml");
        let exp = Experiment::parse(
            "name = \"p\"\nseeds = 1\n[swarm]\nn = 3\ninit = \"square\"\nside = 1.0\n[algorithm]\nname = \"median\"\n",
            "p.toml",
            Path::new("/c"),
            &["seeds=2".into()],
            &crate::Registry::builtin(),
        )
        .unwrap();
        let mut r = Provenance::new(&exp);
        r.attempts.push(Attempt::this_process(
            Some("1/4".into()),
            Some("7_1".into()),
        ));
        r.attempts.push(Attempt::this_process(None, None));
        r.write(&p).unwrap();
        let back = Provenance::read(&p).unwrap().unwrap();
        assert_eq!(back, r);
        assert_eq!(
            back.experiment("p.toml", &crate::Registry::builtin())
                .unwrap()
                .resolved,
            exp.resolved
        );
        assert_eq!(Provenance::read(&tmp.path().join("none")).unwrap(), None);
    }
}

//! What `monoculus slurm` writes into a script, each value checked in one place.
//!
//! A script is made only of [`Value`]s, and a [`Value`] is made only by [`checked`]: no
//! line break, carriage return or NUL (which would end an `#SBATCH` comment and start a
//! command), and each Slurm option's own syntax. Values on the command line of the
//! script are quoted for the shell besides.

use std::fmt::Write as _;

use super::Failure;

/// What a value must look like.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Syntax {
    /// A partition list (`short,long`): names of letters, digits, `_`, `-`, `.`.
    Partitions,
    /// An account: letters, digits, `_`, `-`, `.`.
    Account,
    /// A time limit as Slurm reads it: `M`, `M:S`, `H:M:S`, `D-H`, `D-H:M`, `D-H:M:S`
    /// (whole numbers), or `UNLIMITED`/`INFINITE`.
    Time,
    /// Memory: a whole number with an optional unit `K`, `M`, `G` or `T`.
    Memory,
    /// A job name: letters, digits and `_ - . + = : , @`.
    JobName,
    /// A path Slurm opens from an `#SBATCH` line: no `%` (Slurm reads `%x`, `%j`... in
    /// its output paths), no quote or backslash (sbatch's own reading of the line does
    /// not undo a shell's quoting).
    SlurmPath,
    /// An extra `#SBATCH` option (`--qos=long`): starts with `-`, no spaces.
    Option,
    /// A word of the script's command (quoted for the shell when written).
    Word,
    /// Text of a comment line.
    Comment,
}

/// A value checked for its place in a script (see [`checked`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Value(String);

impl Value {
    /// The value quoted for a POSIX shell (bare when it holds only safe characters).
    pub fn quoted(&self) -> String {
        let s = &self.0;
        if !s.is_empty()
            && s.chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_./=:,+@%".contains(c))
        {
            return s.to_string();
        }
        format!("'{}'", s.replace('\'', r"'\''"))
    }

    /// The value as given.
    pub fn text(&self) -> &str {
        &self.0
    }
}

fn is_time(t: &str) -> bool {
    if matches!(t, "UNLIMITED" | "INFINITE") {
        return true;
    }
    let whole = |s: &str| !s.is_empty() && s.len() <= 9 && s.bytes().all(|b| b.is_ascii_digit());
    let (days, rest) = match t.split_once('-') {
        Some((d, r)) => (Some(d), r),
        None => (None, t),
    };
    let parts: Vec<&str> = rest.split(':').collect();
    days.is_none_or(whole) && parts.iter().all(|p| whole(p)) && parts.len() <= 3
}

fn is_memory(m: &str) -> bool {
    let digits = m.bytes().take_while(u8::is_ascii_digit).count();
    (1..=15).contains(&digits)
        && matches!(
            &m[digits..],
            "" | "K" | "M" | "G" | "T" | "k" | "m" | "g" | "t"
        )
}

fn plain_name(s: &str, extra: &str) -> bool {
    !s.is_empty()
        && s.len() <= 200
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c) || extra.contains(c))
}

/// `text`, given as `option`, checked to hold `syntax` and nothing that could end its
/// line; exit status 2 otherwise, with a one-line message naming the option.
pub fn checked(option: &str, text: &str, syntax: Syntax) -> Result<Value, Failure> {
    let shown = monoculus_experiments::shown(text);
    if let Some(c) = text.chars().find(|&c| matches!(c, '\n' | '\r' | '\0')) {
        return Err(Failure::Input(format!(
            "{option} {shown}: holds a {}; a value written into a script is one line",
            match c {
                '\n' => "line break",
                '\r' => "carriage return",
                _ => "NUL character",
            }
        )));
    }
    let problem = match syntax {
        Syntax::Partitions if !text.split(',').all(|p| plain_name(p, "")) => {
            Some("partition names of letters, digits, _, - and ., separated by commas")
        }
        Syntax::Account if !plain_name(text, "") => Some("letters, digits, _, - and ."),
        Syntax::Time if !is_time(text) => Some(
            "a Slurm time limit: minutes, M:S, H:M:S, D-H, D-H:M or D-H:M:S (whole numbers), or UNLIMITED",
        ),
        Syntax::Memory if !is_memory(text) => {
            Some("a whole number with an optional unit K, M, G or T (e.g. 4G)")
        }
        Syntax::JobName if !plain_name(text, "+=:,@") => {
            Some("a job name of letters, digits and _ - . + = : , @")
        }
        Syntax::SlurmPath if text.contains(['%', '\'', '"', '\\']) => Some(
            "a path without %, quotes or backslashes (Slurm reads %x, %j, ... in the paths of its logs, and its own quoting)",
        ),
        Syntax::Option if !text.starts_with('-') || text.contains(char::is_whitespace) => {
            Some("one sbatch option such as --qos=long (starting with -, without spaces)")
        }
        Syntax::Word | Syntax::Comment if text.chars().any(char::is_control) => {
            Some("printable characters only")
        }
        _ => None,
    };
    match problem {
        Some(want) => Err(Failure::Input(format!("{option} {shown}: expected {want}"))),
        None => Ok(Value(text.to_string())),
    }
}

/// One script's `#SBATCH` lines.
pub struct Header<'a> {
    /// `--job-name`.
    pub job_name: &'a Value,
    /// `--output`: the log path.
    pub output: &'a Value,
    /// `--cpus-per-task`.
    pub cpus: usize,
    /// Other `--KEY=VALUE` options (partition, time, mem, account).
    pub options: &'a [(&'static str, Value)],
    /// Extra options (`--sbatch`), each a line.
    pub extra: &'a [Value],
    /// `--array`, the number of tasks.
    pub array: Option<usize>,
}

/// A script: its `#SBATCH` lines, comment lines, then `exec` of the command `words`.
pub fn script(header: &Header<'_>, comments: &[Value], words: &[Value], tail: &str) -> String {
    let mut out = String::from("#!/bin/bash\n");
    let _ = writeln!(out, "#SBATCH --job-name={}", header.job_name.quoted());
    let _ = writeln!(out, "#SBATCH --output={}", header.output.quoted());
    let _ = writeln!(out, "#SBATCH --cpus-per-task={}", header.cpus);
    for (key, value) in header.options {
        let _ = writeln!(out, "#SBATCH --{key}={}", value.quoted());
    }
    for line in header.extra {
        let _ = writeln!(out, "#SBATCH {}", line.text());
    }
    if let Some(n) = header.array {
        let _ = writeln!(out, "#SBATCH --array=0-{}", n - 1);
    }
    for c in comments {
        let _ = writeln!(out, "# {}", c.text());
    }
    out.push_str("set -euo pipefail\n");
    let words: Vec<String> = words.iter().map(Value::quoted).collect();
    let _ = writeln!(out, "exec {}{tail}", words.join(" "));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ok(text: &str, syntax: Syntax) -> bool {
        checked("--x", text, syntax).is_ok()
    }

    #[test]
    fn each_option_has_its_syntax() {
        for t in [
            "30",
            "30:00",
            "01:00:00",
            "2-0",
            "2-12:00",
            "2-12:00:00",
            "UNLIMITED",
        ] {
            assert!(ok(t, Syntax::Time), "{t}");
        }
        for t in ["", "1:2:3:4", "1-", "a", "01:00:00 ", "1-2-3", "-1"] {
            assert!(!ok(t, Syntax::Time), "{t}");
        }
        for t in ["4G", "4096", "100m"] {
            assert!(ok(t, Syntax::Memory), "{t}");
        }
        for t in ["", "G", "4GB", "4 G", "-4G"] {
            assert!(!ok(t, Syntax::Memory), "{t}");
        }
        assert!(ok("short,long", Syntax::Partitions));
        assert!(!ok("short;touch x", Syntax::Partitions));
        assert!(!ok("short,", Syntax::Partitions));
        assert!(ok("--qos=long", Syntax::Option));
        assert!(!ok("--qos=long; touch x", Syntax::Option));
        assert!(ok("/a b/$(touch x)'", Syntax::Word));
        assert!(!ok("/a/%j", Syntax::SlurmPath));
        assert!(!ok("/a/it's", Syntax::SlurmPath));
        assert!(ok("/a/b c/$(x)", Syntax::SlurmPath));
        for s in [Syntax::Word, Syntax::JobName, Syntax::Time, Syntax::Comment] {
            for bad in ["a\nb", "a\rb", "a\0b"] {
                assert!(!ok(bad, s), "{bad:?}");
            }
        }
    }

    #[test]
    fn quoting_survives_a_shell() {
        let q = |s: &str| checked("--x", s, Syntax::Word).ok().unwrap().quoted();
        assert_eq!(q("/a/b.toml"), "/a/b.toml");
        assert_eq!(q("swarm.n=[10, 20]"), "'swarm.n=[10, 20]'");
        assert_eq!(q("it's"), r"'it'\''s'");
        assert_eq!(q(""), "''");
    }
}

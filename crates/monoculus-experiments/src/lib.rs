//! monoculus experiments: TOML configs swept over parameters and seeds, run in
//! parallel, with results as CSV (`runs.csv`, `summary.csv`) beside the resolved
//! `config.toml`.

pub mod config;
pub mod durations;
pub mod hunt;
pub mod limits;
pub mod look;
pub mod output;
pub mod positions;
pub mod registry;
pub mod replay;
pub mod results;
pub mod runner;
pub mod schedule;
pub mod shard;

pub use config::{Cell, ConfigError, Experiment, RunId};
pub use registry::Registry;

/// The most characters of a value that a message quotes.
pub const MAX_QUOTED: usize = 100;

/// `n` with its noun, singular or plural (nouns whose plural takes an `s`):
/// `1 cell`, `3 cells`.
///
/// ```
/// use monoculus_experiments::counted;
/// assert_eq!(counted(1, "run"), "1 run");
/// assert_eq!(counted(12, "cell"), "12 cells");
/// assert_eq!(counted(0, "seed"), "0 seeds");
/// ```
pub fn counted(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// A value as a message quotes it: in backticks, on one line, and at most
/// [`MAX_QUOTED`] characters of it (a longer value is cut, with its length said), so
/// that a huge value in a config or a CSV gives a short message.
///
/// ```
/// assert_eq!(monoculus_experiments::shown("abc"), "`abc`");
/// let long = "x".repeat(5000);
/// let s = monoculus_experiments::shown(&long);
/// assert!(s.len() < 140 && s.ends_with("(5000 characters)"), "{s}");
/// ```
pub fn shown(value: &str) -> String {
    let count = value.chars().count();
    if count <= MAX_QUOTED {
        return format!("`{}`", one_line(value));
    }
    let head: String = value.chars().take(MAX_QUOTED).collect();
    format!("`{}`... ({count} characters)", one_line(&head))
}

/// `message` with every quoted part (between backticks or double quotes) of more than
/// [`MAX_QUOTED`] characters cut to that length: the safety net under [`shown`] for
/// messages that quote values they were not made with (serde's, the TOML parser's).
///
/// ```
/// let m = format!("invalid type: string \"{}\", expected u64", "x".repeat(500));
/// let short = monoculus_experiments::short_quotes(&m);
/// assert!(short.len() < 160, "{short}");
/// assert!(short.ends_with("...\", expected u64"), "{short}");
/// ```
pub fn short_quotes(message: &str) -> String {
    let chars: Vec<char> = message.chars().collect();
    let mut out = String::with_capacity(message.len().min(4096));
    let mut k = 0;
    while k < chars.len() {
        let c = chars[k];
        out.push(c);
        k += 1;
        if c != '`' && c != '"' {
            continue;
        }
        let Some(len) = chars[k..].iter().position(|&d| d == c) else {
            continue;
        };
        if len > MAX_QUOTED {
            out.extend(&chars[k..k + MAX_QUOTED]);
            out.push_str("...");
        } else {
            out.extend(&chars[k..k + len]);
        }
        out.push(c);
        k += len + 1;
    }
    out
}

/// `text` with line breaks and other control characters escaped (`\n`), so that a
/// message quoting what a user wrote stays one line.
pub fn one_line(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}
pub use runner::{
    Progress, RunOptions, RunProgress, SweepError, SweepReport, run_experiment, run_one,
    run_one_stoppable, run_one_with,
};

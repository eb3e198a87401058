//! [`ConfigError`]: one line naming the file, line and key; and where a config's text
//! came from, to name them.

use super::*;

/// A bad config: where, which key, what is wrong. Displays as one line:
/// `FILE:LINE: KEY: MESSAGE`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct ConfigError {
    /// The config file (or `--set` for an override).
    pub file: String,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// Dotted key, when known.
    pub key: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", crate::one_line(&self.file))?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        if let Some(key) = &self.key {
            write!(f, ": {}", crate::one_line(key))?;
        }
        write!(
            f,
            ": {}",
            crate::short_quotes(&crate::one_line(&self.message))
        )
    }
}

pub(super) struct Source<'a> {
    pub(super) label: String,
    pub(super) text: &'a str,
    pub(super) overridden: Vec<String>,
}

impl Source<'_> {
    pub(super) fn error(&self, key: &str, message: impl Into<String>) -> ConfigError {
        let message = message.into();
        // The override's own key, a key inside it, or a table the config does not have
        // that only the override names (`--set bogus.x=5`).
        if self.overridden.iter().any(|o| {
            key == o
                || key.starts_with(&format!("{o}."))
                || (!key.is_empty()
                    && o.starts_with(&format!("{key}."))
                    && line_of(self.text, key).is_none())
        }) {
            return ConfigError {
                file: "--set".into(),
                line: None,
                key: Some(key.to_string()),
                message,
            };
        }
        ConfigError {
            file: self.label.clone(),
            line: if key.is_empty() {
                None
            } else {
                line_of(self.text, key)
            },
            key: (!key.is_empty()).then(|| key.to_string()),
            message,
        }
    }
}

impl Experiment {
    /// An error about `key` of this experiment's config (read from `file`): with the line
    /// of the key, or naming `--set` when an override set it.
    pub fn error_at(&self, file: &str, key: &str, message: impl Into<String>) -> ConfigError {
        Source {
            label: file.to_string(),
            text: &self.source,
            overridden: self
                .overrides
                .iter()
                .map(|o| {
                    o.split_once('=')
                        .map_or(o.as_str(), |(k, _)| k)
                        .trim()
                        .to_string()
                })
                .collect(),
        }
        .error(key, message)
    }
}

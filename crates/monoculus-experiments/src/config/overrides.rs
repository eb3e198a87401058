//! `--set KEY=VALUE`: one override applied to the parsed table.

use super::*;

/// Applies one `KEY=VALUE` override to a table. VALUE is read as a TOML value
/// (`3`, `[1, 2]`, `"x"`), or else as a bare string.
pub fn apply_override(table: &mut toml::Table, assignment: &str) -> Result<String, ConfigError> {
    let bad = |m: String| ConfigError {
        file: "--set".into(),
        line: None,
        key: None,
        message: m,
    };
    let (key, value) = assignment
        .split_once('=')
        .ok_or_else(|| bad(format!("expected KEY=VALUE, got `{assignment}`")))?;
    let key = key.trim();
    if key.is_empty() || key.split('.').any(str::is_empty) {
        return Err(bad(format!("bad key `{key}`")));
    }
    let value = match toml::from_str::<toml::Table>(&format!("v = {}", value.trim())) {
        Ok(mut t) => t.remove("v").expect("parsed v"),
        Err(_) => toml::Value::String(value.trim().to_string()),
    };
    let parts: Vec<&str> = key.split('.').collect();
    let mut t = table;
    for part in &parts[..parts.len() - 1] {
        let entry = t
            .entry(part.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        t = entry.as_table_mut().ok_or_else(|| ConfigError {
            file: "--set".into(),
            line: None,
            key: Some(key.to_string()),
            message: format!("`{part}` is not a table"),
        })?;
    }
    t.insert(parts[parts.len() - 1].to_string(), value);
    Ok(key.to_string())
}

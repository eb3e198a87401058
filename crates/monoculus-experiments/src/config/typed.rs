//! A cell's table deserialised into its [`RunSpec`], serde's messages rewritten to name
//! the key the user wrote.

use super::*;

pub(super) fn typed(table: toml::Table, src: &Source<'_>) -> Result<RunSpec, ConfigError> {
    serde_path_to_error::deserialize::<_, RunSpec>(toml::Value::Table(table)).map_err(|e| {
        let mut key = e.path().to_string();
        if key == "." {
            key.clear();
        }
        let message = e.inner().message().to_string();
        for marker in ["unknown field `", "missing field `"] {
            if let Some(rest) = message.split(marker).nth(1)
                && let Some(field) = rest.split('`').next()
            {
                let parent = key
                    .strip_suffix(&format!(".{field}"))
                    .unwrap_or(&key)
                    .to_string();
                let parent = if parent == field {
                    String::new()
                } else {
                    parent
                };
                key = if parent.is_empty() {
                    field.to_string()
                } else {
                    format!("{parent}.{field}")
                };
            }
        }
        let message = message.replace(", expected one of", "; expected one of");
        src.error(&key, message)
    })
}

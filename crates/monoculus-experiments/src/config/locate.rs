//! Finding the line of a dotted key in a TOML source, for error messages.

/// The dotted path of a `[table]` header line, split (`[a.b]` -> `["a", "b"]`), if the
/// line is one.
fn table_header(line: &str) -> Option<Vec<String>> {
    if !line.starts_with('[') || line.starts_with("[[") {
        return None;
    }
    let name = line
        .trim_start_matches('[')
        .split(']')
        .next()
        .unwrap_or("")
        .trim();
    Some(
        name.split('.')
            .map(|s| s.trim().trim_matches('"').to_string())
            .collect(),
    )
}

/// The 1-based line on which the key `path` (e.g. `swarm.n`) is set, if found. Handles
/// `[table]` headers, `key = value` lines and dotted keys; good enough for configs.
pub fn line_of(source: &str, path: &str) -> Option<usize> {
    let parts: Vec<&str> = path.split('.').collect();
    let mut table: Vec<String> = Vec::new();
    let mut header_line = None;
    for (no, raw) in source.lines().enumerate() {
        let line = raw.trim();
        if let Some(name) = table_header(line) {
            table = name;
            // The table itself, or else the first table inside it (`[a.b.c]` for `a`).
            if table.iter().map(String::as_str).eq(parts.iter().copied())
                || header_line.is_none()
                    && table.len() > parts.len()
                    && table.iter().zip(&parts).all(|(t, p)| t == p)
            {
                header_line = Some(no + 1);
            }
            continue;
        }
        let Some((key, _)) = line.split_once('=') else {
            continue;
        };
        if line.starts_with('#') {
            continue;
        }
        let mut full: Vec<String> = table.clone();
        full.extend(
            key.split('.')
                .map(|s| s.trim().trim_matches('"').to_string()),
        );
        if full.iter().map(String::as_str).eq(parts.iter().copied()) {
            return Some(no + 1);
        }
    }
    // An unknown or missing key inside a table: point at the table header.
    header_line.or_else(|| {
        if parts.len() > 1 {
            line_of(source, &parts[..parts.len() - 1].join("."))
        } else {
            None
        }
    })
}

/// The dotted key set on 1-based `line` (`swarm.n` for `n = 3` under `[swarm]`), if the
/// line sets one.
pub fn key_at_line(source: &str, line: usize) -> Option<String> {
    let mut table: Vec<String> = Vec::new();
    for (no, raw) in source.lines().enumerate() {
        let l = raw.trim();
        if no + 1 == line {
            let (key, _) = l.split_once('=')?;
            if l.starts_with('#') || l.starts_with('[') {
                return None;
            }
            let mut full = table;
            full.extend(
                key.split('.')
                    .map(|s| s.trim().trim_matches('"').to_string()),
            );
            return Some(full.join("."));
        }
        if let Some(name) = table_header(l) {
            table = name;
        }
    }
    None
}

/// The 1-based line of byte offset `offset`.
pub fn line_of_offset(source: &str, offset: usize) -> usize {
    source[..offset.min(source.len())].matches('\n').count() + 1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_keys_in_tables() {
        let src = "name = \"x\"\n\n[swarm]\nn = [1, 2]\nside = 3\n[algorithm]\nname = \"a\"\n";
        assert_eq!(line_of(src, "name"), Some(1));
        assert_eq!(line_of(src, "swarm.n"), Some(4));
        assert_eq!(line_of(src, "swarm.side"), Some(5));
        assert_eq!(line_of(src, "algorithm.name"), Some(7));
        assert_eq!(line_of(src, "algorithm.step"), Some(6));
        assert_eq!(line_of(src, "swarm"), Some(3));
        assert_eq!(line_of(src, "stop.max_rounds"), None);
        assert_eq!(key_at_line(src, 4).as_deref(), Some("swarm.n"));
        assert_eq!(key_at_line(src, 1).as_deref(), Some("name"));
        assert_eq!(key_at_line(src, 3), None);
    }
}

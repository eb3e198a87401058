//! Sweeps: the lists of a config (its axes) expanded into cells, each typed and
//! validated; the runs of an experiment.

use super::*;

pub(super) fn collect_axes(table: &toml::Table, prefix: &str, out: &mut Vec<Axis>) {
    for (k, v) in table {
        let path = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(t) => collect_axes(t, &path, out),
            toml::Value::Array(a) if path != "seeds" => out.push(Axis {
                path,
                values: a.clone(),
            }),
            _ => {}
        }
    }
}

pub(super) fn set_path(table: &mut toml::Table, path: &str, value: toml::Value) {
    let parts: Vec<&str> = path.split('.').collect();
    let mut t = table;
    for part in &parts[..parts.len() - 1] {
        t = t
            .get_mut(*part)
            .and_then(toml::Value::as_table_mut)
            .expect("axis path exists");
    }
    t.insert(parts[parts.len() - 1].to_string(), value);
}

/// The line that nests deepest, and roughly how deep: the dots of a header or key and the
/// brackets and braces open on it (strings are not told apart: this only points a
/// "nested too deeply" message at its line).
fn deepest_line(text: &str) -> (usize, usize) {
    let mut best = (1, 0);
    let mut open: usize = 0;
    for (k, raw) in text.lines().enumerate() {
        let line = raw.trim();
        let key = if line.starts_with('[') {
            line
        } else {
            line.split('=').next().unwrap_or("")
        };
        let dots = key.matches('.').count();
        let mut deepest_here = open;
        for c in line.chars() {
            match c {
                '[' | '{' => {
                    open += 1;
                    deepest_here = deepest_here.max(open);
                }
                ']' | '}' => open = open.saturating_sub(1),
                _ => {}
            }
        }
        if line.starts_with('[') {
            open = 0;
        }
        let depth = deepest_here.max(dots + 1);
        if depth > best.1 {
            best = (k + 1, depth);
        }
    }
    best
}

pub(super) fn render(value: &toml::Value) -> String {
    match value {
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

impl Experiment {
    /// Loads and validates the config at `path`, with `--set` overrides; algorithm
    /// names resolve through `registry`.
    pub fn load(
        path: &Path,
        overrides: &[String],
        registry: &Registry,
    ) -> Result<Experiment, ConfigError> {
        let label = path.display().to_string();
        let fail = |message: String| ConfigError {
            file: label.clone(),
            line: None,
            key: None,
            message,
        };
        // Read at most one byte past the limit: a huge file (or an endless one, such as
        // /dev/zero) is refused at once, not read.
        let mut bytes = Vec::new();
        std::fs::File::open(path)
            .and_then(|f| {
                std::io::Read::read_to_end(
                    &mut std::io::Read::take(f, crate::limits::MAX_CONFIG_BYTES + 1),
                    &mut bytes,
                )
            })
            .map_err(|e| fail(format!("cannot read: {e}")))?;
        if bytes.len() as u64 > crate::limits::MAX_CONFIG_BYTES {
            return Err(fail(format!(
                "larger than {} MB: a config is at most that; sweep long lists with --set or several configs",
                crate::limits::MAX_CONFIG_BYTES >> 20
            )));
        }
        let text = String::from_utf8(bytes).map_err(|e| {
            fail(format!(
                "not UTF-8 text (byte {})",
                e.utf8_error().valid_up_to()
            ))
        })?;
        let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::parse(&text, &label, &base, overrides, registry)
    }

    /// Parses a config from its text; `label` names it in errors, `base` resolves
    /// relative file paths, `registry` algorithm names.
    pub fn parse(
        text: &str,
        label: &str,
        base: &Path,
        overrides: &[String],
        registry: &Registry,
    ) -> Result<Experiment, ConfigError> {
        let mut table: toml::Table = toml::from_str(text).map_err(|e| {
            let line = e.span().map(|s| line_of_offset(text, s.start));
            let mut message = e.message().trim().to_string();
            if message.contains("as i128") || message.contains("number too large") {
                message = "integer too large: TOML integers are 64-bit".into();
            }
            let mut line = line;
            if message.contains("recursion limit") || message.contains("cannot recurse") {
                let (deepest, depth) = deepest_line(text);
                message = format!(
                    "nested about {depth} levels deep (tables, arrays, inline tables or dotted keys): a config nests at most 80 levels"
                );
                line = line.or(Some(deepest));
            }
            if message == "duplicate key"
                && let Some(span) = e.span()
                && let Some(k) = text.get(span)
            {
                message = format!("duplicate key `{}`", k.trim().trim_matches('"'));
            }
            ConfigError {
                file: label.to_string(),
                line,
                key: line.and_then(|l| key_at_line(text, l)),
                message,
            }
        })?;
        let mut src = Source {
            label: label.to_string(),
            text,
            overridden: Vec::new(),
        };
        for o in overrides {
            src.overridden.push(apply_override(&mut table, o)?);
        }
        let mut axes = Vec::new();
        collect_axes(&table, "", &mut axes);
        let count = validate_axes(&axes, &src)?;
        let mut cells = Vec::with_capacity(count);
        let mut warnings = Vec::new();
        let mut files = validate::Files::default();
        // Each cell starts from the config without its lists (so that making a cell costs
        // the size of the config, not of its lists: a list of 5 x 10^4 values is 5 x 10^4
        // cells, each a small table).
        let mut bare = table.clone();
        for axis in &axes {
            set_path(&mut bare, &axis.path, toml::Value::Boolean(false));
        }
        for index in 0..count {
            let mut rest = index;
            let mut chosen = vec![0; axes.len()];
            for (a, axis) in axes.iter().enumerate().rev() {
                chosen[a] = rest % axis.values.len();
                rest /= axis.values.len();
            }
            let mut cell_table = bare.clone();
            let mut values = Vec::with_capacity(axes.len());
            for (axis, &c) in axes.iter().zip(&chosen) {
                set_path(&mut cell_table, &axis.path, axis.values[c].clone());
                values.push((axis.path.clone(), render(&axis.values[c])));
            }
            let mut spec = typed(cell_table, &src)?;
            let (algorithm, params) = validate::algorithm(&spec, &src, registry, &mut warnings)?;
            spec.algorithm.params = params;
            let loaded = validate(&spec, &src, base, &mut files)?;
            let key = values
                .iter()
                .map(|(k, v)| format!("{k}={v}"))
                .collect::<Vec<_>>()
                .join(";");
            cells.push(Cell {
                index,
                key,
                values,
                spec,
                algorithm,
                file_positions: loaded.positions,
                schedule: loaded.schedule,
                durations: loaded.durations,
            });
        }
        let first = &cells[0].spec;
        validate_run_count(&first.seeds, count, &src)?;
        let seeds = first.seeds.to_vec();
        let mut resolved = toml::Table::try_from(first).expect("a RunSpec serialises");
        for axis in &axes {
            set_path(
                &mut resolved,
                &axis.path,
                toml::Value::Array(axis.values.clone()),
            );
        }
        warnings.sort();
        warnings.dedup();
        let mut resolved = toml::to_string(&resolved).expect("a table serialises");
        if !files.read.is_empty() {
            resolved.push_str(
                "\n# The files this experiment reads, and a hash of each one's contents: part of\n# its identity (config_hash). No run resumes and no merge joins results across a\n# change to one.\n",
            );
            for f in &files.read {
                resolved.push_str(&f.record());
                resolved.push('\n');
            }
        }
        Ok(Experiment {
            name: first.name.clone(),
            seeds,
            axes,
            cells,
            hash: crate::results::config_hash(&resolved),
            resolved,
            warnings,
            base: std::path::absolute(if base.as_os_str().is_empty() {
                Path::new(".")
            } else {
                base
            })
            .unwrap_or_else(|_| base.to_path_buf()),
            source: text.to_string(),
            overrides: overrides.to_vec(),
            inputs: files.read,
        })
    }

    /// Every run, cell-major then by seed.
    pub fn runs(&self) -> Vec<RunId> {
        self.cells
            .iter()
            .flat_map(|c| {
                self.seeds.iter().map(move |&seed| RunId {
                    cell: c.index,
                    seed,
                })
            })
            .collect()
    }
}

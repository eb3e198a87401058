use std::path::{Path, PathBuf};

use monoculus_experiments::results::{SUMMARY_COLUMNS, SummaryStats};

use super::Failure;

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Aligned plain text.
    Text,
    /// A Markdown table.
    Markdown,
}

#[derive(clap::Args, Debug)]
pub struct TableArgs {
    /// Results folders (each with a summary.csv).
    #[arg(required = true)]
    dirs: Vec<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value = "markdown")]
    format: Format,
    /// Also show how often and how much the hull grew: runs in which it grew, and over
    /// those runs the median of the largest relative growth in one round.
    #[arg(long)]
    hull: bool,
}

pub fn table(args: TableArgs) -> Result<(), Failure> {
    for (k, dir) in args.dirs.iter().enumerate() {
        let path = dir.join("summary.csv");
        if !path.exists() {
            return Err(Failure::Input(format!(
                "{}: no summary.csv; run the experiment first",
                dir.display()
            )));
        }
        // A blank line between tables, none after the last.
        if k > 0 {
            out!("\n");
        }
        if args.format == Format::Markdown {
            outln!("**{}**\n", dir.display());
        }
        out!("{}", render_with(&path, args.format, args.hull)?);
    }
    Ok(())
}

fn cell(x: f64, digits: usize) -> String {
    if x.is_nan() {
        "-".into()
    } else {
        format!("{x:.digits$}")
    }
}

/// The converged runs of a cell out of its runs, and how many are stuck (fell quiescent
/// short of their goal), if any: `20/20`, `0/20, 20 stuck`.
pub fn converged_cell(st: &SummaryStats) -> String {
    match st.stuck {
        0 => format!("{}/{}", st.converged, st.runs),
        k => format!("{}/{}, {k} stuck", st.converged, st.runs),
    }
}

/// The per-cell table of a summary.csv: parameters that vary or matter, then
/// converged/runs (with the stuck runs, if any) and rho, tau and rounds as median
/// [q1, q3], over the converged runs.
pub fn render(path: &Path, format: Format) -> Result<String, Failure> {
    render_with(path, format, false)
}

/// [`render`], optionally with the hull-growth columns.
pub fn render_with(path: &Path, format: Format, hull: bool) -> Result<String, Failure> {
    let bad = |e: csv::Error| Failure::Input(format!("{}: {e}", path.display()));
    let mut reader = csv::Reader::from_path(path).map_err(bad)?;
    let header = reader.headers().map_err(bad)?.clone();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| Failure::Input(format!("{}: no column {name}", path.display())))
    };
    // `missing`, `stuck` and `rounds_q1` are absent from folders written before 0.3:
    // read as 0 (NaN) there.
    let stat_names: Vec<&str> = SUMMARY_COLUMNS
        .iter()
        .copied()
        .filter(|&s| {
            !matches!(s, "missing" | "stuck" | "rounds_q1") || header.iter().any(|h| h == s)
        })
        .collect();
    let stat_idx: Vec<usize> = stat_names
        .iter()
        .map(|s| col(s))
        .collect::<Result<_, _>>()?;
    let records: Vec<csv::StringRecord> =
        reader.records().collect::<Result<_, _>>().map_err(bad)?;
    if records.is_empty() {
        return Err(Failure::Input(format!(
            "{}: holds no cells (only a header)",
            path.display()
        )));
    }
    for r in &records {
        let line = r.position().map_or(0, |p| p.line());
        for (&c, &name) in stat_idx.iter().zip(&stat_names) {
            let v = &r[c];
            let whole = matches!(
                name,
                "runs" | "converged" | "stuck" | "hull_grew_runs" | "missing"
            );
            let good = if whole {
                v.parse::<u64>().is_ok()
            } else {
                v.parse::<f64>().is_ok_and(|x| x.is_nan() || x >= 0.0)
            };
            if !good {
                return Err(Failure::Input(format!(
                    "{}:{line}: column {name}: {} is not {}",
                    path.display(),
                    monoculus_experiments::shown(v),
                    if whole {
                        "a whole number >= 0"
                    } else {
                        "a number >= 0 (or NaN)"
                    }
                )));
            }
        }
    }
    // Parameter columns: algorithm, n and side always; the others only where they vary.
    let first_stat = stat_idx[0];
    let params: Vec<usize> = (0..first_stat)
        .filter(|&i| !matches!(&header[i], "name" | "cell"))
        .filter(|&i| {
            matches!(&header[i], "algorithm" | "n" | "side")
                || records.iter().any(|r| r[i] != records[0][i])
        })
        .collect();
    let mut rows: Vec<Vec<String>> = Vec::new();
    let mut head: Vec<String> = params.iter().map(|&i| header[i].to_string()).collect();
    if hull {
        head.extend([
            "hull grew".to_string(),
            "largest growth in a round (median)".to_string(),
        ]);
    }
    head.extend([
        "converged".to_string(),
        "rho median [q1, q3]".into(),
        "tau median [q1, q3]".into(),
        "rounds median [q1, q3]".into(),
    ]);
    rows.push(head);
    let names: Vec<String> = header.iter().map(String::from).collect();
    let schema = SummaryStats::schema(&names)
        .map_err(|m| Failure::Input(format!("{}: {m}", path.display())))?;
    let stats: Vec<SummaryStats> = records
        .iter()
        .map(|r| {
            let fields: Vec<String> = r.iter().map(String::from).collect();
            let line = r.position().map_or(0, |p| p.line());
            schema
                .read(&fields)
                .map_err(|m| Failure::Input(format!("{}:{line}: {m}", path.display())))
        })
        .collect::<Result<_, _>>()?;
    // A partial folder (an unfinished sweep, a merge with --partial) says so, and how
    // many runs each cell lacks.
    let missing: u64 = stats.iter().map(|s| s.missing).sum();
    if missing > 0 {
        rows[0].push("missing runs".into());
    }
    for (r, st) in records.iter().zip(&stats) {
        let mut row: Vec<String> = params.iter().map(|&i| r[i].to_string()).collect();
        if hull {
            row.push(format!("{}/{}", st.hull_grew_runs, st.runs));
            row.push(cell(st.hull_growth_max_median, 3));
        }
        row.push(converged_cell(st));
        row.push(format!(
            "{} [{}, {}]",
            cell(st.rho_median, 3),
            cell(st.rho_q1, 3),
            cell(st.rho_q3, 3)
        ));
        row.push(format!(
            "{} [{}, {}]",
            cell(st.tau_median, 3),
            cell(st.tau_q1, 3),
            cell(st.tau_q3, 3)
        ));
        row.push(format!(
            "{} [{}, {}]",
            cell(st.rounds_median, 1),
            cell(st.rounds_q1, 1),
            cell(st.rounds_q3, 1)
        ));
        if missing > 0 {
            row.push(st.missing.to_string());
        }
        rows.push(row);
    }
    let widths: Vec<usize> = (0..rows[0].len())
        .map(|c| rows.iter().map(|r| r[c].len()).max().unwrap_or(0))
        .collect();
    let mut out = String::new();
    if missing > 0 {
        let total: u64 = stats.iter().map(|s| s.runs + s.missing).sum();
        out.push_str(&format!(
            "partial: {missing} of {total} runs missing (an unfinished sweep, or merged with --partial)\n\n"
        ));
    }
    for (k, r) in rows.iter().enumerate() {
        let cells: Vec<String> = r
            .iter()
            .zip(&widths)
            .map(|(v, w)| format!("{v:>w$}"))
            .collect();
        match format {
            Format::Text => out.push_str(&format!("{}\n", cells.join("  "))),
            Format::Markdown => {
                out.push_str(&format!("| {} |\n", cells.join(" | ")));
                if k == 0 {
                    let rule: Vec<String> = widths
                        .iter()
                        .map(|w| format!("{}:", "-".repeat(w.saturating_sub(1).max(1))))
                        .collect();
                    out.push_str(&format!("| {} |\n", rule.join(" | ")));
                }
            }
        }
    }
    Ok(out)
}

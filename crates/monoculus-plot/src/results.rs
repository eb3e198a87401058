//! Box plots of rho and tau from a results folder.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::PlotError;
use crate::boxes::{BoxSummary, TukeyBox};
use monoculus_experiments::results::RunMetrics;

use crate::table::{Cells, Table};

/// Colours of the algorithms, in order of appearance.
const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
];

/// One figure: for each category on the x axis and each series, the values.
struct BoxFigure {
    title: String,
    x_label: String,
    y_label: String,
    categories: Vec<String>,
    series: Vec<String>,
    /// values[category][series]
    values: Vec<Vec<Vec<f64>>>,
}

fn sanitize(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect::<String>()
        .trim_matches('_')
        .to_string()
}

/// Distinct values in order: numerically if all are numbers, else in order of first
/// appearance (cell order, which is the config's order).
fn sort_values(values: &mut Vec<String>) {
    let mut seen = Vec::new();
    for v in values.drain(..) {
        if !seen.contains(&v) {
            seen.push(v);
        }
    }
    if seen.iter().all(|v| v.parse::<f64>().is_ok()) {
        seen.sort_by(|a, b| {
            a.parse::<f64>()
                .unwrap_or(0.0)
                .total_cmp(&b.parse::<f64>().unwrap_or(0.0))
        });
    }
    *values = seen;
}

/// A compact axis label: `{ kind = "uniform", min = 0.1, max = 1.9 }` becomes
/// `uniform min=0.1 max=1.9`.
fn short_label(v: &str) -> String {
    v.trim_start_matches('{')
        .trim_end_matches('}')
        .replace("kind = ", "")
        .replace('"', "")
        .replace(" = ", "=")
        .replace(", ", " ")
        .trim()
        .to_string()
}

/// Figures of rho and tau along every swept key of the results folder `dir`, written
/// to `out` as PNG and SVG. Returns the files written.
pub fn plot_results(dir: &Path, out: &Path) -> Result<Vec<PathBuf>, PlotError> {
    crate::font::ensure()?;
    let runs = Table::read(&dir.join("runs.csv"))?;
    runs.require_rows("runs")?;
    let (cell_col, seed_col) = (runs.col("cell")?, runs.check("seed", Cells::Whole)?);
    let algo = runs.col("algorithm")?;
    runs.check("converged", Cells::Bool)?;
    for metric in ["rho", "tau"] {
        runs.check(metric, Cells::NonNegative)?;
    }
    // The outcome columns, through the schema the writer uses.
    let schema = RunMetrics::schema(&runs.header).map_err(|message| PlotError::Input {
        path: runs.path.clone(),
        message,
    })?;
    let metrics: Vec<RunMetrics> = runs
        .rows
        .iter()
        .zip(&runs.lines)
        .map(|(r, &line)| {
            schema.read(r).map_err(|message| PlotError::Input {
                path: format!("{}:{line}", runs.path),
                message,
            })
        })
        .collect::<Result<_, _>>()?;
    let name = runs
        .rows
        .first()
        .map(|r| r[runs.col("name").unwrap_or(0)].clone())
        .unwrap_or_default();
    // Parameter columns sit between `cell` and `seed`; the swept ones vary.
    let varying: Vec<usize> = (cell_col + 1..seed_col)
        .filter(|&c| c != algo && runs.rows.iter().any(|r| r[c] != runs.rows[0][c]))
        .collect();
    std::fs::create_dir_all(out).map_err(|e| PlotError::Io {
        path: out.display().to_string(),
        message: e.to_string(),
    })?;
    let mut algorithms: Vec<String> = Vec::new();
    for r in &runs.rows {
        if !algorithms.contains(&r[algo]) {
            algorithms.push(r[algo].clone());
        }
    }
    let axes: Vec<Option<usize>> = if varying.is_empty() {
        vec![None]
    } else {
        varying.iter().map(|&c| Some(c)).collect()
    };
    let mut written = Vec::new();
    for &axis in &axes {
        let others: Vec<usize> = varying
            .iter()
            .copied()
            .filter(|&c| Some(c) != axis)
            .collect();
        let mut groups: BTreeMap<String, Vec<(&Vec<String>, &RunMetrics)>> = BTreeMap::new();
        for (r, m) in runs.rows.iter().zip(&metrics) {
            let key = others
                .iter()
                .map(|&c| format!("{}={}", runs.header[c], r[c]))
                .collect::<Vec<_>>()
                .join(", ");
            groups.entry(key).or_default().push((r, m));
        }
        for (group, rows) in &groups {
            let mut categories: Vec<String> = match axis {
                Some(c) => rows.iter().map(|(r, _)| r[c].clone()).collect(),
                None => vec![String::new()],
            };
            sort_values(&mut categories);
            let x_label = axis.map_or("all runs".to_string(), |c| runs.header[c].clone());
            for metric in ["rho", "tau"] {
                let value = |m: &RunMetrics| if metric == "rho" { m.rho } else { m.tau };
                let collect = |series: &[String]| -> Vec<Vec<Vec<f64>>> {
                    categories
                        .iter()
                        .map(|cat| {
                            series
                                .iter()
                                .map(|a| {
                                    rows.iter()
                                        .filter(|(r, m)| {
                                            axis.is_none_or(|c| &r[c] == cat)
                                                && &r[algo] == a
                                                && m.converged
                                        })
                                        .map(|(_, m)| value(m))
                                        .filter(|v| v.is_finite())
                                        .collect()
                                })
                                .collect()
                        })
                        .collect()
                };
                let suffix = if group.is_empty() {
                    String::new()
                } else {
                    format!("__{}", sanitize(group))
                };
                let stem = format!("{metric}_vs_{}{suffix}", sanitize(&x_label));
                let title = format!(
                    "{name}: {metric}{}",
                    if group.is_empty() {
                        String::new()
                    } else {
                        format!(" ({group})")
                    }
                );
                let fig = BoxFigure {
                    title: title.clone(),
                    x_label: x_label.clone(),
                    y_label: metric.to_string(),
                    categories: categories.clone(),
                    series: algorithms.clone(),
                    values: collect(&algorithms),
                };
                written.extend(draw_both(out, &stem, &fig)?);
                if algorithms.len() > 1 {
                    for a in &algorithms {
                        let single = BoxFigure {
                            title: format!("{title}, {a}"),
                            x_label: x_label.clone(),
                            y_label: metric.to_string(),
                            categories: categories.clone(),
                            series: vec![a.clone()],
                            values: collect(std::slice::from_ref(a)),
                        };
                        written.extend(draw_both(
                            out,
                            &format!("{stem}__{}", sanitize(a)),
                            &single,
                        )?);
                    }
                }
            }
        }
    }
    Ok(written)
}

fn draw_both(out: &Path, stem: &str, fig: &BoxFigure) -> Result<Vec<PathBuf>, PlotError> {
    Ok(both!(out, stem, (900, 560), |root| draw_boxes(root, fig)))
}

fn draw_boxes<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    fig: &BoxFigure,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let all: Vec<f64> = fig.values.iter().flatten().flatten().copied().collect();
    let (mut lo, mut hi) = all
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    if !lo.is_finite() {
        (lo, hi) = (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.08).max(0.05);
    // Room above the data for the legend (upper left, about 20 pixels a series in a
    // plotting area about 430 high), so that it hides no box and no outlier.
    let legend = (12.0 + 20.0 * fig.series.len() as f64) / 430.0;
    let top = hi + pad + (hi - lo + 2.0 * pad) * legend / (1.0 - legend);
    let k = fig.categories.len();
    let mut chart = ChartBuilder::on(&root)
        .caption(&fig.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(
            (0..k - 1).into_segmented(),
            ((lo - pad) as f32)..(top as f32),
        )
        .map_err(e)?;
    let labels: Vec<String> = fig.categories.iter().map(|c| short_label(c)).collect();
    chart
        .configure_mesh()
        .disable_x_mesh()
        .light_line_style(WHITE)
        .x_desc(&fig.x_label)
        .y_desc(&fig.y_label)
        .x_labels(k.max(1))
        .x_label_formatter(&|v| match v {
            SegmentValue::CenterOf(i) => labels.get(*i).cloned().unwrap_or_default(),
            _ => String::new(),
        })
        .label_style(("sans-serif", 15))
        .draw()
        .map_err(e)?;
    let m = fig.series.len().max(1) as f64;
    let width = ((600.0 / (k as f64 * m)).clamp(8.0, 60.0)) as u32;
    for (s, name) in fig.series.iter().enumerate() {
        let color = PALETTE[s % PALETTE.len()];
        let offset = (s as f64 - (m - 1.0) / 2.0) * (width as f64 + 4.0);
        let boxes: Vec<_> = (0..k)
            .filter_map(|c| {
                BoxSummary::of(&fig.values[c][s]).map(|summary| {
                    TukeyBox::new(
                        SegmentValue::CenterOf(c),
                        &summary,
                        color.stroke_width(2),
                        width,
                        offset,
                    )
                })
            })
            .collect();
        chart
            .draw_series(boxes)
            .map_err(e)?
            .label(name.as_str())
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], color.filled()));
    }
    crate::legend::draw_legend(&mut chart)?;
    root.present().map_err(e)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn categories_keep_config_order_unless_numeric() {
        let mut v: Vec<String> = ["fixed", "uniform b", "uniform a", "fixed"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        sort_values(&mut v);
        assert_eq!(v, ["fixed", "uniform b", "uniform a"]);
        let mut n: Vec<String> = ["100", "20", "5", "20"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        sort_values(&mut n);
        assert_eq!(n, ["5", "20", "100"]);
        assert_eq!(
            short_label("{ kind = \"uniform\", min = 0.1, max = 1.9 }"),
            "uniform min=0.1 max=1.9"
        );
        assert_eq!(short_label("converge_locality"), "converge_locality");
    }
}

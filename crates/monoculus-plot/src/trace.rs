//! Figures of one run from `monoculus trace` output.

use std::path::{Path, PathBuf};

use glam::DVec2;
use monoculus_core::geometry::convex_hull_2d;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::PlotError;
use crate::table::{Cells, Table};

/// Figures of the trace CSV `trace` (and of `<stem>.positions.csv` beside it, if
/// present) written to `out` as PNG and SVG: `<stem>_series` (hull, diameter and moving
/// robots over rounds) and `<stem>_run` (paths, start and end, initial and final hull;
/// the x-y projection in 3D). Returns the files written.
pub fn plot_trace(trace: &Path, out: &Path) -> Result<Vec<PathBuf>, PlotError> {
    crate::font::ensure()?;
    let t = Table::read(trace)?;
    t.require_rows("rounds")?;
    let stem = trace
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("trace")
        .to_string();
    let measure = if t.col("hull_volume").is_ok() {
        "hull_volume"
    } else {
        "hull_area"
    };
    let series = vec![
        (
            measure.replace('_', " "),
            t.numbers(measure, Cells::NonNegative)?,
        ),
        (
            "diameter".to_string(),
            t.numbers("diameter", Cells::NonNegative)?,
        ),
        (
            "moving robots".to_string(),
            t.numbers("moving", Cells::Whole)?,
        ),
    ];
    let rounds = t.numbers("round", Cells::Whole)?;
    std::fs::create_dir_all(out).map_err(|e| PlotError::Io {
        path: out.display().to_string(),
        message: e.to_string(),
    })?;
    let mut written = Vec::new();
    let title = format!("{stem}: {} rounds", rounds.len().saturating_sub(1));
    written.extend(both!(out, format!("{stem}_series"), (800, 640), |root| {
        draw_series(root, &title, &rounds, &series)
    }));
    let positions = trace.with_extension("positions.csv");
    if positions.exists() {
        let p = Table::read(&positions)?;
        p.require_rows("positions")?;
        let (round, robot, x, y) = (
            p.numbers("round", Cells::Whole)?,
            p.numbers("robot", Cells::Whole)?,
            p.numbers("x", Cells::Finite)?,
            p.numbers("y", Cells::Finite)?,
        );
        // The swarm is the robots of the first round listed; every row names one of them.
        let n = round.iter().take_while(|&&r| r == round[0]).count();
        let listed_rounds = 1 + round.windows(2).filter(|w| w[0] != w[1]).count();
        monoculus_experiments::positions::check_trace_matches(trace, &positions, listed_rounds, n)
            .map_err(|e| PlotError::Input {
                path: positions.display().to_string(),
                message: e.to_string(),
            })?;
        let mut paths: Vec<Vec<DVec2>> = vec![Vec::new(); n];
        for i in 0..round.len() {
            let r = robot[i] as usize;
            if r >= n {
                return Err(PlotError::Input {
                    path: format!("{}:{}", positions.display(), p.lines[i]),
                    message: format!(
                        "column robot: {r} is not a robot of the swarm (round {} lists {n}: 0 to {})",
                        round[0],
                        n - 1
                    ),
                });
            }
            paths[r].push(DVec2::new(x[i], y[i]));
        }
        let projected = p.col("z").is_ok();
        let title = format!(
            "{stem}: {n} robots{}",
            if projected { " (x-y projection)" } else { "" }
        );
        written.extend(both!(out, format!("{stem}_run"), (640, 640), |root| {
            draw_run(root, &title, &paths)
        }));
    }
    Ok(written)
}

fn draw_series<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    rounds: &[f64],
    series: &[(String, Vec<f64>)],
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let root = root.titled(title, ("sans-serif", 22)).map_err(e)?;
    let panels = root.split_evenly((series.len(), 1));
    let last = rounds.last().copied().unwrap_or(0.0).max(1.0);
    let colors = [
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
    ];
    for (k, ((name, values), panel)) in series.iter().zip(panels.iter()).enumerate() {
        let hi = values
            .iter()
            .copied()
            .filter(|v| v.is_finite())
            .fold(0.0f64, f64::max)
            .max(1e-9);
        let mut chart = ChartBuilder::on(panel)
            .margin(8)
            .x_label_area_size(35)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0..last, 0.0..hi * 1.05)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("round")
            .x_label_formatter(&|x| {
                if (x - x.round()).abs() < 1e-9 {
                    format!("{x:.0}")
                } else {
                    String::new()
                }
            })
            .light_line_style(WHITE)
            .y_desc(name.as_str())
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(e)?;
        // Moving robots are counted per round; the start (round 0) has none.
        let skip = usize::from(name == "moving robots");
        let points = rounds
            .iter()
            .copied()
            .zip(values.iter().copied())
            .skip(skip);
        chart
            .draw_series(LineSeries::new(points, colors[k % 3].stroke_width(2)))
            .map_err(e)?;
    }
    root.present().map_err(e)
}

fn draw_run<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    paths: &[Vec<DVec2>],
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let all = paths.iter().flatten();
    let (lo, hi) = all.fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(l, h), p| (l.min(*p), h.max(*p)),
    );
    let span = (hi - lo).max_element().max(1e-9);
    let centre = (lo + hi) * 0.5;
    let half = span * 0.55;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(
            (centre.x - half)..(centre.x + half),
            (centre.y - half)..(centre.y + half),
        )
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("x")
        .y_desc("y")
        .light_line_style(WHITE)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(e)?;
    let grey = RGBColor(150, 150, 150);
    for path in paths {
        chart
            .draw_series(LineSeries::new(
                path.iter().map(|p| (p.x, p.y)),
                grey.stroke_width(1),
            ))
            .map_err(e)?;
    }
    let starts: Vec<DVec2> = paths.iter().filter_map(|p| p.first().copied()).collect();
    let ends: Vec<DVec2> = paths.iter().filter_map(|p| p.last().copied()).collect();
    let blue = RGBColor(31, 119, 180);
    let red = RGBColor(214, 39, 40);
    for (points, color, label) in [
        (&starts, blue, "start and initial hull"),
        (&ends, red, "end and final hull"),
    ] {
        let mut hull = convex_hull_2d(points);
        if let Some(&first) = hull.first() {
            hull.push(first);
        }
        chart
            .draw_series(LineSeries::new(
                hull.iter().map(|p| (p.x, p.y)),
                color.stroke_width(2),
            ))
            .map_err(e)?;
        let filled = color == red;
        chart
            .draw_series(points.iter().map(|p| {
                let style = if filled {
                    color.filled()
                } else {
                    color.stroke_width(2)
                };
                Circle::new((p.x, p.y), 4, style)
            }))
            .map_err(e)?
            .label(label)
            .legend(move |(x, y)| Circle::new((x + 7, y), 4, color.filled()));
    }
    crate::legend::draw_legend(&mut chart)?;
    root.present().map_err(e)
}

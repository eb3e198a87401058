//! The figure of the impossibility construction ([`monoculus_core::impossibility`]).

use std::path::{Path, PathBuf};

use glam::DVec2;
use monoculus_core::geometry::convex_hull_2d;
use monoculus_core::impossibility::{Indistinguishable, leaves_hull};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::PlotError;

/// Move directions drawn in each panel.
const FAN: usize = 24;

/// Draws `impossibility.png` and `.svg` into `out`: the far configuration (left) and the
/// near one (right), the same directions seen from robot 0 in both, and robot 0's moves
/// of length `step` in 24 directions, red where the move leaves that configuration's
/// hull. Returns the files written.
pub fn plot_impossibility(
    c: &Indistinguishable,
    step: f64,
    out: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    crate::font::ensure()?;
    std::fs::create_dir_all(out).map_err(|e| PlotError::Draw {
        path: out.display().to_string(),
        message: e.to_string(),
    })?;
    Ok(both!(out, "impossibility", (1200, 600), |root| draw(
        root, c, step
    )))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    c: &Indistinguishable,
    step: f64,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (left, right) = root.split_horizontally(600);
    panel(
        &left,
        &c.far,
        step,
        "far: robot 0 (black) sees these directions",
    )?;
    panel(
        &right,
        &c.near,
        step,
        "near: the same directions; every move leaves the hull",
    )?;
    root.present().map_err(e)
}

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    config: &[DVec2],
    step: f64,
    title: &str,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let (lo, hi) = config
        .iter()
        .fold((DVec2::splat(-step), DVec2::splat(step)), |(l, h), p| {
            (l.min(*p), h.max(*p))
        });
    let centre = (lo + hi) * 0.5;
    let half = (hi - lo).max_element() * 0.6;
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 17))
        .margin(12)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(
            (centre.x - half)..(centre.x + half),
            (centre.y - half)..(centre.y + half),
        )
        .map_err(e)?;
    chart
        .configure_mesh()
        .light_line_style(WHITE)
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(e)?;
    let (grey, blue, red, green) = (
        RGBColor(170, 170, 170),
        RGBColor(31, 119, 180),
        RGBColor(214, 39, 40),
        RGBColor(44, 160, 44),
    );
    let me = config[0];
    // The rays robot 0 sees, drawn to the panel's edge: the same in both panels.
    for q in &config[1..] {
        // To the panel's edge, not beyond (plotters clamps each coordinate on its own,
        // which would bend the ray).
        let d = (*q - me).normalize();
        let reach = |m: f64, d: f64, c: f64| match d {
            d if d > 1e-12 => (c + half - m) / d,
            d if d < -1e-12 => (c - half - m) / d,
            _ => f64::INFINITY,
        };
        let t = reach(me.x, d.x, centre.x).min(reach(me.y, d.y, centre.y));
        let end = me + d * t;
        chart
            .draw_series(LineSeries::new(
                [(me.x, me.y), (end.x, end.y)],
                grey.stroke_width(1),
            ))
            .map_err(e)?;
    }
    let mut hull = convex_hull_2d(config);
    if let Some(&first) = hull.first() {
        hull.push(first);
    }
    chart
        .draw_series(LineSeries::new(
            hull.iter().map(|p| (p.x, p.y)),
            blue.stroke_width(2),
        ))
        .map_err(e)?;
    for k in 0..FAN {
        let u = DVec2::from_angle(k as f64 * std::f64::consts::TAU / FAN as f64);
        let color = if leaves_hull(config, step, u) {
            red
        } else {
            green
        };
        let to = me + u * step;
        chart
            .draw_series(LineSeries::new(
                [(me.x, me.y), (to.x, to.y)],
                color.stroke_width(2),
            ))
            .map_err(e)?;
        chart
            .draw_series(std::iter::once(Circle::new(
                (to.x, to.y),
                3,
                color.filled(),
            )))
            .map_err(e)?;
    }
    chart
        .draw_series(
            config[1..]
                .iter()
                .map(|p| Circle::new((p.x, p.y), 5, blue.filled())),
        )
        .map_err(e)?;
    chart
        .draw_series(std::iter::once(Circle::new(
            (me.x, me.y),
            6,
            BLACK.filled(),
        )))
        .map_err(e)?;
    Ok(())
}

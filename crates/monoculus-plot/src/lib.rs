//! Figures from monoculus results, in PNG and SVG, drawn with plotters.
//!
//! - [`plot_results`]: from a results folder (`runs.csv`), box plots of rho and tau per
//!   cell along every swept key, one colour per algorithm: the distributions over seeds
//!   of the paper's Figures 3 to 6 and the algorithm comparisons of Figures 7 to 10.
//! - [`plot_trace`]: from a `monoculus trace` CSV, hull, diameter and moving robots
//!   over rounds; with its positions file, a picture of the run (paths, start and end
//!   positions, initial and final hull).
//!
//! Text is rendered with the bundled DejaVu Sans font (pure Rust, no system fonts).

// (Before the modules, which use it.)
/// Draws a figure as `<stem>.png` and `<stem>.svg` in `out`; evaluates to the two paths
/// or returns the error.
macro_rules! both {
    ($out:expr, $stem:expr, $size:expr, |$root:ident| $draw:expr) => {{
        let stem = $stem;
        let png = $out.join(format!("{stem}.png"));
        let svg = $out.join(format!("{stem}.svg"));
        let fail = |path: &std::path::Path, message: String| crate::PlotError::Draw {
            path: path.display().to_string(),
            message,
        };
        {
            let $root = plotters::prelude::BitMapBackend::new(&png, $size).into_drawing_area();
            $draw.map_err(|m| fail(&png, m))?;
        }
        {
            let $root = plotters::prelude::SVGBackend::new(&svg, $size).into_drawing_area();
            $draw.map_err(|m| fail(&svg, m))?;
        }
        vec![png, svg]
    }};
}

mod boxes;
mod error;
mod font;
mod impossibility;
mod legend;
mod replay;
mod results;
mod table;
mod trace;

pub use error::PlotError;
pub use impossibility::plot_impossibility;
pub use replay::{replay_html, replay_json, write_replay_gif, write_replay_html};
pub use results::plot_results;
pub use trace::plot_trace;

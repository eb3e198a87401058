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
/// or returns the error. Each is drawn in memory and written whole or not at all
/// ([`monoculus_experiments::output`]): a failed or interrupted drawing leaves the
/// figures that were there.
macro_rules! both {
    ($out:expr, $stem:expr, $size:expr, |$root:ident| $draw:expr) => {{
        let stem = $stem;
        let size: (u32, u32) = $size;
        let png = $out.join(format!("{stem}.png"));
        let svg = $out.join(format!("{stem}.svg"));
        let fail = |path: &std::path::Path, message: String| crate::PlotError::Draw {
            path: path.display().to_string(),
            message,
        };
        let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
        {
            let $root = plotters::prelude::BitMapBackend::with_buffer(&mut pixels, size)
                .into_drawing_area();
            $draw.map_err(|m| fail(&png, m))?;
        }
        crate::save_png(&png, &pixels, size)?;
        let mut text = String::new();
        {
            let $root =
                plotters::prelude::SVGBackend::with_string(&mut text, size).into_drawing_area();
            $draw.map_err(|m| fail(&svg, m))?;
        }
        crate::save(&svg, text.as_bytes())?;
        vec![png, svg]
    }};
}

/// Writes `bytes` to `path`, whole or not at all.
pub(crate) fn save(path: &std::path::Path, bytes: &[u8]) -> Result<(), PlotError> {
    monoculus_experiments::output::write_atomic(path, bytes).map_err(|e| PlotError::Io {
        path: e.path,
        message: e.cause.to_string(),
    })
}

/// Encodes RGB `pixels` of `size` as a PNG and writes it to `path`, whole or not at all.
pub(crate) fn save_png(
    path: &std::path::Path,
    pixels: &[u8],
    size: (u32, u32),
) -> Result<(), PlotError> {
    let mut bytes = Vec::new();
    let encoded = (|| {
        let mut e = png::Encoder::new(&mut bytes, size.0, size.1);
        e.set_color(png::ColorType::Rgb);
        e.set_depth(png::BitDepth::Eight);
        let mut w = e.write_header()?;
        w.write_image_data(pixels)?;
        w.finish()
    })();
    encoded.map_err(|e| PlotError::Draw {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    save(path, &bytes)
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
pub use replay::{
    VIEW_JS, VIEW_SLOT, base64, light_colour, replay_html, replay_json, write_replay_gif,
    write_replay_html,
};
pub use results::plot_results;
pub use trace::plot_trace;

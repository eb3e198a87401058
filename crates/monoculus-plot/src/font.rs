//! The bundled font (DejaVu Sans; license in `assets/DejaVu-LICENSE.txt`).

use std::sync::OnceLock;

use plotters::style::{FontStyle, register_font};

use crate::PlotError;

static DEJAVU_SANS: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Registers the font as "sans-serif" once per process.
pub(crate) fn ensure() -> Result<(), PlotError> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok =
        *DONE.get_or_init(|| register_font("sans-serif", FontStyle::Normal, DEJAVU_SANS).is_ok());
    if ok {
        Ok(())
    } else {
        Err(PlotError::Draw {
            path: "DejaVuSans.ttf".into(),
            message: "the bundled font could not be loaded".into(),
        })
    }
}

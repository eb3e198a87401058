//! Plotting errors.

/// Why a figure could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// A file could not be read or written.
    #[error("{}: {}", one_line(path), one_line(message))]
    Io {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// The input lacks what a figure needs.
    #[error("{}: {}", one_line(path), one_line(message))]
    Input {
        /// The file.
        path: String,
        /// What is missing.
        message: String,
    },
    /// Drawing failed.
    #[error("drawing {}: {}", one_line(path), one_line(message))]
    Draw {
        /// The figure.
        path: String,
        /// Why.
        message: String,
    },
}

/// `text` with control characters escaped, so that a message quoting a file stays one
/// line.
fn one_line(text: &str) -> String {
    text.chars()
        .flat_map(|c| {
            if c.is_control() {
                c.escape_default().collect::<Vec<_>>()
            } else {
                vec![c]
            }
        })
        .collect()
}

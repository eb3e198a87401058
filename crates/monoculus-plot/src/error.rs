//! Plotting errors.

/// Why a figure could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// A file could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// The input lacks what a figure needs.
    #[error("{path}: {message}")]
    Input {
        /// The file.
        path: String,
        /// What is missing.
        message: String,
    },
    /// Drawing failed.
    #[error("drawing {path}: {message}")]
    Draw {
        /// The figure.
        path: String,
        /// Why.
        message: String,
    },
}

//! Every file monoculus writes goes through this module: whole or not at all, never over
//! one of the command's own inputs, never two outputs on one path, and one name per
//! distinct output.
//!
//! - [`AtomicFile`] and [`write_atomic`]: a temporary file in the target's folder,
//!   synced, then renamed over the target; an error, a panic or a signal leaves the
//!   previous file as it was ([`remove_temporaries_on_signal`]).
//! - [`Paths`]: a command's inputs and outputs, checked to be distinct files.
//! - [`unique_stems`]: file names for a list of outputs, distinct whatever their labels.
//! - [`json`]: JSON (serde_json), safe to embed in a page's `<script>`.

mod atomic;
pub mod json;
mod names;
mod paths;

pub use atomic::{
    AtomicFile, Graceful, INTERRUPTED, Together, create_if_absent, remove_temporaries_on_signal,
    write_atomic,
};
pub use names::unique_stems;
pub use paths::Paths;

/// Writing an output failed: the file the user asked for (never a temporary name), and
/// why.
#[derive(Debug, thiserror::Error)]
#[error("{}: {cause}", crate::one_line(path))]
pub struct OutputError {
    /// The output file.
    pub path: String,
    /// Why.
    pub cause: std::io::Error,
}

impl OutputError {
    /// An error on `path`.
    pub fn new(path: &std::path::Path, cause: std::io::Error) -> OutputError {
        OutputError {
            path: path.display().to_string(),
            cause,
        }
    }
}

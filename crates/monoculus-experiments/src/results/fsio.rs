//! Reading and writing results files: every write goes through [`crate::output`]'s
//! one writer (a temporary file in the same folder, fsync, rename or hard link), and
//! reads of files appended line by line leave out a last line cut short.

use std::fs;
use std::path::Path;

use super::ResultsError;

/// An I/O error on `path` (the file the user knows, never a temporary name).
pub(crate) fn io(path: &Path) -> impl Fn(std::io::Error) -> ResultsError + '_ {
    move |cause| ResultsError::Io {
        path: path.display().to_string(),
        cause,
    }
}

/// The complete lines of a file appended line by line: its bytes up to the last newline,
/// and whether a last line was cut short (what a kill in mid-append leaves).
pub(crate) fn read_complete_lines(path: &Path) -> Result<(Vec<u8>, bool), ResultsError> {
    let mut bytes = fs::read(path).map_err(io(path))?;
    let whole = bytes
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |last| last + 1);
    let cut = whole != bytes.len();
    bytes.truncate(whole);
    Ok((bytes, cut))
}

/// Replaces `path` by `bytes`, whole or not at all ([`crate::output::write_atomic`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ResultsError> {
    Ok(crate::output::write_atomic(path, bytes)?)
}

/// Creates `path` holding `bytes` unless it exists; `Ok(false)` if it did
/// ([`crate::output::create_if_absent`]).
pub fn create_if_absent(path: &Path, bytes: &[u8]) -> Result<bool, ResultsError> {
    Ok(crate::output::create_if_absent(path, bytes)?)
}

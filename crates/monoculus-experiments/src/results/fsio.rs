//! Writing results files so that at every instant a reader finds the old file or the new
//! one, whole: a unique temporary name in the same folder, fsync, then rename (replace) or
//! hard link (create only if absent).

use std::fs::{self, File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use super::ResultsError;

/// An I/O error on `path` (the file the user knows, never a temporary name).
pub(crate) fn io(path: &Path) -> impl Fn(std::io::Error) -> ResultsError + '_ {
    move |cause| ResultsError::Io {
        path: path.display().to_string(),
        cause,
    }
}

/// A temporary name beside `path`, unique across processes (pid) and threads (counter).
fn temporary(path: &Path) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .map_or_else(|| "file".into(), |n| n.to_string_lossy().into_owned());
    let k = COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.{}.{k}.tmp", std::process::id()))
}

/// Writes `bytes` to a fresh temporary file beside `path` and syncs it.
fn write_temporary(path: &Path, bytes: &[u8]) -> Result<PathBuf, ResultsError> {
    let tmp = temporary(path);
    let written = (|| {
        let mut f = OpenOptions::new().write(true).create_new(true).open(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()
    })();
    if let Err(e) = written {
        let _ = fs::remove_file(&tmp);
        return Err(io(path)(e));
    }
    Ok(tmp)
}

/// Syncs the folder holding `path`, so that a rename survives a crash (best effort: not
/// every file system lets a folder be opened for that).
fn sync_parent(path: &Path) {
    if let Some(parent) = path.parent()
        && let Ok(d) = File::open(if parent.as_os_str().is_empty() {
            Path::new(".")
        } else {
            parent
        })
    {
        let _ = d.sync_all();
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

/// Replaces `path` by `bytes` atomically.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ResultsError> {
    let tmp = write_temporary(path, bytes)?;
    if let Err(e) = fs::rename(&tmp, path) {
        let _ = fs::remove_file(&tmp);
        return Err(io(path)(e));
    }
    sync_parent(path);
    Ok(())
}

/// Creates `path` holding `bytes` unless it exists; `Ok(false)` if it did. Whole or
/// absent at every instant, also when many processes try at once: exactly one creates it.
pub fn create_if_absent(path: &Path, bytes: &[u8]) -> Result<bool, ResultsError> {
    if path.exists() {
        return Ok(false);
    }
    let tmp = write_temporary(path, bytes)?;
    let linked = fs::hard_link(&tmp, path);
    let _ = fs::remove_file(&tmp);
    match linked {
        Ok(()) => {
            sync_parent(path);
            Ok(true)
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(false),
        // A file system without hard links: exclusive creation, then the bytes.
        Err(_) => match OpenOptions::new().write(true).create_new(true).open(path) {
            Ok(mut f) => {
                f.write_all(bytes).map_err(io(path))?;
                f.sync_all().map_err(io(path))?;
                Ok(true)
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(false),
            Err(e) => Err(io(path)(e)),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_replaces_and_leaves_no_temporary() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("a.csv");
        write_atomic(&p, b"one\n").unwrap();
        write_atomic(&p, b"two\n").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"two\n");
        assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 1);
    }

    #[test]
    fn exactly_one_of_many_creates() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("config.toml");
        let created: usize = std::thread::scope(|s| {
            let hs: Vec<_> = (0..16)
                .map(|k| {
                    let p = &p;
                    s.spawn(move || create_if_absent(p, format!("{k}").as_bytes()).unwrap())
                })
                .collect();
            hs.into_iter().map(|h| h.join().unwrap() as usize).sum()
        });
        assert_eq!(created, 1);
        assert_eq!(fs::read_dir(tmp.path()).unwrap().count(), 1);
        assert!(!create_if_absent(&p, b"x").unwrap());
    }
}

//! Whole or not at all: an output is written to a temporary file beside it (a unique
//! name in the same folder, so the rename cannot cross file systems), synced, and renamed
//! over the target. At every instant a reader finds the old file or the new one, whole.

use std::fs::{self, File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, LazyLock, Mutex};

use super::OutputError;

/// The temporary files being written by this process, removed by the signal handler
/// ([`remove_temporaries_on_signal`]) before it exits.
static LIVE: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The exit status of a process stopped by SIGINT, SIGTERM or SIGHUP (128 + SIGINT, as
/// shells report a Ctrl-C).
pub const INTERRUPTED: i32 = 130;

fn live() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    LIVE.lock().unwrap_or_else(|p| p.into_inner())
}

/// Installs handlers for SIGINT, SIGTERM and SIGHUP that remove every temporary file this
/// process is writing and exit with status [`INTERRUPTED`], so that a signal leaves each
/// output as it was before the command started. Call once, first thing in `main`.
///
/// Files appended run by run (`runs.csv`, shard files) need nothing more: every row is
/// whole once written, and a resume drops a row cut short.
///
/// ```no_run
/// monoculus_experiments::output::remove_temporaries_on_signal();
/// ```
pub fn remove_temporaries_on_signal() {
    // A second installation (a test harness, an embedding program) is refused by ctrlc:
    // the first handler stays, which is what we want.
    let _ = ctrlc::set_handler(|| {
        PENDING_EXIT.store(true, Ordering::SeqCst);
        // Inside a [`Together`] section the last one to leave exits instead.
        if TOGETHER.load(Ordering::SeqCst) == 0 {
            exit_interrupted();
        }
    });
}

/// [`Together`] sections open now.
static TOGETHER: AtomicUsize = AtomicUsize::new(0);
/// A signal arrived (the process exits when no [`Together`] section is open): the flag
/// [`Graceful::flag`] hands out.
static PENDING_EXIT: LazyLock<Arc<AtomicBool>> = LazyLock::new(|| Arc::new(AtomicBool::new(false)));
/// Someone is exiting: nobody else calls `exit`.
static EXITING: AtomicBool = AtomicBool::new(false);

fn exit_interrupted() {
    if EXITING.swap(true, Ordering::SeqCst) {
        // Another thread exits; wait for it.
        loop {
            std::thread::park();
        }
    }
    for tmp in live().drain(..) {
        let _ = fs::remove_file(tmp);
    }
    std::process::exit(INTERRUPTED);
}

/// Files that belong together (a hunt's folder: a start and the config that replays
/// it): while one of these guards lives, a signal waits, and the process exits once the
/// last guard is dropped, so that the files are all of the old set or all of the new.
///
/// ```
/// use monoculus_experiments::output::{Together, write_atomic};
/// let dir = tempfile::tempdir()?;
/// {
///     let _together = Together::enter();
///     write_atomic(&dir.path().join("a.csv"), b"x,y\n0,0\n")?;
///     write_atomic(&dir.path().join("a.toml"), b"name = \"a\"\n")?;
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[must_use = "the section ends when the guard is dropped"]
pub struct Together(());

impl Together {
    /// Opens a section.
    pub fn enter() -> Together {
        TOGETHER.fetch_add(1, Ordering::SeqCst);
        Together(())
    }
}

/// A piece of work that a signal ends gracefully (a hunt): while the guard lives, a
/// signal ([`remove_temporaries_on_signal`]'s handlers) sets [`Graceful::flag`] instead
/// of exiting; the work polls the flag, stops, and saves what it has; the process exits
/// with status [`INTERRUPTED`] when the guard is dropped.
///
/// ```
/// use monoculus_experiments::output::Graceful;
/// use std::sync::atomic::Ordering;
///
/// let graceful = Graceful::enter();
/// let stop = graceful.flag();
/// while !stop.load(Ordering::Relaxed) {
///     // ... one step of the work ...
///     break;
/// }
/// // ... save what the work has ...
/// drop(graceful); // exits with status 130 here if a signal came
/// ```
#[must_use = "the section ends when the guard is dropped"]
pub struct Graceful(Together);

impl Graceful {
    /// Opens a section.
    pub fn enter() -> Graceful {
        Graceful(Together::enter())
    }

    /// Set when a signal has come (it stays set).
    pub fn flag(&self) -> Arc<AtomicBool> {
        PENDING_EXIT.clone()
    }
}

impl Drop for Together {
    fn drop(&mut self) {
        if TOGETHER.fetch_sub(1, Ordering::SeqCst) == 1 && PENDING_EXIT.load(Ordering::SeqCst) {
            exit_interrupted();
        }
    }
}

/// A temporary name beside `path`, unique across processes (pid) and threads (counter):
/// `.NAME.PID.K.tmp`.
fn temporary(path: &Path) -> PathBuf {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let k = COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(
        ".{}.{}.{k}.tmp",
        file_name(path),
        std::process::id()
    ))
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map_or_else(|| "file".into(), |n| n.to_string_lossy().into_owned())
}

fn folder(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Removes the temporaries for `path` that processes no longer running left behind (a
/// SIGKILL gives no chance to clean up). Best effort; Linux only (it reads `/proc`).
fn remove_orphans(path: &Path) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let prefix = format!(".{}.", file_name(path));
    let Ok(entries) = fs::read_dir(folder(path)) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name
            .strip_prefix(&prefix)
            .and_then(|r| r.strip_suffix(".tmp"))
        else {
            continue;
        };
        let pid = rest.split('.').next().and_then(|p| p.parse::<u32>().ok());
        if let Some(pid) = pid
            && pid != std::process::id()
            && !Path::new(&format!("/proc/{pid}")).exists()
        {
            let _ = fs::remove_file(e.path());
        }
    }
}

/// Syncs the folder holding `path`, so that a rename survives a crash (best effort: not
/// every file system lets a folder be opened for that).
fn sync_folder(path: &Path) {
    if let Ok(d) = File::open(folder(path)) {
        let _ = d.sync_all();
    }
}

/// An output being written: bytes go to a temporary file beside the target, which
/// [`AtomicFile::commit`] syncs and renames over it. Dropped without a commit (an
/// error, a panic) it removes the temporary, and the target is as it was.
///
/// ```
/// use std::io::Write;
/// use monoculus_experiments::output::AtomicFile;
///
/// let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("trace.csv");
/// std::fs::write(&path, "old\n").unwrap();
/// let mut f = AtomicFile::create(&path).unwrap();
/// writeln!(f, "round,moving").unwrap();
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "old\n"); // not yet
/// f.commit().unwrap();
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "round,moving\n");
/// ```
pub struct AtomicFile {
    target: PathBuf,
    tmp: PathBuf,
    file: Option<BufWriter<File>>,
}

impl AtomicFile {
    /// Starts writing `target` (which is not touched until the commit).
    pub fn create(target: &Path) -> Result<AtomicFile, OutputError> {
        remove_orphans(target);
        let tmp = temporary(target);
        let file = {
            let mut live = live();
            let f = OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&tmp)
                .map_err(|e| OutputError::new(target, e))?;
            live.push(tmp.clone());
            f
        };
        Ok(AtomicFile {
            target: target.to_path_buf(),
            tmp,
            file: Some(BufWriter::new(file)),
        })
    }

    /// The target.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The temporary file, for a writer that opens its output by path (the GIF encoder):
    /// what it writes there is what [`AtomicFile::commit`] renames.
    pub fn temporary(&self) -> &Path {
        &self.tmp
    }

    /// Flushes, syncs and renames the file over the target.
    pub fn commit(mut self) -> Result<(), OutputError> {
        let target = self.target.clone();
        let err = |e| OutputError::new(&target, e);
        let file = self.file.take().expect("committed once");
        let file = file.into_inner().map_err(|e| err(e.into_error()))?;
        drop(file);
        // Synced by path: a writer given the temporary's path may have replaced its
        // contents through another handle.
        File::open(&self.tmp)
            .and_then(|f| f.sync_all())
            .map_err(err)?;
        // Holding the list: a signal handler either finds the temporary (not renamed)
        // and removes it, or finds it gone and the target whole.
        let mut live = live();
        fs::rename(&self.tmp, &self.target).map_err(err)?;
        live.retain(|p| p != &self.tmp);
        drop(live);
        sync_folder(&self.target);
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.file.as_mut().expect("not committed").write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.as_mut().expect("not committed").flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.is_some() || self.tmp.exists() {
            let mut live = live();
            let _ = fs::remove_file(&self.tmp);
            live.retain(|p| p != &self.tmp);
        }
    }
}

/// Replaces `path` by `bytes`, whole or not at all.
///
/// ```
/// let dir = tempfile::tempdir().unwrap();
/// let path = dir.path().join("summary.csv");
/// monoculus_experiments::output::write_atomic(&path, b"runs\n1\n").unwrap();
/// assert_eq!(std::fs::read(&path).unwrap(), b"runs\n1\n");
/// ```
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    let mut f = AtomicFile::create(path)?;
    f.write_all(bytes).map_err(|e| OutputError::new(path, e))?;
    f.commit()
}

/// Creates `path` holding `bytes` unless it exists; `Ok(false)` if it did. Whole or
/// absent at every instant, also when many processes try at once: exactly one creates it
/// (a complete temporary file hard-linked to the name).
pub fn create_if_absent(path: &Path, bytes: &[u8]) -> Result<bool, OutputError> {
    if path.exists() {
        return Ok(false);
    }
    let err = |e| OutputError::new(path, e);
    let mut f = AtomicFile::create(path)?;
    f.write_all(bytes).map_err(err)?;
    f.flush().map_err(err)?;
    File::open(f.temporary())
        .and_then(|h| h.sync_all())
        .map_err(err)?;
    let linked = fs::hard_link(f.temporary(), path);
    drop(f);
    match linked {
        Ok(()) => {
            sync_folder(path);
            Ok(true)
        }
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(false),
        // A file system without hard links: exclusive creation, then the bytes.
        Err(_) => match OpenOptions::new().write(true).create_new(true).open(path) {
            Ok(mut h) => {
                h.write_all(bytes).map_err(err)?;
                h.sync_all().map_err(err)?;
                Ok(true)
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => Ok(false),
            Err(e) => Err(err(e)),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn atomic_write_replaces_and_leaves_no_temporary() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("a.csv");
        write_atomic(&p, b"one\n").unwrap();
        write_atomic(&p, b"two\n").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"two\n");
        assert_eq!(names(tmp.path()), ["a.csv"]);
    }

    #[test]
    fn an_uncommitted_file_leaves_the_old_one_and_no_temporary() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("t.csv");
        fs::write(&p, "good\n").unwrap();
        {
            let mut f = AtomicFile::create(&p).unwrap();
            f.write_all(b"half a ro").unwrap();
            assert_eq!(names(tmp.path()).len(), 2);
        }
        assert_eq!(fs::read(&p).unwrap(), b"good\n");
        assert_eq!(names(tmp.path()), ["t.csv"]);
        assert!(!live().iter().any(|t| t.starts_with(tmp.path())));
    }

    #[test]
    fn temporaries_of_dead_processes_are_removed() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join("r.html");
        // Pid 0 is never a process; another file's temporary is not ours to remove.
        fs::write(tmp.path().join(".r.html.4000000000.0.tmp"), "x").unwrap();
        fs::write(tmp.path().join(".other.4000000000.0.tmp"), "x").unwrap();
        write_atomic(&p, b"page").unwrap();
        let left = names(tmp.path());
        if Path::new("/proc/self").exists() {
            assert_eq!(left, [".other.4000000000.0.tmp", "r.html"]);
        }
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
        assert_eq!(names(tmp.path()), ["config.toml"]);
        assert!(!create_if_absent(&p, b"x").unwrap());
    }
}

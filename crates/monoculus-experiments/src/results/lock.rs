//! Advisory locks on a results folder and on each shard (`flock`: released by the kernel
//! when the process ends, however it ends).

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, Write};
use std::path::Path;

use super::ResultsError;
use super::fsio::io;

/// A held lock; released on drop.
#[derive(Debug)]
pub struct Lock {
    _file: File,
}

/// How a lock is taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LockKind {
    /// One holder (a plain run, a merge, one shard).
    Exclusive,
    /// Many holders (the shards of one folder).
    Shared,
}

fn open(path: &Path) -> Result<File, ResultsError> {
    OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(path)
        .map_err(io(path))
}

/// What the holder of an exclusive lock wrote into it ("pid 12 on host h, job 7_3").
pub fn holder(path: &Path) -> Option<String> {
    let mut s = String::new();
    File::open(path).ok()?.read_to_string(&mut s).ok()?;
    let s = s.trim();
    (!s.is_empty()).then(|| s.to_string())
}

impl Lock {
    /// Takes the lock at `path` without waiting; `Ok(None)` if another process holds it.
    /// An exclusive holder writes `who` into the file, for the message others get.
    pub fn try_take(path: &Path, kind: LockKind, who: &str) -> Result<Option<Lock>, ResultsError> {
        let file = open(path)?;
        let taken = match kind {
            LockKind::Exclusive => file.try_lock(),
            LockKind::Shared => file.try_lock_shared(),
        };
        match taken {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => return Ok(None),
            Err(std::fs::TryLockError::Error(e)) => return Err(io(path)(e)),
        }
        if kind == LockKind::Exclusive {
            let mut f = &file;
            f.set_len(0).map_err(io(path))?;
            f.rewind().map_err(io(path))?;
            f.write_all(format!("{who}\n").as_bytes())
                .map_err(io(path))?;
        }
        Ok(Some(Lock { _file: file }))
    }

    /// Whether some process holds `path` (exclusively or shared) right now.
    pub fn is_held(path: &Path) -> bool {
        let Ok(file) = File::open(path) else {
            return false;
        };
        match file.try_lock() {
            Ok(()) => {
                let _ = file.unlock();
                false
            }
            Err(_) => true,
        }
    }
}

/// "`guarded` is in use by ..." for the lock file `lock`.
fn busy(lock: &Path, guarded: &Path) -> ResultsError {
    ResultsError::Busy {
        path: guarded.display().to_string(),
        holder: holder(lock).unwrap_or_else(|| "another process".into()),
    }
}

/// Takes the exclusive lock `lock` that guards the file `guarded`, or fails naming the
/// process that holds it.
pub fn take_exclusive(lock: &Path, guarded: &Path, who: &str) -> Result<Lock, ResultsError> {
    Lock::try_take(lock, LockKind::Exclusive, who)?.ok_or_else(|| busy(lock, guarded))
}

/// Fails, naming the holder, if some process holds `lock` (which guards `guarded`).
pub fn ensure_free(lock: &Path, guarded: &Path) -> Result<(), ResultsError> {
    if Lock::is_held(lock) {
        return Err(busy(lock, guarded));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exclusive_refuses_everyone_and_names_its_holder() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join(".lock");
        let held = Lock::try_take(&p, LockKind::Exclusive, "pid 1 on host a").unwrap();
        assert!(held.is_some());
        assert!(
            Lock::try_take(&p, LockKind::Exclusive, "b")
                .unwrap()
                .is_none()
        );
        assert!(Lock::try_take(&p, LockKind::Shared, "b").unwrap().is_none());
        assert!(Lock::is_held(&p));
        assert_eq!(holder(&p).as_deref(), Some("pid 1 on host a"));
        drop(held);
        assert!(!Lock::is_held(&p));
        assert!(Lock::try_take(&p, LockKind::Shared, "c").unwrap().is_some());
    }

    #[test]
    fn shared_holders_coexist_and_keep_out_an_exclusive_one() {
        let tmp = tempfile::tempdir().unwrap();
        let p = tmp.path().join(".lock");
        let a = Lock::try_take(&p, LockKind::Shared, "a").unwrap();
        let b = Lock::try_take(&p, LockKind::Shared, "b").unwrap();
        assert!(a.is_some() && b.is_some());
        assert!(
            Lock::try_take(&p, LockKind::Exclusive, "c")
                .unwrap()
                .is_none()
        );
    }
}

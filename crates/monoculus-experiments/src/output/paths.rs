//! A command's inputs and outputs, checked to be distinct files before anything is
//! written: no command writes over a file it reads, and no two outputs share a path.

use std::path::{Path, PathBuf};

/// What a path names, for comparing: the file itself (device and inode) when it exists,
/// so that hard links and symbolic links compare equal, and its canonical path always.
#[derive(Clone, Debug)]
struct Identity {
    canonical: PathBuf,
    inode: Option<(u64, u64)>,
}

impl Identity {
    fn of(path: &Path) -> Identity {
        let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| {
            // Not there yet: its folder's canonical path and its name.
            let name = path.file_name().map(PathBuf::from).unwrap_or_default();
            let folder = match path.parent() {
                Some(p) if !p.as_os_str().is_empty() => p,
                _ => Path::new("."),
            };
            std::fs::canonicalize(folder)
                .or_else(|_| std::path::absolute(folder))
                .unwrap_or_else(|_| folder.to_path_buf())
                .join(name)
        });
        Identity {
            inode: inode(path),
            canonical,
        }
    }

    fn same(&self, other: &Identity) -> bool {
        self.canonical == other.canonical || self.inode.is_some() && self.inode == other.inode
    }
}

#[cfg(unix)]
fn inode(path: &Path) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    std::fs::metadata(path).ok().map(|m| (m.dev(), m.ino()))
}

#[cfg(not(unix))]
fn inode(_: &Path) -> Option<(u64, u64)> {
    None
}

/// The files one command reads and writes, each with how the user named it (`--out`,
/// `the config's scheduler.file`). [`Paths::check`] refuses an output that is one of the
/// inputs, or two outputs that are one file.
///
/// ```
/// use monoculus_experiments::output::Paths;
///
/// let dir = tempfile::tempdir().unwrap();
/// let schedule = dir.path().join("s.csv");
/// std::fs::write(&schedule, "round,robot\n1,0\n").unwrap();
/// let mut paths = Paths::default();
/// paths.input("the config's scheduler.file", &schedule);
/// paths.output("--out", &dir.path().join("t.csv"));
/// assert!(paths.check().is_ok());
/// paths.output("--schedule", &schedule);
/// let e = paths.check().unwrap_err();
/// assert!(e.contains("--schedule") && e.contains("scheduler.file"), "{e}");
/// ```
#[derive(Clone, Debug, Default)]
pub struct Paths {
    inputs: Vec<(String, PathBuf)>,
    outputs: Vec<(String, PathBuf)>,
}

impl Paths {
    /// A file the command reads.
    pub fn input(&mut self, label: impl Into<String>, path: &Path) -> &mut Self {
        self.inputs.push((label.into(), path.to_path_buf()));
        self
    }

    /// A file the command writes.
    pub fn output(&mut self, label: impl Into<String>, path: &Path) -> &mut Self {
        self.outputs.push((label.into(), path.to_path_buf()));
        self
    }

    /// Why the outputs cannot be written, if they cannot: one of them is an input, or
    /// two are one file. One line.
    pub fn check(&self) -> Result<(), String> {
        let inputs: Vec<Identity> = self.inputs.iter().map(|(_, p)| Identity::of(p)).collect();
        let outputs: Vec<Identity> = self.outputs.iter().map(|(_, p)| Identity::of(p)).collect();
        for (k, (label, path)) in self.outputs.iter().enumerate() {
            let out = &outputs[k];
            if let Some(i) = inputs.iter().position(|i| i.same(out)) {
                return Err(format!(
                    "{label} {}: is {} ({}), which this command reads; a command never writes over its own inputs: choose another file",
                    crate::one_line(&path.display().to_string()),
                    self.inputs[i].0,
                    crate::one_line(&self.inputs[i].1.display().to_string()),
                ));
            }
            if let Some(j) = outputs[..k].iter().position(|o| o.same(out)) {
                return Err(format!(
                    "{} {} and {label} {}: two outputs in one file; give each its own",
                    self.outputs[j].0,
                    crate::one_line(&self.outputs[j].1.display().to_string()),
                    crate::one_line(&path.display().to_string()),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn links_and_spellings_of_one_file_are_one_file() {
        let tmp = tempfile::tempdir().unwrap();
        let a = tmp.path().join("a.csv");
        std::fs::write(&a, "x").unwrap();
        let sub = tmp.path().join("sub");
        std::fs::create_dir(&sub).unwrap();
        let hard = tmp.path().join("hard.csv");
        std::fs::hard_link(&a, &hard).unwrap();
        for same in [
            sub.join("../a.csv"),
            hard.clone(),
            tmp.path().join("./a.csv"),
        ] {
            let mut p = Paths::default();
            p.input("in", &a).output("--out", &same);
            assert!(p.check().is_err(), "{}", same.display());
        }
        // Two outputs not yet written, spelled differently.
        let mut p = Paths::default();
        p.output("--out", &tmp.path().join("n.csv"))
            .output("--schedule", &sub.join("../n.csv"));
        let e = p.check().unwrap_err();
        assert!(e.contains("two outputs in one file"), "{e}");
        let mut p = Paths::default();
        p.input("in", &a)
            .output("--out", &tmp.path().join("b.csv"))
            .output("--gif", &sub.join("b.csv"));
        assert!(p.check().is_ok());
    }
}

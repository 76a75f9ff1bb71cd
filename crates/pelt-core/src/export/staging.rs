//! Output that is whole or absent: a failure part-way leaves the previous output (or nothing),
//! never a mix.
//!
//! A single file is written beside its target under a temporary name and renamed over it
//! ([`write_file`], [`save_to_path`]); a rename within one folder is atomic on the file systems
//! Pelt runs on. A folder of files is written into a temporary folder beside the target
//! ([`StagedFolder`]); when every file is there, each is renamed into place, after checking that
//! nothing in the target (a directory where a file should go) would stop a rename half-way. A
//! stage that is dropped without [`StagedFolder::commit`] removes itself.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{PeltError, Result};

/// Distinguishes the temporary names of concurrent writes in one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

fn io_error(path: &Path) -> impl Fn(std::io::Error) -> PeltError + '_ {
    move |source| PeltError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// A name beside `path` (same folder, so a rename stays on one file system) that no other write
/// of this or another process uses: `.<name>.<pid>-<n>.tmp`.
fn temporary_beside(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "pelt".into(), |n| n.to_string_lossy().into_owned());
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.{}-{n}.tmp", std::process::id()))
}

/// Creates `path` whole: `write` fills a temporary file beside it, which is flushed and renamed
/// over `path` only when everything succeeded (and removed otherwise). Every I/O failure becomes
/// [`PeltError::Io`] naming `path`.
pub(crate) fn save_to_path(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<()>,
) -> Result<()> {
    let io = io_error(path);
    if path.is_dir() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::IsADirectory,
            "a folder is in the way",
        )));
    }
    let temporary = temporary_beside(path);
    let result = (|| {
        let mut out = BufWriter::new(File::create(&temporary).map_err(&io)?);
        write(&mut out).map_err(|e| match e {
            PeltError::Io { source, .. } => io(source),
            other => other,
        })?;
        // Whole against a failing process, the concern here; no fsync, which would not be cheap.
        out.into_inner().map_err(|e| io(e.into_error()))?;
        std::fs::rename(&temporary, path).map_err(&io)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// Writes `bytes` to `path` whole (see [`save_to_path`]).
pub(crate) fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    save_to_path(path, |out| out.write_all(bytes).map_err(io_error(path)))
}

/// A temporary folder beside `target` that collects a set of files, then moves them into
/// `target` together ([`StagedFolder::commit`]).
#[derive(Debug)]
pub struct StagedFolder {
    target: PathBuf,
    stage: PathBuf,
    committed: bool,
}

impl StagedFolder {
    /// Creates the temporary folder beside `target` (and `target`'s parent when missing).
    ///
    /// # Errors
    /// [`PeltError::Io`] naming `target` when `target` is a file or the folder cannot be made.
    pub fn new(target: &Path) -> Result<Self> {
        let io = io_error(target);
        if target.exists() && !target.is_dir() {
            return Err(io(std::io::Error::new(
                std::io::ErrorKind::NotADirectory,
                "a file is in the way of the output folder",
            )));
        }
        let target = std::path::absolute(target).map_err(&io)?;
        if let Some(parent) = target.parent() {
            std::fs::create_dir_all(parent).map_err(&io)?;
        }
        let stage = temporary_beside(&target);
        std::fs::create_dir(&stage).map_err(&io)?;
        Ok(StagedFolder {
            target,
            stage,
            committed: false,
        })
    }

    /// The folder to write the files into.
    pub fn path(&self) -> &Path {
        &self.stage
    }

    /// Moves the files `names` (paths relative to [`Self::path`], all written there) into the
    /// target folder, replacing files of the same name and leaving others alone, then removes the
    /// stage. When the target did not exist the whole stage becomes it in one rename.
    ///
    /// # Errors
    /// [`PeltError::Io`] naming the first file that is missing from the stage or whose place in
    /// the target is taken by a folder; nothing has moved then.
    pub fn commit(mut self, names: &[String]) -> Result<()> {
        for name in names {
            let staged = self.stage.join(name);
            if !staged.is_file() {
                return Err(io_error(&staged)(std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    "was not written",
                )));
            }
            let destination = self.target.join(name);
            if destination.is_dir() {
                return Err(io_error(&destination)(std::io::Error::new(
                    std::io::ErrorKind::IsADirectory,
                    "a folder is in the way",
                )));
            }
        }
        if !self.target.exists() {
            std::fs::rename(&self.stage, &self.target).map_err(io_error(&self.target))?;
            self.committed = true;
            return Ok(());
        }
        for name in names {
            let destination = self.target.join(name);
            if let Some(parent) = destination.parent() {
                std::fs::create_dir_all(parent).map_err(io_error(parent))?;
            }
            std::fs::rename(self.stage.join(name), &destination).map_err(io_error(&destination))?;
        }
        Ok(())
    }
}

impl Drop for StagedFolder {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.stage);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("pelt-staging-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_failed_file_write_keeps_the_old_file_and_leaves_no_temporary() {
        let dir = scratch("file");
        let path = dir.join("a.bin");
        std::fs::write(&path, b"old").unwrap();
        let error = save_to_path(&path, |out| {
            out.write_all(b"half").unwrap();
            Err(PeltError::Internal("stopped".into()))
        });
        assert!(error.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(listing(&dir), ["a.bin"]);
        write_file(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        std::fs::create_dir(dir.join("b.bin")).unwrap();
        assert!(write_file(&dir.join("b.bin"), b"x").is_err());
        assert_eq!(listing(&dir), ["a.bin", "b.bin"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_folder_moves_in_whole_or_not_at_all() {
        let dir = scratch("folder");
        let target = dir.join("out");
        // New target: the stage becomes it.
        let stage = StagedFolder::new(&target).unwrap();
        std::fs::write(stage.path().join("x.txt"), b"1").unwrap();
        stage.commit(&["x.txt".into()]).unwrap();
        assert_eq!(listing(&target), ["x.txt"]);
        assert_eq!(listing(&dir), ["out"]);
        // A folder where a file should go: nothing moves, the old file stays, the stage is gone.
        std::fs::create_dir(target.join("y.txt")).unwrap();
        let stage = StagedFolder::new(&target).unwrap();
        std::fs::write(stage.path().join("x.txt"), b"2").unwrap();
        std::fs::write(stage.path().join("y.txt"), b"2").unwrap();
        assert!(stage.commit(&["x.txt".into(), "y.txt".into()]).is_err());
        assert_eq!(std::fs::read(target.join("x.txt")).unwrap(), b"1");
        assert_eq!(listing(&dir), ["out"]);
        // Existing target: files replaced by name, others kept.
        std::fs::remove_dir(target.join("y.txt")).unwrap();
        std::fs::write(target.join("mine.txt"), b"keep").unwrap();
        let stage = StagedFolder::new(&target).unwrap();
        std::fs::write(stage.path().join("x.txt"), b"3").unwrap();
        stage.commit(&["x.txt".into()]).unwrap();
        assert_eq!(std::fs::read(target.join("x.txt")).unwrap(), b"3");
        assert_eq!(listing(&target), ["mine.txt", "x.txt"]);
        assert_eq!(listing(&dir), ["out"]);
        // Dropped without commit: nothing left behind.
        drop(StagedFolder::new(&target).unwrap());
        assert_eq!(listing(&dir), ["out"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

//! Atomic file output: a file appears complete or not at all.
//!
//! Every output file of the project is written to a temporary file in the same directory,
//! `.{name}.tmp-{pid}-{n}`, flushed to disk, then renamed over the target. Renaming within one
//! directory is atomic on POSIX file systems (and replaces the target on Windows), so readers
//! never see a half-written image or mesh, and a failed write leaves the target untouched and
//! no temporary file behind.
//!
//! A job with several outputs (an image, an export, the statistics) uses a [`Batch`]: each
//! output is written in full to its own temporary file first, and only when every one of them
//! is written are they renamed onto their targets, one after the other. A failure before that
//! point (a full disk, an exporter's error, Ctrl-C) leaves every target as it was.

use std::fs::{self, File};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes temporary files of concurrent writes within one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `path` atomically: `write` fills a temporary file next to it, which is then renamed
/// to `path`.
///
/// # Errors
/// The first I/O error of creating, writing, flushing or renaming the temporary file, or the
/// error returned by `write`; the temporary file is then removed and `path` is untouched.
/// A path without a file name is an [`io::ErrorKind::InvalidInput`] error.
pub fn write_atomic(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    let tmp = temporary_path(path)?;
    let result = write_then_rename(&tmp, path, write);
    if result.is_err() {
        // Best effort: the temporary file may not exist if creating it failed.
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// The temporary file for `path`: `.{name}.tmp-{pid}-{n}` in the same directory.
fn temporary_path(path: &Path) -> io::Result<PathBuf> {
    let name = file_part(path, path.file_name())?;
    Ok(path.with_file_name(format!(".{name}.{}", unique())))
}

/// `part` of `path` as text, or an [`io::ErrorKind::InvalidInput`] error naming `path` when it
/// has none (a path without a file name).
fn file_part(path: &Path, part: Option<&std::ffi::OsStr>) -> io::Result<String> {
    let part = part.ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} is not a file path", path.display()),
        )
    })?;
    Ok(part.to_string_lossy().into_owned())
}

/// `tmp-{pid}-{n}`, different for every call in this process and from other processes'.
fn unique() -> String {
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    format!("tmp-{}-{n}", std::process::id())
}

fn write_then_rename(
    tmp: &Path,
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    let mut out = BufWriter::new(File::create(tmp)?);
    write(&mut out)?;
    let file = out.into_inner().map_err(io::IntoInnerError::into_error)?;
    file.sync_all()?;
    drop(file);
    fs::rename(tmp, path)
}

/// Outputs that appear together or not at all: see the module documentation.
///
/// [`Batch::stage`] names a temporary file for a target; the caller writes it (with any
/// writer, atomic or not); [`Batch::commit`] renames every staged file onto its target. A batch
/// dropped without a commit removes its temporary files.
#[derive(Debug, Default)]
pub struct Batch {
    /// (temporary file, target) in the order staged.
    staged: Vec<(PathBuf, PathBuf)>,
}

impl Batch {
    /// An empty batch.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The temporary file to write `path`'s content to: `.{stem}.tmp-{pid}-{n}.{extension}` in
    /// the same directory, keeping the extension for writers that choose a format by it.
    ///
    /// # Errors
    /// A path without a file name ([`io::ErrorKind::InvalidInput`]).
    pub fn stage(&mut self, path: &Path) -> io::Result<PathBuf> {
        let stem = file_part(path, path.file_stem())?;
        let mut name = format!(".{stem}.{}", unique());
        if let Some(extension) = path.extension() {
            name = format!("{name}.{}", extension.to_string_lossy());
        }
        let tmp = path.with_file_name(name);
        self.staged.push((tmp.clone(), path.to_path_buf()));
        Ok(tmp)
    }

    /// Renames every staged file onto its target, in the order staged; returns the targets.
    ///
    /// # Errors
    /// The first rename that fails (a staged file that was never written, say); the files
    /// not yet renamed are then removed. Renames within a directory do not fail in practice
    /// once the files are written, so the targets change together.
    pub fn commit(mut self) -> io::Result<Vec<PathBuf>> {
        let staged = std::mem::take(&mut self.staged);
        let mut done = Vec::with_capacity(staged.len());
        let mut rest = staged.into_iter();
        for (tmp, path) in rest.by_ref() {
            if let Err(e) = fs::rename(&tmp, &path) {
                self.staged = rest.collect();
                let _ = fs::remove_file(&tmp);
                return Err(io::Error::new(
                    e.kind(),
                    format!("{}: cannot write: {e}", path.display()),
                ));
            }
            done.push(path);
        }
        Ok(done)
    }
}

impl Drop for Batch {
    fn drop(&mut self) {
        for (tmp, _) in &self.staged {
            // Best effort: a staged file may not have been written.
            let _ = fs::remove_file(tmp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch_dir(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("radiosity-atomic-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).expect("create scratch dir");
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .expect("read dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn writes_the_whole_file_and_nothing_else() {
        let dir = scratch_dir("ok");
        let path = dir.join("out.txt");
        write_atomic(&path, |w| w.write_all(b"hello")).expect("write");
        assert_eq!(fs::read(&path).expect("read"), b"hello");
        assert_eq!(entries(&dir), vec!["out.txt"]);
        fs::remove_dir_all(&dir).expect("cleanup");
    }

    #[test]
    fn failure_leaves_target_untouched_and_no_temporary() {
        let dir = scratch_dir("err");
        let fresh = dir.join("fresh.txt");
        let err = write_atomic(&fresh, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        })
        .expect_err("must fail");
        assert_eq!(err.to_string(), "boom");
        assert!(entries(&dir).is_empty(), "{:?}", entries(&dir));

        let existing = dir.join("existing.txt");
        fs::write(&existing, b"old").expect("seed");
        assert!(write_atomic(&existing, |_| Err(io::Error::other("boom"))).is_err());
        assert_eq!(fs::read(&existing).expect("read"), b"old");
        assert_eq!(entries(&dir), vec!["existing.txt"]);
        fs::remove_dir_all(&dir).expect("cleanup");
    }

    #[test]
    fn a_batch_lands_whole_on_commit_and_leaves_nothing_when_dropped() {
        let dir = scratch_dir("batch");
        let (image, stats) = (dir.join("out.png"), dir.join("stats.json"));
        fs::write(&image, b"old image").expect("seed");

        let mut batch = Batch::new();
        let tmp = batch.stage(&image).expect("stage");
        assert_eq!(tmp.extension().and_then(|e| e.to_str()), Some("png"));
        fs::write(&tmp, b"new image").expect("write");
        let tmp = batch.stage(&stats).expect("stage");
        fs::write(&tmp, b"{}").expect("write");
        // A failure after some outputs are written: nothing lands, no temporary stays.
        drop(batch);
        assert_eq!(fs::read(&image).expect("read"), b"old image");
        assert_eq!(entries(&dir), vec!["out.png"]);

        let mut batch = Batch::new();
        for (path, text) in [(&image, b"new image".as_slice()), (&stats, b"{}")] {
            let tmp = batch.stage(path).expect("stage");
            write_atomic(&tmp, |w| w.write_all(text)).expect("write");
        }
        assert_eq!(batch.commit().expect("commit"), vec![image.clone(), stats]);
        assert_eq!(fs::read(&image).expect("read"), b"new image");
        assert_eq!(entries(&dir), vec!["out.png", "stats.json"]);

        // A staged file never written: the commit fails and removes what is left.
        let mut batch = Batch::new();
        let _ = batch.stage(&dir.join("never.ply")).expect("stage");
        assert!(batch.commit().is_err());
        assert_eq!(entries(&dir), vec!["out.png", "stats.json"]);
        fs::remove_dir_all(&dir).expect("cleanup");
    }

    #[test]
    fn missing_directory_and_bad_path_are_errors() {
        let dir = scratch_dir("missing");
        assert!(write_atomic(&dir.join("no/such/dir/x.txt"), |_| Ok(())).is_err());
        assert_eq!(
            write_atomic(Path::new("/"), |_| Ok(())).map_err(|e| e.kind()),
            Err(io::ErrorKind::InvalidInput)
        );
        fs::remove_dir_all(&dir).expect("cleanup");
    }
}

//! Atomic file output: a file appears complete or not at all.
//!
//! Every output file of the project is written to a temporary file in the same directory,
//! `.{name}.tmp-{pid}-{n}`, flushed to disk, then renamed over the target. Renaming within one
//! directory is atomic on POSIX file systems (and replaces the target on Windows), so readers
//! never see a half-written image or mesh, and a failed write leaves the target untouched and
//! no temporary file behind.

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
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} is not a file path", path.display()),
        )
    })?;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp_name = format!(".{}.tmp-{}-{n}", name.to_string_lossy(), std::process::id());
    Ok(path.with_file_name(tmp_name))
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

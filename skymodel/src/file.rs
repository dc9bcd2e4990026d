//! Writing a file so that no output is lost silently: [`write_file`] is
//! the one way the renderers and the command line write files (images,
//! `--stats`, the LUT cache).
//!
//! A regular target (or a new one) is written to a temporary file in the
//! target's directory, flushed, synced and only then renamed onto the
//! target; a failed write removes the temporary and leaves the target as it
//! was (no half-written file under the target name). A symbolic link is
//! followed: the file it points to is replaced and the link stays. A target
//! that is not a regular file (a device such as `/dev/full`, a FIFO) cannot
//! be replaced by a rename: it is written directly, with the same
//! flush-and-check discipline, so that e.g. `/dev/full` reports "No space
//! left on device".

use std::fmt;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

/// A failed write, naming the file (as the caller gave it).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WriteError {
    /// The target file.
    pub path: PathBuf,
    /// What failed and why, e.g. "cannot write: No space left on device (os error 28)".
    pub message: String,
}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for WriteError {}

/// Symbolic links followed at most (as the kernel's `ELOOP` limit).
const MAX_LINKS: usize = 40;

/// Writes `path` with `write`, which gets a buffered writer on the file;
/// see the module documentation. Every error (the closure's, the flush,
/// the sync, the rename) is returned, naming `path`.
pub fn write_file<E: fmt::Display>(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), E>,
) -> Result<(), WriteError> {
    let fail = |message: String| WriteError {
        path: path.to_path_buf(),
        message,
    };
    let target = follow_links(path);
    match fs::metadata(&target) {
        Ok(m) if m.is_dir() => Err(fail("is a directory".into())),
        Ok(m) if !m.is_file() => write_in_place(&target, write).map_err(fail),
        Ok(m) => write_replacing(&target, Some(m.permissions()), write).map_err(fail),
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            write_replacing(&target, None, write).map_err(fail)
        }
        Err(e) => Err(fail(format!("cannot access: {e}"))),
    }
}

/// [`write_file`] of a byte string.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    write_file(path, |w| w.write_all(bytes))
}

/// `path` with its symbolic links resolved one by one (a dangling link
/// resolves to the path it names, so the file is created there).
fn follow_links(path: &Path) -> PathBuf {
    let mut p = path.to_path_buf();
    for _ in 0..MAX_LINKS {
        let is_link = fs::symlink_metadata(&p).is_ok_and(|m| m.file_type().is_symlink());
        if !is_link {
            break;
        }
        match fs::read_link(&p) {
            Ok(to) => p = p.parent().unwrap_or(Path::new("")).join(to),
            Err(_) => break,
        }
    }
    p
}

/// Removes the temporary file unless the write succeeded.
struct TempGuard(Option<PathBuf>);

impl Drop for TempGuard {
    fn drop(&mut self) {
        if let Some(p) = self.0.take() {
            let _ = fs::remove_file(p);
        }
    }
}

static COUNTER: AtomicU32 = AtomicU32::new(0);

/// Creates a new temporary file next to `target`.
fn create_temp(target: &Path) -> Result<(File, PathBuf), String> {
    let name = target
        .file_name()
        .ok_or_else(|| "not a file name".to_string())?
        .to_string_lossy();
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut last = None;
    for _ in 0..100 {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let tmp = dir.join(format!(".{name}.{}.{n}.tmp", std::process::id()));
        match OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(f) => return Ok((f, tmp)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => {
                return Err(format!(
                    "cannot create a temporary file in {}: {e}",
                    dir.display()
                ))
            }
        }
    }
    Err(format!(
        "cannot create a temporary file in {}: {}",
        dir.display(),
        last.map_or_else(String::new, |e| e.to_string())
    ))
}

/// Temporary file, flush, sync, rename onto `target`, sync the directory.
fn write_replacing<E: fmt::Display>(
    target: &Path,
    permissions: Option<fs::Permissions>,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), E>,
) -> Result<(), String> {
    let (file, tmp) = create_temp(target)?;
    let mut guard = TempGuard(Some(tmp.clone()));
    if let Some(p) = permissions {
        file.set_permissions(p)
            .map_err(|e| format!("cannot set the permissions: {e}"))?;
    }
    let mut w = BufWriter::new(file);
    write(&mut w).map_err(|e| format!("cannot write: {e}"))?;
    let file = w
        .into_inner()
        .map_err(|e| format!("cannot write: {}", e.error()))?;
    file.sync_all()
        .map_err(|e| format!("cannot write (sync): {e}"))?;
    drop(file);
    fs::rename(&tmp, target).map_err(|e| format!("cannot rename the temporary file: {e}"))?;
    guard.0 = None;
    // The rename is durable once the directory is synced; a file system
    // that cannot sync a directory (EINVAL) still holds the file.
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if let Ok(d) = File::open(dir) {
        match d.sync_all() {
            Err(e) if !sync_unsupported(&e) => {
                return Err(format!("cannot sync the directory: {e}"))
            }
            _ => {}
        }
    }
    Ok(())
}

/// A device or FIFO: written directly, flushed and checked.
fn write_in_place<E: fmt::Display>(
    target: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> Result<(), E>,
) -> Result<(), String> {
    let file = OpenOptions::new()
        .write(true)
        .truncate(true)
        .open(target)
        .map_err(|e| format!("cannot open: {e}"))?;
    let mut w = BufWriter::new(file);
    write(&mut w).map_err(|e| format!("cannot write: {e}"))?;
    let file = w
        .into_inner()
        .map_err(|e| format!("cannot write: {}", e.error()))?;
    match file.sync_all() {
        Err(e) if !sync_unsupported(&e) => Err(format!("cannot write (sync): {e}")),
        _ => Ok(()),
    }
}

/// Whether a failed sync only says the file cannot be synced (a device,
/// a pipe, some file systems' directories): EINVAL or "unsupported".
fn sync_unsupported(e: &io::Error) -> bool {
    matches!(
        e.kind(),
        io::ErrorKind::InvalidInput | io::ErrorKind::Unsupported
    ) || e.raw_os_error() == Some(22)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!(
            "himmel-file-{}-{name}-{}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn writes_and_replaces_leaving_no_temporary() {
        let d = scratch("ok");
        let p = d.join("a.txt");
        write_bytes(&p, b"one").unwrap();
        write_bytes(&p, b"two").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"two");
        assert_eq!(names(&d), ["a.txt"]);
        fs::remove_dir_all(d).unwrap();
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_and_removes_the_temporary() {
        let d = scratch("fail");
        let p = d.join("a.txt");
        write_bytes(&p, b"old").unwrap();
        let e = write_file(&p, |w| {
            w.write_all(&[7u8; 100_000])?;
            Err(io::Error::other("disk on fire"))
        })
        .unwrap_err();
        assert!(e.to_string().contains("a.txt") && e.to_string().contains("disk on fire"));
        assert_eq!(fs::read(&p).unwrap(), b"old");
        assert_eq!(names(&d), ["a.txt"]);
        // Also when the writer panics.
        let r = std::panic::catch_unwind(|| {
            let _ = write_file(&d.join("b.txt"), |_| -> io::Result<()> { panic!("boom") });
        });
        assert!(r.is_err());
        assert_eq!(names(&d), ["a.txt"]);
        fs::remove_dir_all(d).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn links_are_followed_and_devices_written_in_place() {
        let d = scratch("link");
        let real = d.join("real.txt");
        write_bytes(&real, b"old").unwrap();
        let link = d.join("link.txt");
        std::os::unix::fs::symlink("real.txt", &link).unwrap();
        write_bytes(&link, b"new").unwrap();
        assert!(fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(fs::read(&real).unwrap(), b"new");
        if Path::new("/dev/full").exists() {
            let full = d.join("full.txt");
            std::os::unix::fs::symlink("/dev/full", &full).unwrap();
            for p in [Path::new("/dev/full"), &full] {
                let e = write_bytes(p, b"x").unwrap_err();
                assert_eq!(e.path, p);
                assert!(e.message.contains("No space left"), "{e}");
            }
        }
        assert_eq!(
            names(&d),
            ["full.txt", "link.txt", "real.txt"]
                .into_iter()
                .filter(|n| *n != "full.txt" || Path::new("/dev/full").exists())
                .collect::<Vec<_>>()
        );
        let e = write_bytes(&d, b"x").unwrap_err();
        assert!(e.message.contains("directory"), "{e}");
        let e = write_bytes(&d.join("missing/a.txt"), b"x").unwrap_err();
        assert!(e.message.contains("temporary"), "{e}");
        fs::remove_dir_all(d).unwrap();
    }
}

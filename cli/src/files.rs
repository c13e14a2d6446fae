//! Output files that are never left half-written.
//!
//! Every regular file `lgsvi` writes goes first to a temporary file in the destination's
//! directory (so the final rename stays on one file system), is flushed and synced, and
//! only then renamed over the destination. A full disk, an error or an interrupt leaves the
//! previous file (if any) intact and no temporary file behind (it is removed on every
//! error), never a truncated result under the real name.
//!
//! A symbolic link at the destination is written through: the temporary file goes beside
//! the link's target and is renamed onto it, so the link stays a link and its target is
//! the new file. A destination that exists and is not a regular file (a FIFO, a terminal,
//! `/dev/null`) is written directly, as a shell redirection would: renaming over it would
//! replace it and its reader would get nothing.

use crate::error::{CliError, Result};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Where a write to `path` lands: through symbolic links (at most 40, as the kernel
/// allows) to the file they name.
fn resolve(path: &Path) -> PathBuf {
    let mut current = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => match std::fs::read_link(&current) {
                Ok(target) => {
                    current = match current.parent() {
                        Some(dir) if target.is_relative() => dir.join(target),
                        _ => target,
                    };
                }
                Err(_) => return current,
            },
            _ => return current,
        }
    }
    current
}

/// The error of a write to `path` (as the user gave it) that failed for `source`.
fn failed(path: &Path) -> impl Fn(std::io::Error) -> CliError + Copy + '_ {
    move |source| CliError::Write {
        path: path.to_path_buf(),
        source,
    }
}

/// Whether `path` (resolved) exists and is not a regular file: written directly.
fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|meta| !meta.is_file() && !meta.is_dir())
}

/// A temporary file beside `target` (already resolved through links) for a write to
/// `shown` (the path as the user gave it): a hidden name that keeps the destination's, so
/// plotters picks the image format from its extension; removed when dropped.
fn temporary(target: &Path, shown: &Path) -> Result<tempfile::NamedTempFile> {
    let name = target.file_name().map(|n| n.to_string_lossy().into_owned());
    let dir = match target.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    // The mode File::create gives (0666 less the umask), not a temporary file's 0600: the
    // output is renamed into place, and others may need to read it.
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
    let suffix = format!("-{}", name.as_deref().unwrap_or("output"));
    let created = builder.prefix(".partial-").suffix(&suffix).tempfile_in(dir);
    created.map_err(|e| {
        // The system's reason, without the temporary file's random name.
        let text = e.to_string();
        let reason = text
            .rsplit_once(" at path ")
            .map_or(text.as_str(), |(r, _)| r);
        let dir = dir.display();
        let message = format!(
            "cannot create a file in {dir} to write it and rename it into place ({reason}); \
             write elsewhere"
        );
        failed(shown)(std::io::Error::new(e.kind(), message))
    })
}

/// A temporary file beside a destination, to be written by path (a figure), removed when
/// dropped unless [`Partial::commit`] renamed it onto the destination.
pub struct Partial {
    path: tempfile::TempPath,
    target: PathBuf,
}

impl Partial {
    /// The temporary file for a write to `path` (through links).
    ///
    /// # Errors
    /// [`CliError::Write`] naming `path` when no file can be created beside it.
    pub fn new(path: &Path) -> Result<Self> {
        let target = resolve(path);
        let path = temporary(&target, path)?.into_temp_path();
        Ok(Self { path, target })
    }

    /// The temporary file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Renames the finished temporary file onto the destination.
    ///
    /// # Errors
    /// [`CliError::Write`] naming `shown` (the path as the user gave it).
    pub fn commit(self, shown: &Path) -> Result<()> {
        self.path
            .persist(&self.target)
            .map_err(|e| failed(shown)(e.error))
    }
}

/// Writes `path` atomically through `write`, buffered (directly where `path` is not a
/// regular file).
///
/// # Errors
/// A one-line message naming `path` if the temporary file cannot be created, written,
/// synced or renamed; the temporary file is removed then.
pub fn write_with(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<()> {
    let failed = failed(path);
    let target = resolve(path);
    if is_special(&target) {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(&target)
            .map_err(failed)?;
        let mut out = BufWriter::new(file);
        return write(&mut out).and_then(|()| out.flush()).map_err(failed);
    }
    let partial = temporary(&target, path)?;
    // Written through its own handle (no second open by name).
    let mut out = BufWriter::new(partial.as_file().try_clone().map_err(failed)?);
    write(&mut out)
        .and_then(|()| out.into_inner().map_err(|e| e.into_error()))
        .and_then(|file| file.sync_all())
        .map_err(failed)?;
    partial
        .persist(&target)
        .map(|_| ())
        .map_err(|e| failed(e.error))
}

/// Writes `contents` to `path` atomically.
///
/// # Errors
/// As [`write_with`].
pub fn write(path: &Path, contents: &[u8]) -> Result<()> {
    write_with(path, |out| out.write_all(contents))
}

/// Refuses a run whose outputs would land on one file twice (`--out p.svg --plot p`
/// writes `p.svg` from both): the later write would replace the earlier, and the run
/// would exit 0 with an output lost. `outputs` are `(flag, path)` pairs; paths are
/// compared through links, relative to the working directory.
///
/// # Errors
/// [`CliError::Collision`] naming both flags and the file.
pub fn check_distinct(outputs: &[(&'static str, PathBuf)]) -> Result<()> {
    let keys: Vec<PathBuf> = outputs
        .iter()
        .map(|(_, p)| std::path::absolute(resolve(p)).unwrap_or_else(|_| p.clone()))
        .collect();
    for (i, (first, a)) in outputs.iter().enumerate() {
        for (j, (second, _)) in outputs.iter().enumerate().skip(i + 1) {
            if keys[i] == keys[j] {
                return Err(CliError::Collision {
                    first,
                    second,
                    path: a.clone(),
                });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_keeps_the_old_file_and_leaves_no_partial() {
        let dir = std::env::temp_dir().join(format!("lgsvi-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("out.json");
        write(&path, b"{\"old\": 1}\n").unwrap();
        let failed = write_with(&path, |out| {
            out.write_all(b"{\"new\": ")?;
            Err(std::io::Error::other("disk full"))
        });
        let message = failed.unwrap_err().to_string();
        assert!(
            message.contains("out.json") && message.contains("disk full"),
            "{message}"
        );
        assert_eq!(std::fs::read(&path).unwrap(), b"{\"old\": 1}\n");
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().starts_with(".partial"))
            .collect();
        assert!(leftovers.is_empty());
        write(&path, b"new\n").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new\n");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("lgsvi-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A link at the destination stays a link, and its target is the new file.
    #[cfg(unix)]
    #[test]
    fn a_link_is_written_through() {
        let dir = scratch("link");
        std::fs::create_dir(dir.join("sub")).unwrap();
        std::fs::write(dir.join("sub/real.json"), b"old").unwrap();
        std::os::unix::fs::symlink("sub/real.json", dir.join("link.json")).unwrap();
        write(&dir.join("link.json"), b"new").unwrap();
        let meta = std::fs::symlink_metadata(dir.join("link.json")).unwrap();
        assert!(meta.file_type().is_symlink());
        assert_eq!(std::fs::read(dir.join("sub/real.json")).unwrap(), b"new");
        // A dangling link: the file it names is created.
        std::os::unix::fs::symlink("sub/new.json", dir.join("dangling.json")).unwrap();
        write(&dir.join("dangling.json"), b"made").unwrap();
        assert_eq!(std::fs::read(dir.join("sub/new.json")).unwrap(), b"made");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A destination that is not a regular file is written directly: a FIFO stays a FIFO
    /// and its reader gets the whole output (renaming over it would have replaced it, and
    /// the reader would have got nothing).
    #[cfg(unix)]
    #[test]
    fn a_fifo_is_written_directly() {
        use std::io::Read;
        use std::os::unix::fs::FileTypeExt;
        let dir = scratch("fifo");
        let fifo = dir.join("out.json");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .expect("mkfifo runs");
        assert!(made.success());
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || {
                let mut text = String::new();
                File::open(&fifo)
                    .unwrap()
                    .read_to_string(&mut text)
                    .unwrap();
                text
            })
        };
        write(&fifo, b"{\"through\": \"the pipe\"}").unwrap();
        assert_eq!(reader.join().unwrap(), "{\"through\": \"the pipe\"}");
        let meta = std::fs::symlink_metadata(&fifo).unwrap();
        assert!(meta.file_type().is_fifo(), "the FIFO was replaced");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// An output gets the mode a created file gets (0666 less the umask), not a temporary
    /// file's 0600.
    #[cfg(unix)]
    #[test]
    fn an_output_is_as_readable_as_a_created_file() {
        use std::os::unix::fs::PermissionsExt;
        let dir = scratch("mode");
        std::fs::write(dir.join("plain"), b"").unwrap();
        write(&dir.join("out.json"), b"{}").unwrap();
        let mode = |name: &str| {
            std::fs::metadata(dir.join(name))
                .unwrap()
                .permissions()
                .mode()
        };
        assert_eq!(mode("out.json") & 0o777, mode("plain") & 0o777);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A temporary file that is not committed is removed (a plot failing half-drawn).
    #[test]
    fn an_uncommitted_partial_is_removed() {
        let dir = scratch("partial");
        let partial = Partial::new(&dir.join("fig.svg")).unwrap();
        std::fs::write(partial.path(), b"<svg").unwrap();
        let path = partial.path().to_path_buf();
        assert!(path.exists());
        drop(partial);
        assert!(!path.exists());
        let partial = Partial::new(&dir.join("fig.svg")).unwrap();
        std::fs::write(partial.path(), b"<svg/>").unwrap();
        partial.commit(&dir.join("fig.svg")).unwrap();
        assert_eq!(std::fs::read(dir.join("fig.svg")).unwrap(), b"<svg/>");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn outputs_on_one_file_are_refused() {
        let outputs = [
            ("--out", PathBuf::from("p.svg")),
            ("--plot", PathBuf::from("./p.svg")),
        ];
        let error = check_distinct(&outputs).unwrap_err().to_string();
        assert!(
            error.contains("--out and --plot would both write"),
            "{error}"
        );
        assert!(check_distinct(&[
            ("--out", PathBuf::from("p.json")),
            ("--plot", PathBuf::from("p.svg")),
        ])
        .is_ok());
    }
}

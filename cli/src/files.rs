//! Output files that are never left half-written.
//!
//! Every file `lgsvi` writes goes first to a temporary file in the same directory (so the
//! final rename stays on one file system), is flushed and synced, and only then renamed
//! over the destination. A full disk, an error or an interrupt leaves the previous file
//! (if any) intact and at worst a `.partial-…` file beside it, never a truncated result
//! under the real name.

use crate::error::{CliError, Result};
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// The temporary path beside `path` that [`commit`] renames over it: a hidden name that
/// keeps the extension (plotters picks the image format from it).
pub fn partial_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "output".into());
    path.with_file_name(format!(".partial-{}-{name}", std::process::id()))
}

/// Renames the finished `partial` over `path` (or removes it and reports the error).
pub fn commit(partial: &Path, path: &Path) -> Result<()> {
    std::fs::rename(partial, path).map_err(|source| {
        let _ = std::fs::remove_file(partial);
        CliError::Write {
            path: path.to_path_buf(),
            source,
        }
    })
}

/// Writes `path` atomically through `write`, buffered.
///
/// # Errors
/// A one-line message naming `path` if the temporary file cannot be created, written,
/// synced or renamed; the temporary file is removed then.
pub fn write_with(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<()> {
    let partial = partial_path(path);
    let result = (|| {
        let mut out = BufWriter::new(File::create(&partial)?);
        write(&mut out)?;
        let file = out.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()
    })();
    match result {
        Ok(()) => commit(&partial, path),
        Err(source) => {
            let _ = std::fs::remove_file(&partial);
            Err(CliError::Write {
                path: path.to_path_buf(),
                source,
            })
        }
    }
}

/// Writes `contents` to `path` atomically.
///
/// # Errors
/// As [`write_with`].
pub fn write(path: &Path, contents: &[u8]) -> Result<()> {
    write_with(path, |out| out.write_all(contents))
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
}

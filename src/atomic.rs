//! Files written whole or not at all: each output goes to a temporary file in its folder
//! and is renamed over the path, so an interrupted or failed write never leaves half a
//! file or clobbers the previous one.

use std::path::Path;

use anyhow::{Context, Result};

/// Runs `write` on a temporary path in `path`'s folder, then renames it to `path`; on an
/// error the temporary file is removed and `path` is untouched.
pub fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let name = path
        .file_name()
        .with_context(|| format!("{}: not a file name", path.display()))?;
    let mut temporary = std::ffi::OsString::from(".");
    temporary.push(name);
    temporary.push(format!(".{}.tmp", std::process::id()));
    let temporary = path.with_file_name(temporary);
    let written = write(&temporary).and_then(|()| Ok(std::fs::rename(&temporary, path)?));
    if written.is_err() {
        // Best effort: the temporary may not exist, and the write error is what matters.
        let _ = std::fs::remove_file(&temporary);
    }
    written.with_context(|| format!("cannot write {}", path.display()))
}

/// [`write_atomically`] of a byte string.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomically(path, |temporary| Ok(std::fs::write(temporary, bytes)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_leaves_the_old_file_byte_identical() {
        let dir = std::env::temp_dir().join(format!("argil-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("frame.exr");
        write_bytes(&path, b"the previous frame").unwrap();
        let failed = write_atomically(&path, |temporary| {
            std::fs::write(temporary, b"half a fr")?;
            anyhow::bail!("the disk is full")
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"the previous frame");
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "the temporary file is removed"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }
}

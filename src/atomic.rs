//! Files written whole or not at all: each output goes to a temporary file in its folder,
//! is flushed to the disk and renamed over the path, so an interrupted or failed write
//! (kill -9, a full disk, a crash) never leaves half a file or clobbers the previous one.
//! A process killed mid-write can leave its temporary, `.NAME.PID.tmp`, beside the output.
//! Before a command starts, its outputs are checked ([`check_outputs`]): one that already
//! exists is refused unless the command was given `--overwrite`, and one it could not write
//! (a missing or unwritable folder) is refused too, rather than after hours of work. One
//! that appears at its path while the command runs is not replaced ([`Existing::Refuse`]).

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, ErrorKind, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use anyhow::Result;

use crate::error::InputError;
use crate::fault::{Faults, VARIABLE};

/// Refuses the first of `outputs` that already exists, unless `overwrite` (a file at an
/// output's path may be the user's own work, so replacing it must be asked for), that is a
/// folder, or that its folder would not take: missing, not a folder, or refusing the
/// temporary file a write begins with, which is made and removed here to find out.
pub fn check_outputs<'a>(outputs: impl IntoIterator<Item = &'a Path>, overwrite: bool) -> Result<(), InputError> {
    for path in outputs {
        if path.is_dir() {
            return Err(InputError::file(path, "is a folder, not a file"));
        }
        if !overwrite && path.exists() {
            return Err(InputError::file(path, "already exists; pass --overwrite to replace it"));
        }
        let folder = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        if !folder.is_dir() {
            let problem = if folder.exists() { "is not a folder" } else { "does not exist" };
            return Err(InputError::file(path, format!("its folder {} {problem}", folder.display())));
        }
        let probe = temporary(path)?;
        match OpenOptions::new().write(true).create_new(true).open(&probe) {
            Ok(file) => {
                drop(file);
                // Best effort: a leftover empty temporary is only clutter.
                let _ = std::fs::remove_file(&probe);
            }
            // Another run's, killed mid-write: a write replaces it.
            Err(e) if e.kind() == ErrorKind::AlreadyExists => {}
            Err(e) => {
                return Err(InputError::file(path, format!("cannot be written in {}: {e}", folder.display())));
            }
        }
    }
    Ok(())
}

/// The temporary file a write of `path` goes to first: `.NAME.PID.tmp` beside it.
fn temporary(path: &Path) -> Result<PathBuf, InputError> {
    let name = path.file_name().ok_or_else(|| InputError::file(path, "not a file name"))?;
    let mut temporary = std::ffi::OsString::from(".");
    temporary.push(name);
    temporary.push(format!(".{}.tmp", std::process::id()));
    Ok(path.with_file_name(temporary))
}

/// What writing an output does with a file already at its path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Existing {
    /// Replaces it: argil's own files (caches, bench results), outputs under `--overwrite`,
    /// and a scene saved where the user chose.
    Replace,
    /// Leaves it as it is and fails with an [`InputError`] naming it: an output the command
    /// line did not allow to replace a file, which another program created meanwhile.
    Refuse,
}

impl Existing {
    /// What `--overwrite` (or its absence) asks of a command's outputs.
    pub fn from_overwrite(overwrite: bool) -> Self {
        if overwrite {
            Existing::Replace
        } else {
            Existing::Refuse
        }
    }
}

/// The temporary file an output is written to: buffered, seekable (PNG and EXR encoders
/// need it), and failing after its first N bytes under `ARGIL_FAULT=write:N`.
pub struct Sink {
    file: BufWriter<File>,
    /// Bytes that may still be written, when a fault is injected.
    budget: Option<u64>,
}

impl Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let Some(budget) = self.budget else {
            return self.file.write(buf);
        };
        if budget == 0 {
            return Err(std::io::Error::other(format!(
                "no space left on device (injected by {VARIABLE})"
            )));
        }
        let n = self.file.write(&buf[..buf.len().min(budget as usize)])?;
        self.budget = Some(budget - n as u64);
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.file.flush()
    }
}

impl Seek for Sink {
    fn seek(&mut self, position: SeekFrom) -> std::io::Result<u64> {
        self.file.seek(position)
    }
}

/// Runs `write` on a temporary file in `path`'s folder, then moves it to `path` as
/// `existing` says; on an error the temporary file is removed and `path` is untouched, but
/// for a file found at `path` under [`Existing::Refuse`], where the finished output stays in
/// the temporary file that the error names.
pub fn write_atomically(path: &Path, existing: Existing, write: impl FnOnce(&mut Sink) -> Result<()>) -> Result<()> {
    let budget = Faults::from_env()?.write;
    let temporary = temporary(path)?;
    let written = (|| -> Result<bool> {
        let mut sink = Sink {
            file: BufWriter::new(File::create(&temporary)?),
            budget,
        };
        write(&mut sink)?;
        let file = sink.file.into_inner().map_err(|e| e.into_error())?;
        // On the disk before the rename: after a crash the name holds the old file or the
        // new one, never an empty one.
        file.sync_all()?;
        Ok(place(&temporary, path, existing)?)
    })();
    match written {
        Ok(true) => Ok(()),
        Ok(false) => Err(InputError::file(
            path,
            format!(
                "appeared while argil ran and is left as it is (--overwrite replaces it); argil's output is in {}",
                temporary.display()
            ),
        )
        .into()),
        Err(e) => {
            // Best effort: the temporary may not exist, and the write error is what matters.
            let _ = std::fs::remove_file(&temporary);
            Err(e.context(format!("cannot write {}", path.display())))
        }
    }
}

/// Moves the finished `temporary` to `path`, or leaves both as they are and returns false
/// where `existing` refuses a file found at `path`. Under [`Existing::Refuse`] a hard link
/// makes the new name, which fails rather than replace a file, with no moment between a
/// check and the move; on a file system without hard links, the check and then the move.
fn place(temporary: &Path, path: &Path, existing: Existing) -> std::io::Result<bool> {
    if existing == Existing::Replace {
        return std::fs::rename(temporary, path).map(|()| true);
    }
    match std::fs::hard_link(temporary, path) {
        Ok(()) => {
            // Best effort: the output is in place, and a leftover temporary is only clutter.
            let _ = std::fs::remove_file(temporary);
            Ok(true)
        }
        Err(e) if e.kind() == ErrorKind::AlreadyExists => Ok(false),
        Err(_) if path.symlink_metadata().is_ok() => Ok(false),
        Err(_) => std::fs::rename(temporary, path).map(|()| true),
    }
}

/// [`write_atomically`] of a byte string.
pub fn write_bytes(path: &Path, existing: Existing, bytes: &[u8]) -> Result<()> {
    write_atomically(path, existing, |sink| Ok(sink.write_all(bytes)?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scratch::Scratch;

    /// A PNG encoder stopped half-way by a sink that fails after 100 bytes.
    #[test]
    fn a_write_failing_half_way_leaves_the_old_file_byte_identical() {
        let dir = Scratch::new("atomic").unwrap();
        let path = dir.join("frame.png");
        write_bytes(&path, Existing::Replace, b"the previous frame").unwrap();
        let image = image::RgbaImage::from_fn(64, 64, |x, y| image::Rgba([x as u8 * 4, y as u8 * 4, 7, 255]));
        let mut reached = 0;
        let failed = write_atomically(&path, Existing::Replace, |sink| {
            sink.budget = Some(100);
            let result = image.write_to(sink, image::ImageFormat::Png);
            reached = 100 - sink.budget.unwrap_or(0);
            Ok(result?)
        });
        let error = format!("{:#}", failed.unwrap_err());
        assert!(
            error.contains("frame.png") && error.contains("no space left"),
            "{error}"
        );
        assert_eq!(reached, 100, "the encoder wrote up to the fault");
        assert_eq!(std::fs::read(&path).unwrap(), b"the previous frame");
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "the temporary file is removed"
        );
        write_atomically(&path, Existing::Replace, |sink| Ok(image.write_to(sink, image::ImageFormat::Png)?)).unwrap();
        assert_eq!(image::open(&path).unwrap().to_rgba8(), image);
    }

    #[test]
    fn an_existing_output_is_refused_unless_overwriting() {
        let dir = Scratch::new("existing").unwrap();
        let (old, new) = (dir.join("old.png"), dir.join("new.png"));
        write_bytes(&old, Existing::Replace, b"the user's image").unwrap();
        let refused = check_outputs([new.as_path(), old.as_path()], false).unwrap_err().to_string();
        assert!(refused.contains("old.png") && refused.contains("--overwrite"), "{refused}");
        check_outputs([new.as_path(), old.as_path()], true).unwrap();
        check_outputs([new.as_path()], false).unwrap();
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "the probes are removed");
    }

    /// What a write could only fail at its end is refused at the start, `--overwrite` or not.
    #[test]
    fn an_output_its_folder_would_not_take_is_refused() {
        let dir = Scratch::new("unwritable").unwrap();
        let file = dir.join("a-file");
        std::fs::write(&file, "").unwrap();
        for (output, problem) in [
            (dir.join("missing/frame.exr"), "missing does not exist"),
            (file.join("frame.exr"), "a-file is not a folder"),
            (dir.to_path_buf(), "is a folder, not a file"),
        ] {
            for overwrite in [false, true] {
                let refused = check_outputs([output.as_path()], overwrite).unwrap_err().to_string();
                assert!(refused.contains(problem), "{refused}");
            }
        }
    }

    /// Another program creates the output while it is being written: under `Refuse` its
    /// file stays, and the finished output waits in the temporary file the error names.
    #[test]
    fn a_file_that_appears_during_the_write_is_not_replaced_unless_allowed() {
        let dir = Scratch::new("appears").unwrap();
        let path = dir.join("frame.exr");
        let appearing = |sink: &mut Sink| {
            std::fs::write(&path, b"another program's frame")?;
            Ok(sink.write_all(b"argil's frame")?)
        };
        let error = write_atomically(&path, Existing::Refuse, appearing).unwrap_err();
        assert!(error.is::<InputError>(), "{error:#}");
        assert_eq!(std::fs::read(&path).unwrap(), b"another program's frame");
        let kept = dir.join(format!(".frame.exr.{}.tmp", std::process::id()));
        let message = error.to_string();
        assert!(message.contains("frame.exr: appeared") && message.contains(&kept.display().to_string()), "{message}");
        assert_eq!(std::fs::read(&kept).unwrap(), b"argil's frame");
        std::fs::remove_file(&kept).unwrap();

        write_atomically(&path, Existing::Replace, appearing).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"argil's frame");
        std::fs::remove_file(&path).unwrap();
        write_bytes(&path, Existing::Refuse, b"a new frame").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"a new frame");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "no temporary is left");
    }
}

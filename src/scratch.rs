//! Folders for passing files, removed when dropped whether the work failed or not: a bench
//! run's (the startup's caches and frames, the soak's reloaded scenes and viewer log) and
//! the tests'.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

/// A folder under the system's temporary folder, read as its `Path`.
pub struct Scratch(PathBuf);

impl Scratch {
    /// `argil-NAME-PID`, emptied first.
    pub fn new(name: &str) -> Result<Self> {
        let dir = std::env::temp_dir().join(format!("argil-{name}-{}", std::process::id()));
        if dir.exists() {
            std::fs::remove_dir_all(&dir).with_context(|| format!("cannot empty {}", dir.display()))?;
        }
        std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
        Ok(Self(dir))
    }
}

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<OsStr> for Scratch {
    fn as_ref(&self) -> &OsStr {
        self.0.as_os_str()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

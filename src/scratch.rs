//! The folder a bench run writes its passing files into (the startup's caches and frames,
//! the soak's reloaded scenes and viewer log), removed when the run ends, failed or not.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

pub struct Scratch(PathBuf);

impl Scratch {
    /// `argil-NAME-PID` under the system's temporary folder, emptied first.
    pub fn new(name: &str) -> Result<Self> {
        let dir = std::env::temp_dir().join(format!("argil-{name}-{}", std::process::id()));
        if dir.exists() {
            std::fs::remove_dir_all(&dir).with_context(|| format!("cannot empty {}", dir.display()))?;
        }
        std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
        Ok(Self(dir))
    }

    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

//! Errors shared by the commands.

use std::fmt::Display;
use std::path::Path;

use crate::scene::SceneError;

/// Bad input from the user: a file that is missing, unreadable, of the wrong kind, or
/// inconsistent with another. The command line exits with code 2 for it, as for bad
/// arguments, so that scripts can tell it from a failure of argil itself (code 1).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct InputError(pub String);

impl InputError {
    /// "`path`: `problem`".
    pub fn file(path: &Path, problem: impl Display) -> Self {
        Self(format!("{}: {problem}", path.display()))
    }
}

/// Whether `error` or any error in its chain is an [`InputError`] or a scene that cannot
/// be used ([`SceneError`]: its file, a mesh, a texture or a value in it).
pub fn is_input_error(error: &anyhow::Error) -> bool {
    error.chain().any(|e| e.is::<InputError>() || e.is::<SceneError>())
}

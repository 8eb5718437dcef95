//! Errors shared by the commands.

use std::fmt::Display;
use std::path::Path;

use ash::vk;
use gpu_allocator::AllocationError;

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

/// The user stopped the command (Ctrl-C, SIGTERM or SIGHUP). The command line exits with
/// [`INTERRUPTED_EXIT_CODE`] after writing what the command had when it can.
#[derive(Debug, thiserror::Error)]
#[error("interrupted {0}")]
pub struct Interrupted(pub String);

/// 128 + SIGINT, as a shell reports a process that Ctrl-C ended.
pub const INTERRUPTED_EXIT_CODE: u8 = 130;

/// Whether `error` or any error in its chain is [`Interrupted`].
pub fn is_interrupted(error: &anyhow::Error) -> bool {
    error.chain().any(|e| e.is::<Interrupted>())
}

/// Whether `error` or any error in its chain is an [`InputError`] or a scene that cannot
/// be used ([`SceneError`]: its file, a mesh, a texture or a value in it).
pub fn is_input_error(error: &anyhow::Error) -> bool {
    error.chain().any(|e| e.is::<InputError>() || e.is::<SceneError>())
}

/// One sentence on what a failure of the machine means and what to do, when `error` is one
/// argil can recognise (a lost device, memory running out).
pub fn advice(error: &anyhow::Error) -> Option<&'static str> {
    const OUT_OF_MEMORY: &str =
        "the GPU ran out of memory: try a smaller size, fewer or smaller meshes and textures, or another --device";
    error.chain().find_map(|e| {
        if let Some(result) = e.downcast_ref::<vk::Result>() {
            match *result {
                vk::Result::ERROR_DEVICE_LOST => Some(
                    "the Vulkan device was lost (its driver reset or crashed) and argil stopped; \
                     run the command again, and update the driver if it keeps happening",
                ),
                vk::Result::ERROR_OUT_OF_DEVICE_MEMORY | vk::Result::ERROR_OUT_OF_HOST_MEMORY => Some(OUT_OF_MEMORY),
                _ => None,
            }
        } else if let Some(AllocationError::OutOfMemory) = e.downcast_ref::<AllocationError>() {
            Some(OUT_OF_MEMORY)
        } else {
            None
        }
    })
}

//! Ctrl-C (SIGINT, and SIGTERM and SIGHUP alike: a terminal closed, a job stopped) for the
//! commands that have work to keep: the first signal asks them to end with it (`argil
//! reference` writes the samples it took, `argil render --accumulate` the mean of the
//! frames it drew, the viewer the scene's changes not saved), a second ends the process at
//! once with code 130.

use anyhow::{Context, Result};

use crate::error::INTERRUPTED_EXIT_CODE;

/// Calls `first` on Ctrl-C (on a thread of its own), and exits on the signal after it.
/// A process has one handler: this is called once, by the command's entry point.
pub fn on_ctrl_c(first: impl Fn() + Send + 'static) -> Result<()> {
    let pressed = std::sync::atomic::AtomicBool::new(false);
    ctrlc::set_handler(move || {
        if pressed.swap(true, std::sync::atomic::Ordering::Relaxed) {
            std::process::exit(i32::from(INTERRUPTED_EXIT_CODE));
        }
        first();
    })
    .context("cannot handle Ctrl-C")
}

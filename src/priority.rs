//! Work beside a start's serial path, on threads of the lowest priority: the builtin maps
//! beside the warm-up frame (scene/pending.rs) and the forward pipelines beside the
//! environment's precompute (render/renderer.rs). lavapipe runs a queue's work and
//! compiles its shaders on one thread of the usual priority, which then keeps its core;
//! the work beside it takes what is left, every core while the queue is idle.

use anyhow::{Context, Result};

/// Gives the calling thread, and the threads it goes on to create, the lowest priority.
/// Linux keeps a nice value per thread, which new threads inherit; elsewhere the work
/// runs at the usual priority.
pub fn lowest_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority reads no memory of ours; who = 0 is the calling thread. Failing
    // leaves the priority as it was, which is only slower.
    unsafe {
        libc::setpriority(libc::PRIO_PROCESS, 0, 19);
    }
}

/// A thread pool of one thread per core, each of the lowest priority.
pub fn lowest_priority_pool() -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .thread_name(|i| format!("argil-beside-{i}"))
        .start_handler(|_| lowest_priority())
        .build()
        .context("creating a thread pool failed")
}

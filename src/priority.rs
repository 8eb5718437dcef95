//! Work beside a start's serial path, on threads of a low priority: the builtin maps
//! beside the warm-up frame (scene/pending.rs) and the forward pipelines beside the
//! environment's precompute (render/renderer.rs). lavapipe runs a queue's work and
//! compiles its shaders on one thread of the usual priority, which then keeps most of its
//! core; the work beside it takes what is left, every core while the queue is idle.

use anyhow::{Context, Result};

/// The nice value of the work beside: low enough that lavapipe's queue thread keeps about
/// 90% of a core it shares, not so low that other programs starve it. Measured on 2 cores,
/// cold starts of the default scene: at 19 (the lowest) 1.42–1.47 s, but 16–19 s beside two
/// busy processes of the usual priority; at 10, 1.46–1.50 s and 3.5–4.2 s; at 0, 1.59–1.67 s
/// and 2.7 s.
const LOW_NICE: i32 = 10;

/// Gives the calling thread, and the threads it goes on to create, a low priority. Linux
/// keeps a nice value per thread, which new threads inherit; elsewhere the work runs at
/// the usual priority.
pub fn low_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority reads no memory of ours; who = 0 is the calling thread. Failing
    // leaves the priority as it was, which is only slower.
    unsafe {
        libc::setpriority(libc::PRIO_PROCESS, 0, LOW_NICE);
    }
}

/// A thread pool of one thread per core, each of a low priority.
pub fn low_priority_pool() -> Result<rayon::ThreadPool> {
    rayon::ThreadPoolBuilder::new()
        .thread_name(|i| format!("argil-beside-{i}"))
        .start_handler(|_| low_priority())
        .build()
        .context("creating a thread pool failed")
}

//! Noticing that the scene file, or a file it reads, changed on disk: its modification
//! time, polled about twice a second (cheaper and simpler than an OS file-watching
//! dependency).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};

use crate::scene::Scene;

pub const POLL_INTERVAL: Duration = Duration::from_millis(500);

pub struct FileWatch {
    pub path: PathBuf,
    /// The modification time last seen; `None` while the file cannot be read.
    seen: Option<SystemTime>,
    last_poll: Instant,
}

fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

impl FileWatch {
    pub fn new(path: PathBuf, now: Instant) -> Self {
        Self {
            seen: modified(&path),
            path,
            last_poll: now,
        }
    }

    /// Whether the file changed since it was last seen; looks at the disk at most once per
    /// [`POLL_INTERVAL`]. A file that disappears is not a change (an editor saving by
    /// rename), its reappearance is.
    pub fn poll(&mut self, now: Instant) -> bool {
        if now.duration_since(self.last_poll) < POLL_INTERVAL {
            return false;
        }
        self.last_poll = now;
        match modified(&self.path) {
            Some(t) if Some(t) != self.seen => {
                self.seen = Some(t);
                true
            }
            Some(_) => false,
            None => {
                self.seen = None;
                false
            }
        }
    }

    /// Takes the file's current state as seen, e.g. after the viewer wrote it itself.
    pub fn mark_seen(&mut self) {
        self.seen = modified(&self.path);
    }
}

/// A watch on each file loading `scene` read ([`Scene::inputs`]).
pub fn inputs_watch(scene: &Scene, now: Instant) -> Vec<FileWatch> {
    (scene.inputs.iter()).map(|file| FileWatch::new(file.clone(), now)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notices_a_change_once_and_not_more_often_than_the_interval() {
        let dir = std::env::temp_dir().join(format!("argil-watch-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join("scene.toml");
        std::fs::write(&path, "a").expect("write");
        let t0 = Instant::now();
        let mut watch = FileWatch::new(path.clone(), t0);
        let later = |n: u32| t0 + POLL_INTERVAL * n;
        assert!(!watch.poll(later(1)), "unchanged");

        let file = std::fs::File::options().write(true).open(&path).expect("open");
        file.set_modified(SystemTime::now() + Duration::from_secs(5))
            .expect("set mtime");
        assert!(
            !watch.poll(later(1) + Duration::from_millis(10)),
            "too soon to look again"
        );
        assert!(watch.poll(later(2)), "changed");
        assert!(!watch.poll(later(3)), "reported once");

        std::fs::remove_file(&path).expect("remove");
        assert!(!watch.poll(later(4)), "a missing file is not a change");
        std::fs::write(&path, "b").expect("write");
        assert!(watch.poll(later(5)), "its reappearance is");

        std::fs::write(&path, "c").expect("write");
        watch.mark_seen();
        assert!(!watch.poll(later(6)), "the viewer's own write is not a change");
        std::fs::remove_dir_all(&dir).ok();
    }
}

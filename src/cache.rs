//! What argil computes the same way at every start (the builtin maps, the pre-integrated
//! subsurface table, the environment's BRDF tables, the studio's cube, prefiltered maps,
//! irradiance cube and luminance grid, the ground's maps, the bounce at the vertices, the
//! driver's compiled pipelines), kept on disk so that a warm start reads it instead.
//!
//! The folder is `ARGIL_CACHE_DIR` (set and empty: no disk cache), else
//! `$XDG_CACHE_HOME/argil`, else `$HOME/.cache/argil`. An entry is a file `NAME-KEY.bin`,
//! KEY a hash of everything the bytes depend on, holding a header (magic, key, length,
//! CRC-32 of the payload: SIMD-fast, where FNV-1a took 10 ms of a warm start) and the
//! payload. A missing, truncated or corrupt entry is computed again and rewritten; a cache
//! that cannot be written costs only the time, so a failure to write an entry is reported
//! on stderr (the first of a process, as the others almost always share its cause) and
//! otherwise ignored.

use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::sync::Once;

use xxhash_rust::xxh3::Xxh3;

use crate::atomic::{write_bytes, Existing};

const MAGIC: &[u8; 8] = b"argilc02";
const HEADER: usize = 32;

/// The one report of an entry that could not be written: a folder that refuses one
/// refuses every entry of the start, a dozen lines of one cause.
static WRITE_FAILURE_REPORTED: Once = Once::new();

/// FNV-1a, 64 bits: a stable hash of bytes (`std`'s hashers may change between releases),
/// which names the bench's references and the fuzzer's findings.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    const OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
    const PRIME: u64 = 0x0000_0100_0000_01b3;
    bytes
        .iter()
        .fold(OFFSET_BASIS, |hash, &b| (hash ^ u64::from(b)).wrapping_mul(PRIME))
}

/// The key of bytes that depend on `parts` (source texts, sizes, device identities,
/// texels, meshes): XXH3-64 of argil's version and each part's length and bytes in turn.
pub fn key(parts: &[&[u8]]) -> u64 {
    let mut hasher = Xxh3::new();
    for part in std::iter::once(env!("CARGO_PKG_VERSION").as_bytes()).chain(parts.iter().copied()) {
        hasher.update(&(part.len() as u64).to_le_bytes());
        hasher.update(part);
    }
    hasher.digest()
}

#[derive(Clone, Debug)]
pub struct DiskCache {
    dir: Option<PathBuf>,
}

impl DiskCache {
    /// The cache the environment names (see the module's documentation).
    pub fn from_env() -> Self {
        let var = |name| std::env::var_os(name).filter(|v| !v.is_empty()).map(PathBuf::from);
        let dir = match std::env::var_os("ARGIL_CACHE_DIR") {
            Some(dir) if dir.is_empty() => None,
            Some(dir) => Some(PathBuf::from(dir)),
            None => var("XDG_CACHE_HOME")
                .map(|d| d.join("argil"))
                .or_else(|| var("HOME").map(|h| h.join(".cache").join("argil"))),
        };
        Self { dir }
    }

    /// A cache in `dir`, or none.
    pub fn at(dir: Option<&Path>) -> Self {
        Self {
            dir: dir.map(Path::to_path_buf),
        }
    }

    pub fn dir(&self) -> Option<&Path> {
        self.dir.as_deref()
    }

    fn path(&self, name: &str, key: u64) -> Option<PathBuf> {
        self.dir.as_ref().map(|d| d.join(format!("{name}-{key:016x}.bin")))
    }

    /// The payload stored under `name` and `key`, if it is there and whole.
    pub fn load(&self, name: &str, key: u64) -> Option<Vec<u8>> {
        let bytes = std::fs::read(self.path(name, key)?).ok()?;
        let (header, payload) = bytes.split_at_checked(HEADER)?;
        let word = |i: usize| u64::from_le_bytes(header[i..i + 8].try_into().expect("8 bytes"));
        let crc = u64::from(crc32fast::hash(payload));
        (&header[..8] == MAGIC && word(8) == key && word(16) == payload.len() as u64 && word(24) == crc)
            .then(|| payload.to_vec())
    }

    /// Stores `payload` under `name` and `key`, atomically.
    pub fn store(&self, name: &str, key: u64, payload: &[u8]) {
        let Some(path) = self.path(name, key) else { return };
        let mut bytes = Vec::with_capacity(HEADER + payload.len());
        bytes.extend_from_slice(MAGIC);
        for word in [key, payload.len() as u64, u64::from(crc32fast::hash(payload))] {
            bytes.extend_from_slice(&word.to_le_bytes());
        }
        bytes.extend_from_slice(payload);
        let written = path
            .parent()
            .map_or(Ok(()), std::fs::create_dir_all)
            .map_err(anyhow::Error::from)
            .and_then(|()| write_bytes(&path, Existing::Replace, &bytes));
        if let Err(e) = written {
            WRITE_FAILURE_REPORTED.call_once(|| {
                let path = path.display();
                let later = "later ones that fail are not reported";
                eprintln!("argil: warning: cannot write the cache entry {path}: {e:#}; {later}");
            });
        }
    }

    /// The payload under `name` and `key`, or `compute`'s, stored for the next start. A
    /// loaded payload `valid` rejects is computed again.
    pub fn get_or_compute(
        &self,
        name: &str,
        key: u64,
        valid: impl Fn(&[u8]) -> bool,
        compute: impl FnOnce() -> Vec<u8>,
    ) -> Vec<u8> {
        if let Some(bytes) = self.load(name, key).filter(|b| valid(b)) {
            return bytes;
        }
        let bytes = compute();
        self.store(name, key, &bytes);
        bytes
    }
}

/// The disk cache's key of a result that a frame computes on the device (the ground's
/// maps, the bounce at the vertices) and the cache did not hold: set when the cache misses
/// it, carried by the frame that records the computation, and taken to store the result
/// once that frame is done.
#[derive(Default)]
pub struct Unsaved {
    /// The computation the next recorded frame runs.
    missed: Cell<Option<u64>>,
    /// The one a recorded frame ran.
    recorded: Cell<Option<u64>>,
}

impl Unsaved {
    /// What the next recorded computation is stored under: `key`, or nothing.
    pub fn miss(&self, key: Option<u64>) {
        self.missed.set(key);
    }

    /// A frame records the computation.
    pub fn record(&self) {
        self.recorded.set(self.missed.take());
    }

    /// The key to store the recorded result under, once.
    pub fn take(&self) -> Option<u64> {
        self.recorded.take()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct TempDir(PathBuf);

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn temp_dir(name: &str) -> TempDir {
        TempDir(std::env::temp_dir().join(format!("argil-cache-{name}-{}", std::process::id())))
    }

    /// A missed key is stored only once a frame recorded its computation, and only once.
    #[test]
    fn an_unsaved_key_is_taken_once_after_its_computation_is_recorded() {
        let unsaved = Unsaved::default();
        unsaved.miss(Some(7));
        assert_eq!(unsaved.take(), None, "not recorded yet");
        unsaved.record();
        assert_eq!((unsaved.take(), unsaved.take()), (Some(7), None));
        unsaved.miss(Some(8));
        unsaved.miss(None);
        unsaved.record();
        assert_eq!(unsaved.take(), None, "a hit after the miss stores nothing");
    }

    #[test]
    fn fnv1a_matches_the_published_test_vectors() {
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn keys_depend_on_every_part_and_its_order() {
        let k = key(&[b"a", b"b"]);
        assert_ne!(k, key(&[b"b", b"a"]));
        assert_ne!(k, key(&[b"ab"]));
        assert_eq!(k, key(&[b"a", b"b"]));
    }

    #[test]
    fn a_second_start_reads_what_the_first_computed() {
        let dir = temp_dir("hit");
        let cache = DiskCache::at(Some(&dir.0));
        let mut computed = 0;
        for _ in 0..2 {
            let bytes = cache.get_or_compute(
                "t",
                7,
                |_| true,
                || {
                    computed += 1;
                    vec![1, 2, 3]
                },
            );
            assert_eq!(bytes, [1, 2, 3]);
        }
        assert_eq!(computed, 1);
        assert_eq!(cache.load("t", 8), None, "another key is another entry");
    }

    #[test]
    fn corrupt_truncated_or_rejected_entries_are_computed_again() {
        let dir = temp_dir("corrupt");
        let cache = DiskCache::at(Some(&dir.0));
        cache.store("t", 1, &[5; 100]);
        let path = cache.path("t", 1).unwrap();
        let mut bytes = std::fs::read(&path).unwrap();
        bytes[HEADER + 50] ^= 1;
        std::fs::write(&path, &bytes).unwrap();
        assert_eq!(cache.load("t", 1), None, "a flipped bit");
        std::fs::write(&path, &bytes[..HEADER + 10]).unwrap();
        assert_eq!(cache.load("t", 1), None, "truncated");
        assert_eq!(cache.get_or_compute("t", 1, |_| true, || vec![6; 4]), [6; 4]);
        assert_eq!(cache.load("t", 1), Some(vec![6; 4]), "rewritten");
        assert_eq!(cache.get_or_compute("t", 1, |b| b.len() == 8, || vec![7; 8]), [7; 8]);
    }

    #[test]
    fn no_folder_means_no_cache() {
        let cache = DiskCache::at(None);
        cache.store("t", 1, &[1]);
        assert_eq!(cache.load("t", 1), None);
        assert_eq!(cache.get_or_compute("t", 1, |_| true, || vec![2]), [2]);
    }
}

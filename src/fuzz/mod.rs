//! Fuzzing of what argil reads from users: scene TOML, OBJ meshes (tobj, then tangents and
//! curvature) and the image files it decodes (PNG, JPEG, Radiance HDR, OpenEXR, as
//! textures and as environment maps). Each input goes through the same public loaders the
//! commands call, from a file, and must come back as `Ok` or as an error: a panic or an
//! input that takes too long is a crasher.
//!
//! `argil-fuzz` (src/bin/argil-fuzz.rs) mutates a seed corpus for a given time;
//! `tests/fuzz.rs` replays the corpus and every crasher found so far, which live in
//! `tests/fuzz/corpus/TARGET/` and `tests/fuzz/crashers/TARGET/`.

mod mutate;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use crate::cache::fnv1a;
use crate::render::environment::equirect;
use crate::scene::{load_texture, Mesh, Scene, TextureRole};

pub use mutate::Mutator;

/// One kind of input, named as its corpus folder.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Target {
    Scene,
    Obj,
    Png,
    Jpeg,
    Hdr,
    Exr,
}

impl Target {
    pub const ALL: [Target; 6] = [
        Target::Scene,
        Target::Obj,
        Target::Png,
        Target::Jpeg,
        Target::Hdr,
        Target::Exr,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Target::Scene => "scene",
            Target::Obj => "obj",
            Target::Png => "png",
            Target::Jpeg => "jpeg",
            Target::Hdr => "hdr",
            Target::Exr => "exr",
        }
    }

    pub fn from_name(name: &str) -> Option<Target> {
        Target::ALL.into_iter().find(|t| t.name() == name)
    }

    /// The file extension the loaders expect.
    fn extension(self) -> &'static str {
        match self {
            Target::Scene => "toml",
            Target::Obj => "obj",
            Target::Png => "png",
            Target::Jpeg => "jpg",
            Target::Hdr => "hdr",
            Target::Exr => "exr",
        }
    }
}

/// Runs inputs through the loaders. Each input is written to `scratch/input.EXT` first, so
/// that an input that kills the process (an abort, out of memory) is left on disk.
pub struct Harness {
    scratch: PathBuf,
    /// The folder scene inputs resolve their relative paths against (meshes, textures and
    /// environment maps the scene seeds name).
    assets: PathBuf,
}

impl Harness {
    pub fn new(scratch: &Path, assets: &Path) -> Result<Self> {
        std::fs::create_dir_all(scratch).with_context(|| format!("cannot create {}", scratch.display()))?;
        Ok(Self {
            scratch: scratch.to_path_buf(),
            assets: assets.to_path_buf(),
        })
    }

    /// Where the current input of `target` is written.
    pub fn input_path(&self, target: Target) -> PathBuf {
        self.scratch.join(format!("input.{}", target.extension()))
    }

    /// Loads `input` as `target` does; `Err` is the loader's message (a rejected input),
    /// the outer `Result` a failure of the harness itself.
    pub fn run(&self, target: Target, input: &[u8]) -> Result<Result<(), String>> {
        let path = self.input_path(target);
        std::fs::write(&path, input).with_context(|| format!("cannot write {}", path.display()))?;
        let message = |e: &dyn std::fmt::Display| format!("{e:#}");
        Ok(match target {
            Target::Scene => {
                // The scene's text from the file, as `Scene::load` reads it, but against the
                // assets folder.
                match std::str::from_utf8(input) {
                    Ok(text) => Scene::from_toml(text, "fuzz", &self.assets)
                        .map(drop)
                        .map_err(|e| message(&e)),
                    Err(e) => Err(message(&e)),
                }
            }
            Target::Obj => Mesh::load_obj(&path).map(drop).map_err(|e| message(&e)),
            Target::Png | Target::Jpeg => {
                let colour = load_texture(&path, TextureRole::BaseColor).map_err(|e| message(&e));
                let normal = load_texture(&path, TextureRole::Normal).map_err(|e| message(&e));
                colour.and(normal).map(drop)
            }
            Target::Hdr | Target::Exr => {
                let texture = load_texture(&path, TextureRole::BaseColor).map_err(|e| message(&e));
                let map = equirect::load(&path).map_err(|e| message(&e));
                texture.and(map).map(drop)
            }
        })
    }
}

/// The files of `dir` (none if it does not exist), sorted by name, with their bytes.
pub fn read_corpus(dir: &Path) -> Result<Vec<(PathBuf, Vec<u8>)>> {
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(e).with_context(|| format!("cannot list {}", dir.display())),
    };
    let mut files = Vec::new();
    for entry in entries {
        let path = entry.with_context(|| format!("cannot list {}", dir.display()))?.path();
        if path.is_file() {
            let bytes = std::fs::read(&path).with_context(|| format!("cannot read {}", path.display()))?;
            files.push((path, bytes));
        }
    }
    files.sort();
    Ok(files)
}

/// What a rejected input's message says with its numbers left out, so that inputs that
/// fail the same check with other values count as one behaviour. Only the first and the
/// last line count: TOML errors quote the offending line between them.
pub fn signature(message: &str) -> String {
    let first = message.lines().next().unwrap_or_default();
    let last = message.lines().last().unwrap_or_default();
    let mut out = String::with_capacity(first.len() + last.len());
    for c in first.chars().chain(['\n']).chain(last.chars()) {
        if c.is_ascii_digit() {
            if !out.ends_with('#') {
                out.push('#');
            }
        } else {
            out.push(c);
        }
    }
    out
}

/// A crasher's file name: its content's hash, so that finding it again changes nothing.
pub fn crasher_name(target: Target, bytes: &[u8]) -> String {
    format!("{:016x}.{}", fnv1a(bytes), target.extension())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signatures_ignore_numbers() {
        assert_eq!(
            signature("a.png: the image is too large (70000 × 3)"),
            signature("a.png: the image is too large (9 × 12345)")
        );
        assert_ne!(signature("a: empty"), signature("a: too large"));
        assert_eq!(
            signature("fuzz: TOML parse error at line 3\n3 | scale = 2x\n  |   ^\ninvalid number"),
            signature("fuzz: TOML parse error at line 9\n9 | roughness = 0.5.\n  |   ^\ninvalid number")
        );
    }

    #[test]
    fn targets_are_named_as_their_folders() {
        for target in Target::ALL {
            assert_eq!(Target::from_name(target.name()), Some(target));
        }
    }
}

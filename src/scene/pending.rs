//! A scene's builtin maps, made after the scene loads. Making them (or reading them from
//! the disk cache) is most of a scene's load, and a start has other work that does not
//! read their texels: its device, environment and pipelines, and the driver's compile of
//! the frame's shaders, which lavapipe does on one core at the first draw. Stand-ins
//! (`procedural::stand_in`) take the maps' places in the scene until
//! [`PendingMaps::finish`].

use std::path::Path;
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use anyhow::{anyhow, Result};

use super::{builtin_texture, BuiltinMaps, Scene, SceneError, TextureData, BUILTIN_PREFIX, DEFAULT_SCENE_TOML};
use crate::priority::low_priority;

/// The builtin maps of a scene loaded with stand-ins for them, and the threads making
/// them once begun. Dropped unfinished, it leaves its threads to finish on their own.
pub struct PendingMaps {
    /// Each map's index in the scene's textures, and its name.
    stand_ins: Vec<(usize, String)>,
    /// When the maps were begun.
    begun: Option<Instant>,
    makers: Vec<Maker>,
}

/// A thread making a builtin map, which returns it and when it was done.
type Maker = JoinHandle<(Option<TextureData>, Instant)>;

impl PendingMaps {
    /// Loads the scene file at `path` as `Scene::load` does, or the default scene, with
    /// stand-ins for its builtin maps, which the returned maps replace.
    pub fn load(path: Option<&Path>) -> Result<(Scene, PendingMaps), SceneError> {
        let stand_ins = BuiltinMaps::StandIns;
        let scene = match path {
            Some(path) => Scene::load_with(path, stand_ins)?,
            None => Scene::from_toml_with(DEFAULT_SCENE_TOML, "<default scene>", Path::new(""), stand_ins)?,
        };
        Ok(PendingMaps::of(scene))
    }

    /// [`Self::load`] of scene TOML, as `Scene::from_toml` reads it.
    pub fn from_toml(text: &str, origin: &str, base_dir: &Path) -> Result<(Scene, PendingMaps), SceneError> {
        Scene::from_toml_with(text, origin, base_dir, BuiltinMaps::StandIns).map(PendingMaps::of)
    }

    /// `scene`, loaded with stand-ins, and its maps to make.
    fn of(scene: Scene) -> (Scene, PendingMaps) {
        let textures = scene.textures.iter().enumerate();
        let stand_ins = textures
            .filter(|(_, texture)| texture.name.starts_with(BUILTIN_PREFIX))
            .map(|(index, texture)| (index, texture.name.clone()))
            .collect();
        let maps = PendingMaps {
            stand_ins,
            begun: None,
            makers: Vec::new(),
        };
        (scene, maps)
    }

    /// Takes the maps at the texture indices `later` picks out of these: their stand-ins
    /// stay in the scene until the returned maps are finished, or for good. A frame that
    /// never samples a map draws the same with its stand-in. Before [`Self::begin`], whose
    /// threads [`Self::finish`] takes in the stand-ins' order.
    pub fn split_off(&mut self, later: impl Fn(usize) -> bool) -> PendingMaps {
        debug_assert!(self.begun.is_none(), "the maps' threads are already running");
        let (taken, kept) = std::mem::take(&mut self.stand_ins)
            .into_iter()
            .partition(|(index, _)| later(*index));
        self.stand_ins = kept;
        PendingMaps {
            stand_ins: taken,
            begun: None,
            makers: Vec::new(),
        }
    }

    /// Whether no map is left to make.
    pub fn is_empty(&self) -> bool {
        self.stand_ins.is_empty()
    }

    /// Where the stand-ins are among the scene's textures: what [`Self::finish`] replaces.
    pub fn stand_ins(&self) -> Vec<usize> {
        self.stand_ins.iter().map(|(index, _)| *index).collect()
    }

    /// Starts making the maps, each on a thread of its own at a low priority: they
    /// take what the rest of the start leaves idle. Begun beside work that keeps both
    /// cores busy (lavapipe's compute), they would only slow it; beside the driver's
    /// compile, they fill the core it leaves.
    pub fn begin(&mut self) {
        if self.begun.is_some() {
            return;
        }
        self.begun = Some(Instant::now());
        self.makers = (self.stand_ins.iter())
            .map(|(_, name)| {
                let name = name.clone();
                thread::spawn(move || {
                    low_priority();
                    (builtin_texture(&name), Instant::now())
                })
            })
            .collect();
    }

    /// Waits for the maps, or makes them on the calling thread at its own priority if they
    /// were not begun (a scene loaded while nothing else runs: the viewer's reloads), and
    /// puts them in `scene`'s textures in place of the stand-ins; returns the wall time from
    /// [`Self::begin`] (or from now) to the last map made.
    pub fn finish(self, scene: &mut Scene) -> Result<Duration> {
        let begun = self.begun.unwrap_or_else(Instant::now);
        let mut done = begun;
        // begin() starts a thread for every map or none.
        let mut makers = self.makers.into_iter();
        for (index, name) in self.stand_ins {
            let (made, at) = match makers.next() {
                Some(maker) => maker.join().unwrap_or((None, begun)),
                None => (builtin_texture(&name), Instant::now()),
            };
            let texture = (scene.textures.get_mut(index).filter(|t| t.name == name))
                .ok_or_else(|| anyhow!("{name} is not the scene's texture {index}"))?;
            *texture = made.ok_or_else(|| anyhow!("making the builtin map {name} failed"))?;
            done = done.max(at);
        }
        Ok(done - begun)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stand-ins take the default scene's builtin maps' places until the maps replace them,
    /// which leaves the scene loaded at once.
    #[test]
    fn a_scene_with_stand_ins_finishes_as_the_scene_loaded_at_once() {
        let (mut scene, maps) = PendingMaps::load(None).unwrap();
        let stand_ins = maps.stand_ins();
        assert!(!stand_ins.is_empty(), "the default scene has builtin maps");
        for (i, texture) in scene.textures.iter().enumerate() {
            let builtin = texture.name.starts_with(BUILTIN_PREFIX);
            assert_eq!(stand_ins.contains(&i), builtin, "{}", texture.name);
            assert!(!builtin || (texture.width, texture.height) == (2, 2), "{}", texture.name);
        }
        maps.finish(&mut scene).unwrap();
        assert_eq!(scene, Scene::default_scene());
    }

    /// A map split off stays a stand-in while the others are made and put in as before,
    /// until it is made in turn.
    #[test]
    fn a_map_split_off_keeps_its_stand_in_until_it_is_made() {
        let (mut scene, mut maps) = PendingMaps::load(None).unwrap();
        let noise = scene.textures.iter().position(|t| t.name == "builtin:noise").unwrap();
        let later = maps.split_off(|index| index == noise);
        assert_eq!(later.stand_ins(), [noise]);
        assert!(!maps.stand_ins().contains(&noise) && !maps.is_empty());
        maps.finish(&mut scene).unwrap();
        let whole = Scene::default_scene();
        for (i, (texture, made)) in scene.textures.iter().zip(&whole.textures).enumerate() {
            let kept = (texture.width, texture.height) == (2, 2);
            assert_eq!(kept, i == noise, "{}", texture.name);
            assert!(kept || texture == made, "{}", texture.name);
        }
        later.finish(&mut scene).unwrap();
        assert_eq!(scene, whole);
    }

    /// The maps go into the scene they came with, not another.
    #[test]
    fn the_maps_of_one_scene_are_refused_by_another() {
        let (_, maps) = PendingMaps::load(None).unwrap();
        let mut other = Scene::from_toml("[[objects]]\nmesh = \"builtin:sphere\"", "test", Path::new("")).unwrap();
        assert!(maps.finish(&mut other).is_err());
    }
}

//! A scene whose builtin maps are still being made. Making them (or reading them from the
//! disk cache) is most of a scene's load, and nothing before the first draw reads their
//! texels: a start creates its device, environment and pipelines for the scene while other
//! threads make its maps, and waits for them only to upload them.

use std::path::Path;
use std::thread::{self, JoinHandle};

use anyhow::{anyhow, Result};

use super::{builtin_texture, BuiltinMaps, Scene, SceneError, TextureData, BUILTIN_PREFIX, DEFAULT_SCENE_TOML};

/// A scene with a texel standing in for each of its builtin maps, and the threads making
/// them. Dropped unfinished, it leaves its threads to finish on their own.
pub struct PendingScene {
    scene: Scene,
    /// Each builtin map's index in the scene's textures, and the thread making it.
    makers: Vec<(usize, JoinHandle<Option<TextureData>>)>,
}

impl PendingScene {
    /// Loads the scene file at `path` as `Scene::load` does, or the default scene, and
    /// starts making its builtin maps.
    pub fn load(path: Option<&Path>) -> Result<PendingScene, SceneError> {
        let stand_ins = BuiltinMaps::StandIns;
        let scene = match path {
            Some(path) => Scene::load_with(path, stand_ins)?,
            None => Scene::from_toml_with(DEFAULT_SCENE_TOML, "<default scene>", Path::new(""), stand_ins)?,
        };
        let makers = scene
            .textures
            .iter()
            .enumerate()
            .filter(|(_, texture)| texture.name.starts_with(BUILTIN_PREFIX))
            .map(|(index, texture)| {
                let name = texture.name.clone();
                (index, thread::spawn(move || builtin_texture(&name)))
            })
            .collect();
        Ok(PendingScene { scene, makers })
    }

    /// The scene with its builtin maps stood in for: enough for everything but drawing it.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene to change before it is finished; its textures are the stand-ins
    /// [`Self::finish`] replaces.
    pub fn scene_mut(&mut self) -> &mut Scene {
        &mut self.scene
    }

    /// Waits for the builtin maps and returns the scene with them.
    pub fn finish(self) -> Result<Scene> {
        let PendingScene { mut scene, makers } = self;
        for (index, maker) in makers {
            let texture = &mut scene.textures[index];
            let made = maker.join().ok().flatten();
            *texture = made.ok_or_else(|| anyhow!("making the builtin map {} failed", texture.name))?;
        }
        Ok(scene)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A texel stands in for each builtin map of the default scene until it finishes as the
    /// scene loaded at once.
    #[test]
    fn a_pending_scene_finishes_as_the_scene_loaded_at_once() {
        let pending = PendingScene::load(None).unwrap();
        let textures = &pending.scene().textures;
        let builtins: Vec<_> = textures.iter().filter(|t| t.name.starts_with(BUILTIN_PREFIX)).collect();
        assert!(!builtins.is_empty(), "the default scene has builtin maps");
        assert!(builtins.iter().all(|t| (t.width, t.height) == (1, 1)));
        assert_eq!(pending.finish().unwrap(), Scene::default_scene());
    }
}

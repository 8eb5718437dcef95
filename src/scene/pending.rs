//! A scene whose builtin maps are still being made. Making them (or reading them from the
//! disk cache) is most of a scene's load, and a start has other work that does not read
//! their texels: its device, environment and pipelines, and the driver's compile of the
//! frame's shaders, which lavapipe does on one core at the first draw. Stand-ins take
//! the maps' places until [`PendingScene::finish`].

use std::path::Path;
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use anyhow::{anyhow, Result};

use super::{builtin_texture, BuiltinMaps, Scene, SceneError, TextureData, BUILTIN_PREFIX, DEFAULT_SCENE_TOML};

/// A scene with stand-ins for its builtin maps (`procedural::stand_in`), and the threads
/// making the maps once begun. Dropped unfinished, it leaves its threads to finish on
/// their own.
pub struct PendingScene {
    scene: Scene,
    /// When the maps were begun.
    begun: Option<Instant>,
    /// Each builtin map's index in the scene's textures, and the thread making it.
    makers: Vec<(usize, Maker)>,
}

/// A thread making a builtin map, which returns it and when it was done.
type Maker = JoinHandle<(Option<TextureData>, Instant)>;

impl PendingScene {
    /// Loads the scene file at `path` as `Scene::load` does, or the default scene, with
    /// stand-ins for its builtin maps.
    pub fn load(path: Option<&Path>) -> Result<PendingScene, SceneError> {
        let stand_ins = BuiltinMaps::StandIns;
        let scene = match path {
            Some(path) => Scene::load_with(path, stand_ins)?,
            None => Scene::from_toml_with(DEFAULT_SCENE_TOML, "<default scene>", Path::new(""), stand_ins)?,
        };
        Ok(PendingScene {
            scene,
            begun: None,
            makers: Vec::new(),
        })
    }

    /// The scene with its builtin maps stood in for.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene to change before it is finished; its textures are the stand-ins
    /// [`Self::finish`] replaces.
    pub fn scene_mut(&mut self) -> &mut Scene {
        &mut self.scene
    }

    /// Where the stand-ins are among the scene's textures: what [`Self::finish`] replaces.
    pub fn stand_ins(&self) -> Vec<usize> {
        let textures = self.scene.textures.iter().enumerate();
        textures.filter(|(_, texture)| texture.name.starts_with(BUILTIN_PREFIX)).map(|(i, _)| i).collect()
    }

    /// Starts making the builtin maps, each on a thread of its own at the lowest priority:
    /// they take what the rest of the start leaves idle. Begun beside work that keeps both
    /// cores busy (lavapipe's compute), they would only slow it; beside the driver's
    /// compile, they fill the core it leaves.
    pub fn begin_maps(&mut self) {
        if self.begun.is_some() {
            return;
        }
        self.begun = Some(Instant::now());
        self.makers = self
            .stand_ins()
            .into_iter()
            .map(|index| {
                let name = self.scene.textures[index].name.clone();
                let maker = thread::spawn(move || {
                    lowest_priority();
                    (builtin_texture(&name), Instant::now())
                });
                (index, maker)
            })
            .collect();
    }

    /// Makes the builtin maps if they are not begun, waits for them, and returns the scene
    /// with them, and the wall time from [`Self::begin_maps`] to the last map made.
    pub fn finish(mut self) -> Result<(Scene, Duration)> {
        self.begin_maps();
        let PendingScene {
            mut scene,
            begun,
            makers,
        } = self;
        let begun = begun.unwrap_or_else(Instant::now);
        let mut done = begun;
        for (index, maker) in makers {
            let texture = &mut scene.textures[index];
            let (made, at) = maker.join().unwrap_or((None, begun));
            *texture = made.ok_or_else(|| anyhow!("making the builtin map {} failed", texture.name))?;
            done = done.max(at);
        }
        Ok((scene, done - begun))
    }
}

/// Gives the calling thread, and the threads it goes on to create, the lowest priority.
/// Linux keeps a nice value per thread, which new threads inherit; elsewhere the maps
/// run at the usual priority.
fn lowest_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority reads no memory of ours; who = 0 is the calling thread. Failing
    // leaves the priority as it was, which is only slower.
    unsafe {
        libc::setpriority(libc::PRIO_PROCESS, 0, 19);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stand-ins take the default scene's builtin maps' places until it finishes as the
    /// scene loaded at once.
    #[test]
    fn a_pending_scene_finishes_as_the_scene_loaded_at_once() {
        let pending = PendingScene::load(None).unwrap();
        let stand_ins = pending.stand_ins();
        assert!(!stand_ins.is_empty(), "the default scene has builtin maps");
        for (i, texture) in pending.scene().textures.iter().enumerate() {
            let builtin = texture.name.starts_with(BUILTIN_PREFIX);
            assert_eq!(stand_ins.contains(&i), builtin, "{}", texture.name);
            assert!(!builtin || (texture.width, texture.height) == (2, 2), "{}", texture.name);
        }
        assert_eq!(pending.finish().unwrap().0, Scene::default_scene());
    }
}

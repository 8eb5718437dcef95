//! Undo and redo of the panel's edits, and whether the scene differs from its file. The
//! camera is left out: it moves all the time, and Reset view (R) restores the file's.

use crate::scene::{Environment, Material, PointLight, Scene};

/// Steps kept for undo.
const DEPTH: usize = 200;

/// What the panel edits.
#[derive(Clone, Debug, PartialEq)]
struct Edits {
    materials: Vec<Material>,
    lights: Vec<PointLight>,
    environment: Environment,
}

impl Edits {
    fn of(scene: &Scene) -> Edits {
        Edits {
            materials: scene.materials.clone(),
            lights: scene.lights.clone(),
            environment: scene.environment.clone(),
        }
    }

    fn apply(&self, scene: &mut Scene) {
        scene.materials.clone_from(&self.materials);
        scene.lights.clone_from(&self.lights);
        scene.environment.clone_from(&self.environment);
    }
}

pub struct History {
    undo: Vec<Edits>,
    redo: Vec<Edits>,
    /// The state the last step left.
    current: Edits,
    /// The state of the file on disk.
    saved: Edits,
}

impl History {
    /// A history whose file holds `scene`.
    pub fn new(scene: &Scene) -> History {
        History {
            undo: Vec::new(),
            redo: Vec::new(),
            current: Edits::of(scene),
            saved: Edits::of(scene),
        }
    }

    /// Makes the scene's state one step when it changed and `settled` (no button is held:
    /// a drag is one step, not one per frame).
    pub fn observe(&mut self, scene: &Scene, settled: bool) {
        if !settled {
            return;
        }
        let now = Edits::of(scene);
        if now != self.current {
            self.undo.push(std::mem::replace(&mut self.current, now));
            if self.undo.len() > DEPTH {
                self.undo.remove(0);
            }
            self.redo.clear();
        }
    }

    pub fn undo(&mut self, scene: &mut Scene) {
        self.observe(scene, true);
        if let Some(step) = self.undo.pop() {
            step.apply(scene);
            self.redo.push(std::mem::replace(&mut self.current, step));
        }
    }

    pub fn redo(&mut self, scene: &mut Scene) {
        self.observe(scene, true);
        if let Some(step) = self.redo.pop() {
            step.apply(scene);
            self.undo.push(std::mem::replace(&mut self.current, step));
        }
    }

    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty()
    }

    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    /// Whether `scene` differs from the file (camera aside).
    pub fn modified(&self, scene: &Scene) -> bool {
        Edits::of(scene) != self.saved
    }

    /// The file now holds `scene`.
    pub fn mark_saved(&mut self, scene: &Scene) {
        self.saved = Edits::of(scene);
    }

    /// Takes `scene`, resolved again from the same text after files it reads changed on
    /// disk: with the same edits, which name the same files, every step still applies
    /// and is kept; otherwise (a model that now brings other materials) it starts over.
    pub fn reread(&mut self, scene: &Scene) {
        if Edits::of(scene) != self.current {
            self.rebase(scene);
        }
    }

    /// Starts over from `scene`, which was rebuilt (its textures may have changed, so
    /// older steps no longer apply); the file's state stays what it was.
    pub fn rebase(&mut self, scene: &Scene) {
        self.undo.clear();
        self.redo.clear();
        self.current = Edits::of(scene);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_drag_is_one_step_that_undoes_and_redoes() {
        let mut scene = Scene::default_scene();
        let mut history = History::new(&scene);
        assert!(!history.modified(&scene) && !history.can_undo());
        for roughness in [0.7, 0.75, 0.8] {
            scene.materials[0].roughness = roughness;
            history.observe(&scene, false);
        }
        history.observe(&scene, true);
        scene.lights[0].position.x += 1.0;
        history.observe(&scene, true);
        assert!(history.modified(&scene));

        history.undo(&mut scene);
        assert_eq!(scene.lights, Scene::default_scene().lights);
        assert_eq!(scene.materials[0].roughness, 0.8);
        history.undo(&mut scene);
        assert_eq!(scene, Scene::default_scene(), "back to the file's scene");
        assert!(!history.modified(&scene) && !history.can_undo());
        history.redo(&mut scene);
        history.redo(&mut scene);
        assert_eq!(scene.materials[0].roughness, 0.8);
        assert_eq!(
            scene.lights[0].position.x,
            Scene::default_scene().lights[0].position.x + 1.0
        );
        assert!(!history.can_redo());

        history.mark_saved(&scene);
        assert!(!history.modified(&scene));
        scene.materials[0].f0 = 0.1;
        history.undo(&mut scene);
        assert!(history.can_redo(), "an edit not yet observed is a step of its own");
        assert_eq!(scene.materials[0].f0, Scene::default_scene().materials[0].f0);
    }

    #[test]
    fn a_scene_read_again_keeps_its_steps_unless_its_edits_changed() {
        let mut scene = Scene::default_scene();
        let mut history = History::new(&scene);
        scene.materials[0].roughness = 0.7;
        history.observe(&scene, true);
        history.reread(&scene);
        assert!(history.can_undo(), "the same edits: the steps apply");
        let mut other = scene.clone();
        other.materials[0].base_color.x = 0.25;
        history.reread(&other);
        assert!(!history.can_undo(), "other materials: starts over");
    }
}

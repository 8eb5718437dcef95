//! A split frame: the columns right of `x` drawn with other materials and another
//! reflection mode, the viewer's comparison of two configurations side by side. Both halves
//! share the frame's camera, lights, shadow maps, occlusion, environment images, skybox,
//! exposure and display transform; only the forward pass draws twice, each half under its
//! own scissor rectangle with its own pipelines and materials (forward.rs).

use anyhow::{ensure, Result};
use ash::vk;

use crate::scene::{Environment, Material, Scene};

/// What the right part of a frame is drawn with.
#[derive(Clone, Debug, PartialEq)]
pub struct Split {
    /// One per material of the frame's scene, in the same order.
    pub materials: Vec<Material>,
    /// The frame's environment with, possibly, another reflection mode.
    pub environment: Environment,
    /// The first column of the right part, in pixels of the render target.
    pub x: u32,
}

impl Split {
    /// Checks that the split can be drawn beside `scene`: a material for each of its
    /// materials and the same environment but for the reflection mode (the environment's
    /// images and uniforms are the scene's, read by both halves).
    pub fn check(&self, scene: &Scene) -> Result<()> {
        ensure!(
            self.materials.len() == scene.materials.len(),
            "the split view has {} materials for the scene's {}",
            self.materials.len(),
            scene.materials.len()
        );
        ensure!(
            same_but_reflection_mode(&self.environment, &scene.environment),
            "the split view's environment differs from the scene's in more than its reflection mode"
        );
        Ok(())
    }

    /// The scissor rectangles of the left and right parts of a target of `extent`.
    pub fn scissors(&self, extent: vk::Extent2D) -> [vk::Rect2D; 2] {
        let x = self.x.min(extent.width);
        [
            vk::Rect2D {
                offset: vk::Offset2D::default(),
                extent: vk::Extent2D {
                    width: x,
                    height: extent.height,
                },
            },
            vk::Rect2D {
                offset: vk::Offset2D { x: x as i32, y: 0 },
                extent: vk::Extent2D {
                    width: extent.width - x,
                    height: extent.height,
                },
            },
        ]
    }
}

/// Whether `a` and `b` are the same environment once `a` takes `b`'s reflection mode.
pub fn same_but_reflection_mode(a: &Environment, b: &Environment) -> bool {
    let mut a = a.clone();
    if let (Some(ra), Some(rb)) = (a.reflection_mut(), b.reflection()) {
        ra.mode = rb.mode;
    }
    a == *b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::ReflectionMode;

    fn studio(mode: ReflectionMode, samples: u32) -> Environment {
        let mut e = Scene::default_scene().environment;
        let r = e.reflection_mut().expect("the default scene has an environment");
        (r.mode, r.samples) = (mode, samples);
        e
    }

    #[test]
    fn only_the_reflection_mode_may_differ() {
        let split_sum = studio(ReflectionMode::SplitSum, 64);
        assert!(same_but_reflection_mode(&studio(ReflectionMode::Seed, 64), &split_sum));
        assert!(!same_but_reflection_mode(&studio(ReflectionMode::Seed, 16), &split_sum));
        assert!(!same_but_reflection_mode(&Environment::None, &split_sum));
    }

    #[test]
    fn scissors_cover_the_target_once() {
        let split = Split {
            materials: Vec::new(),
            environment: Environment::None,
            x: 70,
        };
        let extent = vk::Extent2D { width: 160, height: 90 };
        let [left, right] = split.scissors(extent);
        assert_eq!((left.offset.x, left.extent.width), (0, 70));
        assert_eq!((right.offset.x, right.extent.width), (70, 90));
        assert!([left, right].iter().all(|r| r.extent.height == 90));
        let past = Split { x: 500, ..split };
        assert_eq!(past.scissors(extent)[1].extent.width, 0);
    }
}

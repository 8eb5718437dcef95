//! Where the objects can shadow the ground: the rectangle of the ground's square outside
//! which every point sees every shadowed light's sphere whole. The ground's shadow map
//! covers it alone (src/render/ground_maps.rs), and the ground reads 1 outside it
//! (shaders/lib/ground_shadow.glsl), which there is exact.

use glam::{Vec2, Vec3, Vec3Swizzles};

use super::mesh::box_corners;
use super::Scene;

/// A rectangle of the ground's plane: x and z from `min` to `max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GroundRect {
    pub min: Vec2,
    pub max: Vec2,
}

impl Scene {
    /// The part of the ground's square where an object may stand between a point and the
    /// sphere of one of the lights `shadowed` (indices into `lights`), or None where none
    /// can (or there is no ground). A shadow falls where a segment from a point of a light's
    /// sphere through a point of an object's bounding box, above the ground, meets the
    /// ground. A central projection onto the plane maps the hull of a box's corners to the
    /// hull of their images, from a fixed light point and through a fixed object point
    /// alike, so the corners of each light's box projected through each object's bound the
    /// shadow. An object that reaches as high as a light's lowest point may shadow the
    /// ground to its horizon: then the whole square.
    pub fn ground_shadow_rect(&self, shadowed: &[usize]) -> Option<GroundRect> {
        let ground_index = self.ground_index()?;
        let ground = &self.objects[ground_index];
        let height = ground.position.y;
        let square = GroundRect {
            min: ground.position.xz() - ground.scale,
            max: ground.position.xz() + ground.scale,
        };
        // Each object's bounding box above the ground: (lowest corner, highest corner).
        let casters: Vec<(Vec3, Vec3)> = (0..self.objects.len())
            .filter(|&i| i != ground_index)
            .map(|i| self.bounding_box(i))
            .filter(|&(_, high)| high.y > height)
            .map(|(low, high)| (low.max(Vec3::new(f32::MIN, height, f32::MIN)), high))
            .collect();
        let mut min = Vec2::INFINITY;
        let mut max = Vec2::NEG_INFINITY;
        for light in shadowed.iter().map(|&i| &self.lights[i]) {
            if light.position.y <= height {
                continue;
            }
            let lowest = light.position.y - light.radius;
            if casters.iter().any(|&(_, top)| top.y >= lowest) {
                return Some(square);
            }
            for &(low, high) in &casters {
                for l in box_corners(light.position - light.radius, light.position + light.radius) {
                    for p in box_corners(low, high) {
                        let x = l + (p - l) * ((l.y - height) / (l.y - p.y));
                        min = min.min(x.xz());
                        max = max.max(x.xz());
                    }
                }
            }
        }
        let rect = GroundRect {
            min: min.max(square.min),
            max: max.min(square.max),
        };
        rect.min.cmple(rect.max).all().then_some(rect)
    }
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use glam::{Vec2, Vec3, Vec3Swizzles};

    use super::GroundRect;
    use crate::rng::Rng;
    use crate::scene::{Scene, DEFAULT_SCENE_TOML};

    fn contains(rect: &GroundRect, x: Vec2) -> bool {
        x.cmpge(rect.min).all() && x.cmple(rect.max).all()
    }

    fn default_scene() -> Scene {
        Scene::from_toml(DEFAULT_SCENE_TOML, "default", Path::new("")).expect("the default scene")
    }

    /// Whether the segment from a to b passes through the box from `low` to `high` (slabs).
    fn segment_hits(a: Vec3, b: Vec3, (low, high): (Vec3, Vec3)) -> bool {
        let d = b - a;
        let (t0, t1) = ((low - a) / d, (high - a) / d);
        let (enter, leave) = (t0.min(t1).max_element().max(0.0), t0.max(t1).min_element().min(1.0));
        enter <= leave
    }

    /// Outside the rectangle, no segment from a ground point to a point of the light's
    /// sphere passes through an object's bounding box; inside it, some points are
    /// shadowed, and the rectangle is a small part of the default scene's ground.
    #[test]
    fn outside_the_rectangle_every_light_is_seen_whole() {
        let scene = default_scene();
        let rect = scene.ground_shadow_rect(&[0]).expect("the objects shadow the ground");
        let ground_index = scene.ground_index().expect("a ground");
        let ground = &scene.objects[ground_index];
        let light = &scene.lights[0];
        let boxes: Vec<(Vec3, Vec3)> =
            (0..scene.objects.len()).filter(|&i| i != ground_index).map(|i| scene.bounding_box(i)).collect();
        let mut rng = Rng::new(7);
        let mut signed = || rng.uniform() as f32 * 2.0 - 1.0;
        let (mut outside, mut shadowed_inside) = (0, 0);
        for _ in 0..4000 {
            let xz = ground.position.xz() + Vec2::new(signed(), signed()) * ground.scale;
            let x = Vec3::new(xz.x, ground.position.y, xz.y);
            let shadowed = (0..64).any(|_| {
                let l = light.position + Vec3::new(signed(), signed(), signed()).clamp_length_max(1.0) * light.radius;
                boxes.iter().any(|&b| segment_hits(x, l, b))
            });
            if contains(&rect, xz) {
                shadowed_inside += usize::from(shadowed);
            } else {
                outside += 1;
                assert!(!shadowed, "{xz} is outside {rect:?} but shadowed");
            }
        }
        assert!(outside > 3000 && shadowed_inside > 50, "{outside} outside, {shadowed_inside} shadowed inside");
        let area = |min: Vec2, max: Vec2| (max - min).x * (max - min).y;
        assert!(area(rect.min, rect.max) < 0.25 * area(Vec2::splat(-ground.scale), Vec2::splat(ground.scale)));
    }

    /// An object as high as the light's lowest point may shadow the ground to its horizon;
    /// a light below the ground, or no shadowed light, shadows nothing.
    #[test]
    fn a_light_as_low_as_an_object_takes_the_whole_square_and_none_takes_nothing() {
        let mut scene = default_scene();
        let ground = *scene.ground().expect("a ground");
        assert_eq!(scene.ground_shadow_rect(&[]), None);
        scene.lights[0].position.y = 1.2;
        let rect = scene.ground_shadow_rect(&[0]).expect("the whole square");
        assert_eq!((rect.min, rect.max), (ground.position.xz() - ground.scale, ground.position.xz() + ground.scale));
        scene.lights[0].position.y = ground.position.y - 1.0;
        assert_eq!(scene.ground_shadow_rect(&[0]), None);
    }
}

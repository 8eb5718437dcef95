//! Which lights' shadows can fall on which objects: a convex solid cannot shadow itself, so
//! one that no other object can stand in front of, seen from any point of a light's
//! sphere, is lit whole by that light. A draw holds shadow code only if some light may
//! shadow it, and runs it only for those lights (src/render/forward.rs): in the default
//! scene the ball, a fifth of the frame's pixels, holds none.

use glam::Vec3;

use super::{MeshExtent, Scene};

/// The most objects a scene may have for [`Scene::shadowing_lights`] to test them: it weighs
/// every pair, at every change of the lights or objects (0.6 s at 10,000 objects, where the
/// viewer moves one a frame); beyond this count every object is taken to be shadowable.
pub const MAX_SHADOW_RECEIVER_OBJECTS: usize = 256;

impl Scene {
    /// Which of the lights `shadowed` (indices into `lights`, below 32) may cast a shadow on
    /// a point of object `receiver`, as bit i for light i: every one where the object is not
    /// convex ([`super::Mesh::is_convex`]); else each where another object may stand
    /// between one of its points and a point of the light's sphere. Every such segment lies
    /// in the convex hull of the receiver's bounding box and the light's, so an object
    /// apart from that hull casts nothing on it: its bounding box apart from the hull's
    /// along an axis (touching does not shadow: the ground under an object resting on it),
    /// or its bounding sphere apart from the capsule about the light's centre and the
    /// receiver's bounding sphere's, as wide as the wider of the two, which holds the hull.
    /// `extent` gives each mesh's. In a scene of more than [`MAX_SHADOW_RECEIVER_OBJECTS`]
    /// every light may.
    pub fn shadowing_lights(&self, receiver: usize, shadowed: &[usize], extent: impl Fn(usize) -> MeshExtent) -> u32 {
        let world = |i: usize| {
            let o = &self.objects[i];
            let e = o.world_extent(&extent(o.mesh));
            (e.low, e.high, e.centre, e.radius, e.convex)
        };
        let (low, high, centre, radius, convex) = world(receiver);
        if !convex || self.objects.len() > MAX_SHADOW_RECEIVER_OBJECTS {
            return light_bits(shadowed.iter().copied());
        }
        let others: Vec<_> = (0..self.objects.len()).filter(|&i| i != receiver).map(world).collect();
        let casts = |&i: &usize| {
            let light = &self.lights[i];
            let hull_low = low.min(light.position - light.radius);
            let hull_high = high.max(light.position + light.radius);
            let reach = light.radius.max(radius);
            others.iter().any(|&(o_low, o_high, o_centre, o_radius, _)| {
                let apart_on_an_axis = (o_low.cmpge(hull_high) | o_high.cmple(hull_low)).any();
                let apart_from_the_capsule =
                    segment_distance(o_centre, light.position, centre) >= o_radius + reach;
                !(apart_on_an_axis || apart_from_the_capsule)
            })
        };
        light_bits(shadowed.iter().copied().filter(casts))
    }
}

/// Bit i set for each light i.
fn light_bits(lights: impl Iterator<Item = usize>) -> u32 {
    lights.fold(0, |bits, i| bits | 1 << i)
}

/// The distance from p to the segment from a to b.
fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    p.distance(a + ab * t)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use glam::Vec3;

    use super::super::{MeshExtent, Object, Scene};
    use super::MAX_SHADOW_RECEIVER_OBJECTS;

    /// Each object's lights that may shadow it, as bits.
    fn shadowing(scene: &Scene) -> Vec<u32> {
        let extents: Vec<MeshExtent> = scene.meshes.iter().map(|m| m.extent()).collect();
        let lights: Vec<usize> = (0..scene.lights.len()).filter(|&i| scene.lights[i].shadows).collect();
        (0..scene.objects.len()).map(|i| scene.shadowing_lights(i, &lights, |m| extents[m])).collect()
    }

    fn shadowed(scene: &Scene) -> Vec<bool> {
        shadowing(scene).into_iter().map(|bits| bits != 0).collect()
    }

    /// In the default scene the ball, convex and away from the torus, resting on the ground,
    /// is lit whole; the torus shadows itself, the ball shadows the ground.
    #[test]
    fn the_default_scenes_ball_is_lit_whole() {
        let mut scene = Scene::default_scene();
        assert_eq!(shadowed(&scene), [false, true, true]);
        // Between the light and the ball, the torus may shadow it.
        scene.objects[1].position = Vec3::new(-2.5, 2.0, 1.6);
        assert_eq!(shadowed(&scene), [true, true, true]);
        // A light that casts no shadow shadows nothing.
        scene.lights[0].shadows = false;
        assert_eq!(shadowed(&scene), [false, false, false]);
    }

    /// Each light is weighed alone: a second light beyond the torus, which may stand between
    /// it and the ball, may shadow the ball, while the key light still cannot.
    #[test]
    fn each_light_may_shadow_an_object_or_not() {
        let mut scene = Scene::default_scene();
        let mut fill = scene.lights[0];
        fill.position = Vec3::new(5.0, 1.0, -2.0);
        scene.lights.push(fill);
        assert_eq!(shadowing(&scene), [0b10, 0b11, 0b11]);
        scene.lights[1].shadows = false;
        assert_eq!(shadowing(&scene), [0b00, 0b01, 0b01]);
    }

    /// Two balls side by side under a light above them: apart along an axis, neither shadows
    /// the other, until the light's sphere grows as wide as the gap (the test is
    /// conservative: over both, it may), or the light moves so that one stands between it
    /// and the other; a ball reaching below the ground's plane is shadowed by the ground.
    #[test]
    fn a_ball_is_shadowed_where_another_can_stand_in_front_of_the_lights_sphere() {
        let text = |light: [f32; 3], radius: f32, y: f32| {
            format!(
                "[camera]\nposition = [0.0, 2.0, 8.0]\ntarget = [0.0, 0.0, 0.0]\n\
                 [[lights]]\nkind = \"point\"\nposition = {light:?}\nintensity = [10.0, 10.0, 10.0]\n\
                 radius = {radius}\n\
                 [[objects]]\nmesh = \"builtin:sphere\"\nposition = [-1.5, {y}, 0.0]\n\
                 [[objects]]\nmesh = \"builtin:sphere\"\nposition = [1.5, 1.0, 0.0]\n\
                 [[objects]]\nmesh = \"builtin:plane\"\nscale = 5.0\n"
            )
        };
        let scene = |light, radius, y| Scene::from_toml(&text(light, radius, y), "scene.toml", Path::new("")).unwrap();
        assert_eq!(shadowed(&scene([0.0, 6.0, 0.0], 0.2, 1.0)), [false, false, true]);
        assert_eq!(shadowed(&scene([0.0, 6.0, 0.0], 3.0, 1.0)), [true, true, true]);
        assert_eq!(shadowed(&scene([6.0, 1.0, 0.0], 0.2, 1.0)), [true, false, true]);
        assert_eq!(shadowed(&scene([0.0, 6.0, 0.0], 0.2, 0.5)), [true, false, true]);
        let mut crowded = scene([0.0, 6.0, 0.0], 0.2, 1.0);
        let far = crowded.objects[1];
        crowded.objects.extend((0..MAX_SHADOW_RECEIVER_OBJECTS).map(|k| Object {
            position: Vec3::new(100.0 + k as f32 * 3.0, 1.0, 0.0),
            ..far
        }));
        assert!(shadowed(&crowded).iter().all(|&s| s), "beyond the count, every object may be shadowed");
    }
}

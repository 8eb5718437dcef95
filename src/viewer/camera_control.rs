//! The viewer's camera control, without a window: fly and orbit modes driven by an
//! [`Input`] snapshot per frame, key bindings, and framing the scene. The window code only
//! turns events into an `Input`.
//!
//! The scene camera (position + target) stays the only state: each update derives yaw and
//! pitch from it and writes it back only when the input moved it, so an idle viewer renders
//! exactly the camera of the file.

use glam::{Vec2, Vec3};
use winit::keyboard::KeyCode;

use crate::scene::{Camera, Scene};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Move freely: WASD along the view, Q/E down/up, right button to look around.
    Fly,
    /// Circle the selected object: right button to orbit, wheel and W/S to zoom.
    Orbit,
}

/// What the user did since the last frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Input {
    /// Movement along the camera's right, the world's up and the camera's forward axis,
    /// each component in [-1, 1].
    pub movement: Vec3,
    /// Mouse motion in pixels while the look button is held (+x right, +y down).
    pub look: Vec2,
    /// Wheel notches, positive away from the user.
    pub wheel: f32,
    /// Shift held: move faster.
    pub fast: bool,
}

/// Radians of turn per pixel of mouse motion.
const LOOK_RADIANS_PER_PIXEL: f32 = 0.004;
/// Shift multiplies speeds by this.
const FAST_FACTOR: f32 = 4.0;
/// Each wheel notch multiplies the fly speed by this (and divides the orbit distance).
const WHEEL_FACTOR: f32 = 1.25;
/// Fly speeds, in scene units per second.
const MIN_SPEED: f32 = 0.05;
const MAX_SPEED: f32 = 200.0;
/// Pitch stays this far from straight up/down, where yaw is undefined.
const MAX_PITCH: f32 = 89.0 * std::f32::consts::PI / 180.0;
/// Orbit keys turn this many radians per second.
const ORBIT_KEY_RADIANS_PER_SECOND: f32 = 1.5;
/// The orbit camera stays this far from its pivot (a few near-plane distances).
const MIN_ORBIT_DISTANCE: f32 = 4.0 * Camera::NEAR;
/// The orbit camera stays this far above the ground, so the near plane does not cut it.
const FLOOR_CLEARANCE: f32 = 2.0 * Camera::NEAR;
/// An object this flat (height over its largest extent) is ground, not a thing to frame.
const GROUND_FLATNESS: f32 = 1e-3;

/// Unit direction for yaw (about +y, 0 = looking down -z, positive turns right) and pitch.
fn direction(yaw: f32, pitch: f32) -> Vec3 {
    Vec3::new(pitch.cos() * yaw.sin(), pitch.sin(), -pitch.cos() * yaw.cos())
}

/// Yaw and pitch of a unit direction (inverse of [`direction`]).
fn angles(dir: Vec3) -> (f32, f32) {
    (dir.x.atan2(-dir.z), dir.y.clamp(-1.0, 1.0).asin())
}

pub struct CameraControl {
    pub mode: Mode,
    /// Fly speed, scene units per second.
    pub speed: f32,
    /// The top of the ground, which the orbit camera stays above.
    pub floor: Option<f32>,
}

impl Default for CameraControl {
    fn default() -> Self {
        Self {
            mode: Mode::Fly,
            speed: 2.0,
            floor: None,
        }
    }
}

impl CameraControl {
    pub fn toggle_mode(&mut self) {
        self.mode = match self.mode {
            Mode::Fly => Mode::Orbit,
            Mode::Orbit => Mode::Fly,
        };
    }

    /// Moves `camera` by `input` over `dt` seconds; in orbit mode around `pivot`. Returns
    /// whether the camera changed.
    pub fn update(&mut self, camera: &mut Camera, pivot: Vec3, input: &Input, dt: f32) -> bool {
        let before = *camera;
        match self.mode {
            Mode::Fly => self.fly(camera, input, dt),
            Mode::Orbit => self.orbit(camera, pivot, input, dt),
        }
        *camera != before
    }

    fn fly(&mut self, camera: &mut Camera, input: &Input, dt: f32) {
        if input.wheel != 0.0 {
            self.speed = (self.speed * WHEEL_FACTOR.powf(input.wheel)).clamp(MIN_SPEED, MAX_SPEED);
        }
        let offset = camera.target - camera.position;
        let distance = offset.length();
        let mut forward = offset / distance;
        if input.look != Vec2::ZERO {
            let (yaw, pitch) = angles(forward);
            let yaw = yaw + input.look.x * LOOK_RADIANS_PER_PIXEL;
            let pitch = (pitch - input.look.y * LOOK_RADIANS_PER_PIXEL).clamp(-MAX_PITCH, MAX_PITCH);
            forward = direction(yaw, pitch);
            camera.target = camera.position + forward * distance;
        }
        if input.movement != Vec3::ZERO {
            // Straight up or down, "right" follows the yaw the view came from.
            let right = forward.cross(Vec3::Y).try_normalize().unwrap_or(Vec3::X);
            let step = self.speed * dt * if input.fast { FAST_FACTOR } else { 1.0 };
            let delta = (right * input.movement.x + Vec3::Y * input.movement.y + forward * input.movement.z) * step;
            camera.position += delta;
            camera.target += delta;
        }
    }

    fn orbit(&mut self, camera: &mut Camera, pivot: Vec3, input: &Input, dt: f32) {
        let offset = camera.position - pivot;
        let distance = offset.length();
        let looking_at_pivot = camera.target == pivot;
        if looking_at_pivot && input == &Input::default() {
            return;
        }
        let (mut yaw, mut pitch) = angles(offset.try_normalize().unwrap_or(Vec3::Z));
        let turn = ORBIT_KEY_RADIANS_PER_SECOND * dt * if input.fast { FAST_FACTOR } else { 1.0 };
        // Dragging right carries the camera left around the pivot, so the object follows the mouse.
        yaw -= input.look.x * LOOK_RADIANS_PER_PIXEL + input.movement.x * turn;
        pitch = (pitch + input.look.y * LOOK_RADIANS_PER_PIXEL + input.movement.y * turn).clamp(-MAX_PITCH, MAX_PITCH);
        let zoom = WHEEL_FACTOR.powf(-input.wheel) * (1.0 - input.movement.z * turn).max(0.1);
        let distance = (distance.max(MIN_ORBIT_DISTANCE) * zoom).max(MIN_ORBIT_DISTANCE);
        if let Some(floor) = self.floor {
            // Lowest pitch that keeps the camera a near-plane distance above the ground.
            let lowest = ((floor + FLOOR_CLEARANCE - pivot.y) / distance).clamp(-1.0, 1.0).asin();
            pitch = pitch.max(lowest).min(MAX_PITCH);
        }
        camera.position = pivot + direction(yaw, pitch) * distance;
        camera.target = pivot;
    }
}

/// Movement axes from the held keys: D/A right/left, E/Q up/down, W/S forward/back.
pub fn movement_from_keys(held: impl Fn(KeyCode) -> bool) -> Vec3 {
    let axis = |plus: KeyCode, minus: KeyCode| f32::from(u8::from(held(plus))) - f32::from(u8::from(held(minus)));
    Vec3::new(
        axis(KeyCode::KeyD, KeyCode::KeyA),
        axis(KeyCode::KeyE, KeyCode::KeyQ),
        axis(KeyCode::KeyW, KeyCode::KeyS),
    )
}

/// The world-space bounding box of `object`.
fn object_box(scene: &Scene, object: usize) -> (Vec3, Vec3) {
    let o = &scene.objects[object];
    let (min, max) = scene.meshes[o.mesh]
        .vertices
        .iter()
        .map(|v| Vec3::from(v.position))
        .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| {
            (lo.min(p), hi.max(p))
        });
    (o.position + min * o.scale, o.position + max * o.scale)
}

/// A sphere around everything that `object` draws, in world space.
pub fn object_bounds(scene: &Scene, object: usize) -> (Vec3, f32) {
    let (min, max) = object_box(scene, object);
    ((min + max) * 0.5, (max - min).length() * 0.5)
}

/// Whether `object` is ground: flat and level, like the builtin plane.
fn is_ground(scene: &Scene, object: usize) -> bool {
    let size = {
        let (min, max) = object_box(scene, object);
        max - min
    };
    size.y <= GROUND_FLATNESS * size.max_element()
}

/// The top of the highest ground object, if the scene has one.
pub fn floor_height(scene: &Scene) -> Option<f32> {
    (0..scene.objects.len())
        .filter(|&i| is_ground(scene, i))
        .map(|i| object_box(scene, i).1.y)
        .reduce(f32::max)
}

/// A sphere around the objects that are not ground (all of them if every one is).
pub fn objects_bounds(scene: &Scene) -> (Vec3, f32) {
    let all: Vec<usize> = (0..scene.objects.len()).collect();
    let things: Vec<usize> = all.iter().copied().filter(|&i| !is_ground(scene, i)).collect();
    let chosen = if things.is_empty() { &all } else { &things };
    let spheres: Vec<(Vec3, f32)> = chosen.iter().map(|&i| object_bounds(scene, i)).collect();
    let (min, max) = spheres
        .iter()
        .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), (c, r)| {
            (lo.min(*c - *r), hi.max(*c + *r))
        });
    let centre = (min + max) * 0.5;
    let radius = spheres.iter().map(|(c, r)| c.distance(centre) + r).fold(0.0, f32::max);
    (centre, radius)
}

/// `camera` moved along its view direction so that the sphere (`centre`, `radius`) fills
/// the view at `aspect` (width / height), looking at its centre.
pub fn frame_sphere(camera: &Camera, centre: Vec3, radius: f32, aspect: f32) -> Camera {
    let half_y = camera.fov_y_degrees.to_radians() * 0.5;
    let half_x = (half_y.tan() * aspect.max(1e-3)).atan();
    let distance = (radius.max(Camera::NEAR) / half_y.min(half_x).sin()).max(MIN_ORBIT_DISTANCE);
    let forward = (camera.target - camera.position).try_normalize().unwrap_or(Vec3::NEG_Z);
    Camera {
        position: centre - forward * distance,
        target: centre,
        ..*camera
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(0.0, 1.0, 5.0),
            target: Vec3::new(0.0, 1.0, 0.0),
            fov_y_degrees: 30.0,
            near: Camera::NEAR,
            far: Camera::FAR,
        }
    }

    fn close(a: Vec3, b: Vec3) -> bool {
        a.distance(b) < 1e-4
    }

    #[test]
    fn idle_input_leaves_the_camera_bit_for_bit() {
        for mode in [Mode::Fly, Mode::Orbit] {
            let mut control = CameraControl {
                mode,
                ..Default::default()
            };
            let mut cam = camera();
            // In orbit mode the pivot is the target, as after the first orbit frame.
            let pivot = cam.target;
            let changed = control.update(&mut cam, pivot, &Input::default(), 0.016);
            assert!(!changed);
            assert_eq!(cam, camera());
        }
    }

    #[test]
    fn fly_moves_along_the_view_and_keeps_looking_the_same_way() {
        let mut control = CameraControl::default();
        let mut cam = camera();
        let input = Input {
            movement: Vec3::new(0.0, 0.0, 1.0),
            ..Default::default()
        };
        assert!(control.update(&mut cam, Vec3::ZERO, &input, 0.5));
        // speed 2 for 0.5 s towards -z.
        assert!(close(cam.position, Vec3::new(0.0, 1.0, 4.0)), "{cam:?}");
        assert!(close(cam.target - cam.position, camera().target - camera().position));
        let fast = Input {
            movement: Vec3::new(1.0, 1.0, 0.0),
            fast: true,
            ..Default::default()
        };
        let before = cam.position;
        control.update(&mut cam, Vec3::ZERO, &fast, 0.25);
        // Right is +x looking down -z; Q/E move along world up; shift is 4x.
        assert!(close(cam.position - before, Vec3::new(2.0, 2.0, 0.0)), "{cam:?}");
    }

    #[test]
    fn mouse_right_turns_right_and_pitch_stops_short_of_vertical() {
        let mut control = CameraControl::default();
        let mut cam = camera();
        let input = Input {
            look: Vec2::new(100.0, 0.0),
            ..Default::default()
        };
        control.update(&mut cam, Vec3::ZERO, &input, 0.016);
        let forward = (cam.target - cam.position).normalize();
        assert!(forward.x > 0.3 && forward.y.abs() < 1e-5, "{forward}");
        assert!(
            (cam.target.distance(cam.position) - 5.0).abs() < 1e-4,
            "distance to the target is kept"
        );
        let up = Input {
            look: Vec2::new(0.0, -1e5),
            ..Default::default()
        };
        control.update(&mut cam, Vec3::ZERO, &up, 0.016);
        let forward = (cam.target - cam.position).normalize();
        assert!(forward.y > 0.99 && forward.y < 0.9999, "{forward}");
        assert!(cam.view().is_finite());
    }

    #[test]
    fn wheel_changes_fly_speed_within_bounds() {
        let mut control = CameraControl::default();
        let mut cam = camera();
        control.update(
            &mut cam,
            Vec3::ZERO,
            &Input {
                wheel: 2.0,
                ..Default::default()
            },
            0.016,
        );
        assert!((control.speed - 2.0 * 1.25 * 1.25).abs() < 1e-5);
        control.update(
            &mut cam,
            Vec3::ZERO,
            &Input {
                wheel: -1000.0,
                ..Default::default()
            },
            0.016,
        );
        assert_eq!(control.speed, MIN_SPEED);
        assert_eq!(cam, camera(), "the wheel changes the speed, not the camera");
    }

    #[test]
    fn orbit_looks_at_the_pivot_and_keeps_its_distance() {
        let mut control = CameraControl {
            mode: Mode::Orbit,
            ..Default::default()
        };
        let mut cam = camera();
        let pivot = Vec3::new(1.0, 0.0, 0.0);
        assert!(
            control.update(&mut cam, pivot, &Input::default(), 0.016),
            "switching to orbit looks at the pivot"
        );
        assert_eq!(cam.target, pivot);
        let distance = cam.position.distance(pivot);
        control.update(
            &mut cam,
            pivot,
            &Input {
                look: Vec2::new(300.0, 50.0),
                ..Default::default()
            },
            0.016,
        );
        assert!((cam.position.distance(pivot) - distance).abs() < 1e-4);
        assert_eq!(cam.target, pivot);
        control.update(
            &mut cam,
            pivot,
            &Input {
                wheel: 1.0,
                ..Default::default()
            },
            0.016,
        );
        assert!((cam.position.distance(pivot) - distance / 1.25).abs() < 1e-4);
        control.update(
            &mut cam,
            pivot,
            &Input {
                wheel: 1000.0,
                ..Default::default()
            },
            0.016,
        );
        assert!(cam.position.distance(pivot) >= MIN_ORBIT_DISTANCE * 0.999);
        assert!(cam.view().is_finite());
    }

    #[test]
    fn tab_style_toggle_alternates_modes() {
        let mut control = CameraControl::default();
        control.toggle_mode();
        assert_eq!(control.mode, Mode::Orbit);
        control.toggle_mode();
        assert_eq!(control.mode, Mode::Fly);
    }

    #[test]
    fn keys_map_to_axes_and_opposite_keys_cancel() {
        let held = |keys: &'static [KeyCode]| move |k: KeyCode| keys.contains(&k);
        assert_eq!(
            movement_from_keys(held(&[KeyCode::KeyW, KeyCode::KeyD])),
            Vec3::new(1.0, 0.0, 1.0)
        );
        assert_eq!(
            movement_from_keys(held(&[KeyCode::KeyS, KeyCode::KeyQ, KeyCode::KeyA])),
            Vec3::new(-1.0, -1.0, -1.0)
        );
        assert_eq!(movement_from_keys(held(&[KeyCode::KeyE, KeyCode::KeyQ])), Vec3::ZERO);
    }

    #[test]
    fn framing_puts_the_whole_sphere_in_view() {
        let cam = camera();
        for aspect in [0.5, 1.0, 2.0] {
            let framed = frame_sphere(&cam, Vec3::new(3.0, 0.0, -2.0), 2.0, aspect);
            assert_eq!(framed.target, Vec3::new(3.0, 0.0, -2.0));
            let forward = (framed.target - framed.position).normalize();
            assert!(close(forward, Vec3::NEG_Z), "the view direction is kept");
            // Points on the sphere's silhouette project inside [-1, 1].
            let clip = framed.projection(aspect) * framed.view();
            for offset in [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y] {
                let p = clip * (framed.target + offset * 2.0).extend(1.0);
                let ndc = p.truncate() / p.w;
                assert!(
                    ndc.x.abs() <= 1.0 + 1e-4 && ndc.y.abs() <= 1.0 + 1e-4,
                    "{aspect}: {ndc}"
                );
            }
        }
    }

    #[test]
    fn framing_covers_the_clay_and_leaves_out_the_ground() {
        let scene = Scene::default_scene();
        let (centre, radius) = objects_bounds(&scene);
        let ground = scene.objects.len() - 1;
        assert!(is_ground(&scene, ground) && !is_ground(&scene, 0) && !is_ground(&scene, 1));
        for i in 0..ground {
            let (c, r) = object_bounds(&scene, i);
            assert!(c.distance(centre) + r <= radius + 1e-4);
        }
        // The 16-unit plane would need a radius over 11; the ball and the ring need < 4.
        assert!(radius < 4.0, "radius {radius}");
        assert_eq!(floor_height(&scene), Some(-1.0));
        // The sphere is the unit sphere at its object's position.
        let (c, r) = object_bounds(&scene, 0);
        assert!(
            close(c, scene.objects[0].position) && (r - 3f32.sqrt()).abs() < 1e-4,
            "{c} {r}"
        );
    }

    #[test]
    fn the_orbit_camera_stays_above_the_floor() {
        let mut control = CameraControl {
            mode: Mode::Orbit,
            floor: Some(-1.0),
            ..Default::default()
        };
        let mut cam = camera();
        let pivot = Vec3::new(0.0, -0.5, 0.0);
        for _ in 0..20 {
            control.update(
                &mut cam,
                pivot,
                &Input {
                    look: Vec2::new(0.0, -400.0),
                    ..Default::default()
                },
                0.016,
            );
            assert!(cam.position.y >= -1.0 + FLOOR_CLEARANCE - 1e-4, "{cam:?}");
        }
        assert!(
            cam.position.y <= -1.0 + FLOOR_CLEARANCE + 1e-3,
            "it went as low as it could: {cam:?}"
        );
        assert!((cam.position.distance(pivot) - camera().position.distance(pivot)).abs() < 1e-3);
    }
}

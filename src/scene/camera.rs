use glam::{Mat4, UVec2, Vec3, Vec4Swizzles};

use super::mesh::box_corners;

/// A right-handed, y-up perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub target: Vec3,
    /// Vertical field of view, in degrees, in (0, 180).
    pub fov_y_degrees: f32,
    /// Clipping distances in world units, 0 < near < far: [`Camera::NEAR`] and
    /// [`Camera::FAR`] for scene files, from its bounds for a model opened alone.
    pub near: f32,
    pub far: f32,
}

impl Camera {
    /// Near clipping distance of scene files, in world units.
    pub const NEAR: f32 = 0.05;
    /// Far clipping distance of scene files, in world units.
    pub const FAR: f32 = 200.0;

    /// World-to-view matrix (right-handed look-at, +y up; the camera looks
    /// down its -z axis).
    ///
    /// When looking straight up or down, +y cannot serve as the up vector, so
    /// the screen's up becomes the horizontal direction the view was tilting
    /// away from (-z looking down, +z looking up).
    pub fn view(&self) -> Mat4 {
        let forward = (self.target - self.position).normalize_or(Vec3::NEG_Z);
        let up = if forward.y.abs() > 0.9999 {
            Vec3::new(0.0, 0.0, forward.y.signum())
        } else {
            Vec3::Y
        };
        Mat4::look_at_rh(self.position, self.position + forward, up)
    }

    /// World-to-clip matrix: [`Camera::projection`] after [`Camera::view`].
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view()
    }

    /// View-to-clip matrix for Vulkan: depth 0 at `near` and 1 at `far`, and y negated because Vulkan's NDC +y points down the
    /// screen, so world-up stays up on screen.
    ///
    /// `aspect` is width / height; a non-positive or non-finite aspect (a
    /// minimised window) is treated as 1 so the matrix stays finite.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let mut projection =
            Mat4::perspective_rh(self.fov_y_degrees.to_radians(), usable_aspect(aspect), self.near, self.far);
        projection.y_axis.y = -projection.y_axis.y;
        projection
    }

    /// Whether every pixel's view ray starts outside the sphere: the rays start on the
    /// near plane's visible rectangle, whose corners are its farthest points from the eye.
    /// The sphere must clear that distance by a thousandth, for the rounding of its radius.
    pub fn sees_from_outside(&self, aspect: f32, centre: Vec3, radius: f32) -> bool {
        let aspect = usable_aspect(aspect);
        let tan_half_fov = (self.fov_y_degrees.to_radians() * 0.5).tan();
        let near_corner = self.near * (1.0 + tan_half_fov * tan_half_fov * (1.0 + aspect * aspect)).sqrt();
        (centre - self.position).length() > (radius + near_corner) * 1.001
    }

    /// The pixels of a frame `height` pixels high that the outline of a sphere covers, as
    /// the disc of its radius at its distance: infinite with the eye inside it.
    pub fn sphere_pixels(&self, height: u32, centre: Vec3, radius: f32) -> f32 {
        let distance = (centre - self.position).length();
        if distance <= radius {
            return f32::INFINITY;
        }
        let tan_half_fov = (self.fov_y_degrees.to_radians() * 0.5).tan();
        let radius_pixels = radius / (distance * tan_half_fov) * height as f32 * 0.5;
        std::f32::consts::PI * radius_pixels * radius_pixels
    }

    /// The pixels of a `width` × `height` frame that a sphere's outline may cover, as the
    /// half-open rectangle [min, max), empty where none: those of its box in view space.
    pub fn sphere_pixel_bounds(&self, width: u32, height: u32, centre: Vec3, radius: f32) -> (UVec2, UVec2) {
        let view_centre = self.view().transform_point3(centre);
        let corners = box_corners(view_centre - radius, view_centre + radius);
        self.pixel_bounds(width, height, corners)
    }

    /// The pixels of a `width` × `height` frame that an axis-aligned box of the world, from
    /// corner `low` to `high`, may cover, as [`Camera::sphere_pixel_bounds`] has them.
    pub fn box_pixel_bounds(&self, width: u32, height: u32, low: Vec3, high: Vec3) -> (UVec2, UVec2) {
        let view = self.view();
        self.pixel_bounds(width, height, box_corners(low, high).map(|p| view.transform_point3(p)))
    }

    /// The pixels that the convex hull of `corners` (in view space) may cover: their
    /// projections' bounds, a pixel wider on each side for rounding; the whole frame where
    /// one lies short of the near plane, in front of which projection holds no bound.
    fn pixel_bounds(&self, width: u32, height: u32, corners: [Vec3; 8]) -> (UVec2, UVec2) {
        let size = UVec2::new(width, height);
        if corners.iter().any(|p| !p.is_finite() || p.z >= -self.near) {
            return (UVec2::ZERO, size);
        }
        let projection = self.projection(width as f32 / height as f32);
        let (mut low, mut high) = (glam::Vec2::INFINITY, glam::Vec2::NEG_INFINITY);
        for p in corners {
            let clip = projection * p.extend(1.0);
            let ndc = clip.xy() / clip.w;
            low = low.min(ndc);
            high = high.max(ndc);
        }
        let pixels = |ndc: glam::Vec2| (ndc * 0.5 + 0.5) * size.as_vec2();
        let clamp = |p: glam::Vec2| p.max(glam::Vec2::ZERO).min(size.as_vec2()).as_uvec2();
        let (min, max) = (clamp((pixels(low) - 1.0).floor()), clamp((pixels(high) + 1.0).ceil()));
        (min, max.max(min))
    }
}

/// `aspect`, or 1 where it is non-positive or non-finite (a minimised window).
fn usable_aspect(aspect: f32) -> f32 {
    if aspect.is_finite() && aspect > 0.0 {
        aspect
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3Swizzles;

    /// Normalised device coordinates of a world-space point. In Vulkan, x = -1
    /// is the left of the screen, y = -1 the top, and depth runs 0..1.
    fn ndc(camera: &Camera, aspect: f32, point: Vec3) -> Vec3 {
        let clip = camera.projection(aspect) * camera.view() * point.extend(1.0);
        clip.xyz() / clip.w
    }

    const CAMERA: Camera = Camera {
        position: Vec3::new(1.0, 2.0, 6.0),
        target: Vec3::new(0.0, 0.5, 0.0),
        fov_y_degrees: 30.0,
        near: Camera::NEAR,
        far: Camera::FAR,
    };

    #[test]
    fn target_projects_to_the_centre() {
        let p = ndc(&CAMERA, 16.0 / 9.0, CAMERA.target);
        assert!(p.x.abs() < 1e-5 && p.y.abs() < 1e-5, "{p}");
        assert!(p.z > 0.0 && p.z < 1.0, "{p}");
    }

    #[test]
    fn up_is_up_and_right_is_right_on_screen() {
        let above = ndc(&CAMERA, 1.5, CAMERA.target + Vec3::Y * 0.5);
        assert!(above.y < -0.1 && above.x.abs() < 1e-5, "{above}");
        // The camera sits at +x and +z of the target, so world +x is
        // towards the right of the screen.
        let right = ndc(&CAMERA, 1.5, CAMERA.target + Vec3::X * 0.5);
        assert!(right.x > 0.1, "{right}");
    }

    /// A sphere's outline in pixels is the disc of the radius that a point a radius above
    /// its centre, across the view, projects to; the eye inside it sees it everywhere.
    #[test]
    fn a_spheres_pixels_are_its_projected_disc() {
        let (centre, radius, height) = (CAMERA.target, 0.4, 720);
        let view = CAMERA.target - CAMERA.position;
        let above = centre + view.cross(Vec3::Y).cross(view).normalize() * radius;
        let radius_pixels = ndc(&CAMERA, 1.0, above).y.abs() * height as f32 * 0.5;
        let expected = std::f32::consts::PI * radius_pixels * radius_pixels;
        let pixels = CAMERA.sphere_pixels(height, centre, radius);
        assert!((pixels / expected - 1.0).abs() < 1e-4, "{pixels} against {expected}");
        assert_eq!(CAMERA.sphere_pixels(height, CAMERA.position, radius), f32::INFINITY);
    }

    /// A sphere's pixel bounds hold every point of it that projects into the frame, within a
    /// few pixels of its outermost; the whole frame with the eye at its surface, none where
    /// it lies beside the frame.
    #[test]
    fn a_spheres_pixel_bounds_hold_its_outline() {
        let (width, height) = (1280, 720);
        let size = glam::Vec2::new(width as f32, height as f32);
        let spheres = [(CAMERA.target, 0.4), (Vec3::new(-1.5, 0.0, 2.0), 0.7), (Vec3::new(2.0, 1.0, -3.0), 1.5)];
        for (centre, radius) in spheres {
            let (min, max) = CAMERA.sphere_pixel_bounds(width, height, centre, radius);
            let (mut low, mut high) = (size, glam::Vec2::ZERO);
            for i in 0..64 {
                for j in 0..=32 {
                    let phi = i as f32 / 64.0 * std::f32::consts::TAU;
                    let theta = j as f32 / 32.0 * std::f32::consts::PI;
                    let d = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
                    let p = (ndc(&CAMERA, width as f32 / height as f32, centre + d * radius).xy() * 0.5 + 0.5) * size;
                    let p = p.clamp(glam::Vec2::ZERO, size);
                    assert!(p.cmpge(min.as_vec2()).all() && p.cmple(max.as_vec2()).all(), "{p} outside {min}..{max}");
                    (low, high) = (low.min(p), high.max(p));
                }
            }
            // The view-space box's corners project a little beyond the outline.
            let slack = (high - low) * 0.25 + 3.0;
            assert!((low - min.as_vec2()).cmple(slack).all() && (max.as_vec2() - high).cmple(slack).all(),
                    "{min}..{max} against the outline's {low}..{high}");
        }
        let whole = (UVec2::ZERO, UVec2::new(width, height));
        assert_eq!(CAMERA.sphere_pixel_bounds(width, height, CAMERA.position + Vec3::X * 0.5, 0.5), whole);
        let forward = (CAMERA.target - CAMERA.position).normalize();
        let beside = CAMERA.position + forward * 5.0 + forward.cross(Vec3::Y) * 50.0;
        let (min, max) = CAMERA.sphere_pixel_bounds(width, height, beside, 0.5);
        assert!(min.x == max.x || min.y == max.y, "{min}..{max}");
    }

    /// A box's pixel bounds hold its corners' projections and are theirs within the pixel
    /// of rounding; the whole frame once it reaches behind the eye.
    #[test]
    fn a_boxs_pixel_bounds_hold_its_corners() {
        let (width, height) = (1280, 720);
        let size = glam::Vec2::new(width as f32, height as f32);
        let (low, high) = (Vec3::new(-1.0, 0.2, -0.5), Vec3::new(0.5, 0.6, 1.0));
        let (min, max) = CAMERA.box_pixel_bounds(width, height, low, high);
        let projected: Vec<glam::Vec2> = box_corners(low, high)
            .iter()
            .map(|&p| (ndc(&CAMERA, width as f32 / height as f32, p).xy() * 0.5 + 0.5) * size)
            .collect();
        let least = projected.iter().fold(size, |a, &p| a.min(p));
        let most = projected.iter().fold(glam::Vec2::ZERO, |a, &p| a.max(p));
        assert!((least - min.as_vec2()).cmpge(glam::Vec2::splat(1.0)).all(), "{min} against {least}");
        assert!((least - min.as_vec2()).cmple(glam::Vec2::splat(2.0)).all(), "{min} against {least}");
        assert!((max.as_vec2() - most).cmpge(glam::Vec2::splat(1.0)).all(), "{max} against {most}");
        assert!((max.as_vec2() - most).cmple(glam::Vec2::splat(2.0)).all(), "{max} against {most}");
        let behind = CAMERA.box_pixel_bounds(width, height, low, CAMERA.position + 1.0);
        assert_eq!(behind, (UVec2::ZERO, UVec2::new(width, height)));
    }

    #[test]
    fn fov_is_vertical_and_aspect_widens() {
        let camera = Camera {
            position: Vec3::ZERO,
            target: Vec3::NEG_Z,
            fov_y_degrees: 90.0,
            near: Camera::NEAR,
            far: Camera::FAR,
        };
        // At 90°, a point 45° up is on the top edge whatever the aspect.
        let top = ndc(&camera, 2.0, Vec3::new(0.0, 1.0, -1.0));
        assert!((top.y + 1.0).abs() < 1e-5, "{top}");
        let side = ndc(&camera, 2.0, Vec3::new(2.0, 0.0, -1.0));
        assert!((side.x - 1.0).abs() < 1e-5, "{side}");
    }

    #[test]
    fn depth_is_zero_at_near_and_one_at_far() {
        let camera = Camera {
            position: Vec3::ZERO,
            target: Vec3::NEG_Z,
            fov_y_degrees: 45.0,
            near: Camera::NEAR,
            far: Camera::FAR,
        };
        assert!(ndc(&camera, 1.0, Vec3::new(0.0, 0.0, -Camera::NEAR)).z.abs() < 1e-5);
        assert!((ndc(&camera, 1.0, Vec3::new(0.0, 0.0, -Camera::FAR)).z - 1.0).abs() < 1e-5);
    }

    #[test]
    fn looking_straight_down_or_up_stays_finite() {
        for (position, screen_up) in [
            (Vec3::new(0.0, 5.0, 0.0), Vec3::NEG_Z),
            (Vec3::new(0.0, -5.0, 0.0), Vec3::Z),
        ] {
            let camera = Camera {
                position,
                target: Vec3::ZERO,
                fov_y_degrees: 30.0,
                near: Camera::NEAR,
                far: Camera::FAR,
            };
            assert!(camera.view().is_finite());
            let centre = ndc(&camera, 1.0, Vec3::ZERO);
            assert!(centre.x.abs() < 1e-5 && centre.y.abs() < 1e-5);
            assert!(ndc(&camera, 1.0, screen_up * 0.5).y < -0.1);
        }
    }

    #[test]
    fn unusable_aspect_gives_a_finite_projection() {
        for aspect in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert_eq!(CAMERA.projection(aspect), CAMERA.projection(1.0));
        }
    }
}

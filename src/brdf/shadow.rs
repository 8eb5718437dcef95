//! Shadows of the point lights in f64: the twins of `shaders/lib/shadows.glsl` (the
//! shadow map's face selection and depth, the receiver-plane test, PCSS's penumbra) and
//! the faces' projections that `src/render/shadow.rs` renders with.

use super::Vec3;

/// Per face of a cube map (+x, −x, +y, −y, +z, −z): its axis F and the directions A and B
/// that a and b grow along, so that F + aA + bB points through (a, b), as
/// [`super::environment::cube_direction`] (the twin of env_math.glsl's) has it.
pub const CUBE_FACE_AXES: [[Vec3; 3]; 6] = [
    [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, -1.0, 0.0]],
    [[-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
    [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]],
    [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]],
    [[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]],
];

/// The face that direction d falls in and (a, b) on it: the inverse of `cube_direction`
/// (Vulkan's cube map face selection, ties to x, then y).
pub fn cube_face(d: Vec3) -> (u32, [f64; 2]) {
    let m = d.map(f64::abs);
    if m[0] >= m[1] && m[0] >= m[2] {
        if d[0] > 0.0 {
            (0, [-d[2] / m[0], -d[1] / m[0]])
        } else {
            (1, [d[2] / m[0], -d[1] / m[0]])
        }
    } else if m[1] >= m[2] {
        if d[1] > 0.0 {
            (2, [d[0] / m[1], d[2] / m[1]])
        } else {
            (3, [d[0] / m[1], -d[2] / m[1]])
        }
    } else if d[2] > 0.0 {
        (4, [d[0] / m[2], -d[1] / m[2]])
    } else {
        (5, [-d[0] / m[2], -d[1] / m[2]])
    }
}

/// The depth a face's projection stores for a point at major-axis distance λ from the
/// light, with near and far planes n and f: f/(f − n) · (1 − n/λ), 0 at n and 1 at f.
pub fn shadow_depth(lambda: f64, near: f64, far: f64) -> f64 {
    far / (far - near) * (1.0 - near / lambda)
}

/// The inverse of [`shadow_depth`]: the major-axis distance n f / (f − d (f − n)).
pub fn shadow_linear_depth(depth: f64, near: f64, far: f64) -> f64 {
    near * far / (far - depth * (far - near))
}

/// The major-axis distance at which the ray from the light along c (scaled to a major
/// component of 1, [`super::environment::cube_face_point`]) meets the receiver's plane
/// through q (relative to the light) with normal n, given c·n: (q·n)/(c·n), and no further
/// than `receiver`, the ray's point as far from the light as the receiver (|q|/|c|): what
/// lies beyond cannot stand between them, so a ray that meets the plane there or not at
/// all in front of the light (past its horizon) is compared there.
pub fn receiver_plane_depth(c_dot_n: f64, q_dot_n: f64, receiver: f64) -> f64 {
    let depth = q_dot_n / c_dot_n;
    if depth > 0.0 && depth < receiver {
        depth
    } else {
        receiver
    }
}

/// PCSS (Fernando 2005): the penumbra's half-width on the receiver, r (d − d_b)/d_b, for a
/// light of radius r, a receiver at d and blockers at d_b from it (similar triangles
/// through the blocker's edge), as the angle it subtends from the light, divided by d.
pub fn penumbra_angle(radius: f64, receiver: f64, blocker: f64) -> f64 {
    radius * (receiver - blocker).max(0.0) / (blocker * receiver)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::environment::{cube_direction, cube_face_point};

    fn normalize(v: Vec3) -> Vec3 {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / l)
    }

    #[test]
    fn face_axes_and_face_selection_invert_cube_direction() {
        for (face, [f, a_axis, b_axis]) in CUBE_FACE_AXES.iter().enumerate() {
            for (a, b) in [(0.0, 0.0), (0.7, -0.2), (-0.99, 0.99), (0.3, 0.8)] {
                let d = cube_direction(face as u32, a, b);
                let point: Vec3 = std::array::from_fn(|i| f[i] + a * a_axis[i] + b * b_axis[i]);
                assert_eq!(cube_face_point(face as u32, a, b), point, "face {face} ({a}, {b})");
                let from_axes = normalize(point);
                for i in 0..3 {
                    assert!((d[i] - from_axes[i]).abs() < 1e-15, "face {face} ({a}, {b})");
                }
                let (found, ab) = cube_face(d);
                assert_eq!(found, face as u32);
                assert!((ab[0] - a).abs() < 1e-15 && (ab[1] - b).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn linear_depth_inverts_the_stored_depth() {
        let (near, far) = (0.01, 12.0);
        assert_eq!(shadow_depth(near, near, far), 0.0);
        assert!((shadow_depth(far, near, far) - 1.0).abs() < 1e-15);
        for lambda in [0.02, 0.5, 3.0, 11.9] {
            let back = shadow_linear_depth(shadow_depth(lambda, near, far), near, far);
            assert!((back - lambda).abs() < 1e-12 * lambda);
        }
    }

    #[test]
    fn receiver_plane_depth_is_where_the_ray_meets_the_plane() {
        // The plane y = −2 below a light at the origin, the receiver 2.1 from the light:
        // the ray through c meets the plane at major-axis distance 2/|c_y| when it points
        // down, and is compared no further than 2.1/|c|.
        let n = [0.0, 1.0, 0.0];
        let q_dot_n = -2.0; // q = (0.5, −2, 0.3)
        let length = |c: Vec3| (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        let dot = |c: Vec3| c[0] * n[0] + c[1] * n[1] + c[2] * n[2];
        let c = [0.25, -1.0, 0.1];
        assert!((receiver_plane_depth(dot(c), q_dot_n, 2.1 / length(c)) - 2.0).abs() < 1e-15);
        // Past the receiver's distance, grazing, or never reaching the plane.
        for c in [[1.0, -0.5, 0.0], [1.0, 0.0, 0.0], [1.0, 0.5, 0.0]] {
            assert_eq!(receiver_plane_depth(dot(c), q_dot_n, 2.1 / length(c)), 2.1 / length(c));
        }
    }

    #[test]
    fn penumbra_follows_similar_triangles() {
        // A light of radius 0.5 at 6 from the receiver, a blocker at 4: the penumbra is
        // 0.5·2/4 = 0.25 wide on the receiver, 0.25/6 radians from the light.
        assert!((penumbra_angle(0.5, 6.0, 4.0) - 0.25 / 6.0).abs() < 1e-15);
        assert_eq!(penumbra_angle(0.0, 6.0, 4.0), 0.0);
        assert_eq!(penumbra_angle(0.5, 4.0, 4.0), 0.0);
    }
}

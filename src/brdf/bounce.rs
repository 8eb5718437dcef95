//! Light bounced once off the ground, in f64: the twins of `shaders/lib/bounce.glsl`'s gather
//! and its gradient in the normal, of `shaders/lib/ground_light.glsl`'s ground light and its
//! map's coordinates, and of the tap patterns of `shaders/lib/sampling.glsl` (and
//! `plane_point_irradiance` of shading.glsl).

use super::environment::{tangent_frame, to_world};
use super::{Vec3, PI};

/// `BOUNCE_TAPS` of bounce.glsl: cosine-weighted taps of the gather. Measured on the bench's
/// ball on the ground against the `full` reference (320×180): 16 taps change ꟻLIP by 2e-4.
pub const BOUNCE_TAPS: u32 = 8;

/// The golden angle π(3 − √5), as sampling.glsl rounds it.
pub const GOLDEN_ANGLE: f64 = 2.39996323;

/// Tap k of n on a Vogel disk of unit radius turned by `rotation` (Vogel 1979).
pub fn vogel_disk(k: u32, n: u32, rotation: f64) -> [f64; 2] {
    let radius = ((f64::from(k) + 0.5) / f64::from(n)).sqrt();
    let angle = f64::from(k) * GOLDEN_ANGLE + rotation;
    [radius * angle.cos(), radius * angle.sin()]
}

/// Tap k of n of a cosine-weighted hemisphere about +z: the Vogel disk's point lifted onto
/// the hemisphere (Malley's method, pbrt-v4 §A.5.3).
pub fn cosine_hemisphere_tap(k: u32, n: u32) -> Vec3 {
    let [x, y] = vogel_disk(k, n, 0.0);
    [x, y, (1.0 - x * x - y * y).max(0.0).sqrt()]
}

/// The lowest height above the ground a point gathers at: a vertex on the ground (a ball
/// resting on it) or below it gathers as the surface just above it, where its triangles'
/// pixels are seen.
pub const MIN_BOUNCE_HEIGHT: f64 = 1e-4;

/// `BOUNCE_GRADIENT_TAPS` of bounce.glsl: taps of the gather's gradient, each 2π/32 sr.
pub const BOUNCE_GRADIENT_TAPS: u32 = 32;

/// Tap k of n spread evenly over the hemisphere below the horizon (−y), each standing for
/// 2π/n sr: heights evenly spaced in (−1, 0), turned by the golden angle from one to the
/// next (a spherical Fibonacci set, González 2010).
pub fn lower_hemisphere_tap(k: u32, n: u32) -> Vec3 {
    let y = -(f64::from(k) + 0.5) / f64::from(n);
    let r = (1.0 - y * y).max(0.0).sqrt();
    let angle = f64::from(k) * GOLDEN_ANGLE;
    [r * angle.cos(), y, r * angle.sin()]
}

/// Irradiance per unit intensity on a plane from a point light `height` above it at squared
/// distance `distance2`: cos θ / d² = height / d³; 0 where the light is not above it.
pub fn plane_point_irradiance(height: f64, distance2: f64) -> f64 {
    if height <= 0.0 {
        return 0.0;
    }
    height / (distance2.sqrt() * distance2)
}

/// The ground of the gather: an upward square.
#[derive(Clone, Copy, Debug)]
pub struct Ground {
    pub centre: Vec3,
    pub half_side: f64,
    pub albedo: Vec3,
}

/// A point light: position and radiant intensity.
#[derive(Clone, Copy, Debug)]
pub struct BounceLight {
    pub position: Vec3,
    pub intensity: Vec3,
}

/// ground_light.glsl's `ground_lights_irradiance`: E_lights(x), the lights' irradiance at
/// ground point x, `visibility(i, x)` the share of light i reaching it.
pub fn ground_lights_irradiance(x: Vec3, lights: &[BounceLight], visibility: impl Fn(usize, Vec3) -> f64) -> Vec3 {
    let mut lit = [0.0; 3];
    for (i, light) in lights.iter().enumerate() {
        let to_light = [
            light.position[0] - x[0],
            light.position[1] - x[1],
            light.position[2] - x[2],
        ];
        let distance2 = super::dot(to_light, to_light).max(MIN_LIGHT_DISTANCE2);
        let e = plane_point_irradiance(to_light[1], distance2);
        if e > 0.0 {
            let v = visibility(i, x);
            for (l, intensity) in lit.iter_mut().zip(light.intensity) {
                *l += intensity * e * v;
            }
        }
    }
    lit
}

/// ground_light.glsl's `ground_light_point`: the ground point at the centre of texel
/// (column, row) of a map `size` texels on a side over the ground's square.
pub fn ground_light_point(texel: [u32; 2], size: u32, ground: &Ground) -> Vec3 {
    let at = |i: u32| (f64::from(i) + 0.5) / f64::from(size) * 2.0 - 1.0;
    [
        ground.centre[0] + at(texel[0]) * ground.half_side,
        ground.centre[1],
        ground.centre[2] + at(texel[1]) * ground.half_side,
    ]
}

/// ground_light.glsl's `ground_light_uv`: where ground point x falls on the map, (0, 0) to
/// (1, 1) over the ground's square.
pub fn ground_light_uv(x: Vec3, ground: &Ground) -> [f64; 2] {
    let side = 2.0 * ground.half_side;
    [
        (x[0] - ground.centre[0]) / side + 0.5,
        (x[2] - ground.centre[2]) / side + 0.5,
    ]
}

/// What the gather reads of the ground and the environment: `ground_light(x)` is E_lights
/// at ground point x (on the GPU the ground's light map read bilinearly, of
/// [`ground_lights_irradiance`] at its texel centres) and `environment_over_pi(d)` E_env(d)/π.
pub struct BounceSource<'a, L: Fn(Vec3) -> Vec3, E: Fn(Vec3) -> Vec3> {
    pub ground: &'a Ground,
    pub ground_light: L,
    pub environment_over_pi: E,
}

impl<L: Fn(Vec3) -> Vec3, E: Fn(Vec3) -> Vec3> BounceSource<'_, L, E> {
    /// bounce.glsl's `ground_tap`: π ΔL along downward d from p, `height` above the ground,
    /// the ground's radiance ρ_g (E_lights + E_env(+y))/π less the environment's E_env(d)/π
    /// that it hides, times π; 0 where d misses the ground's square.
    fn tap(&self, p: Vec3, d: Vec3, height: f64, ground_environment: Vec3) -> Vec3 {
        let ground = self.ground;
        let t = height / -d[1];
        let x = [p[0] + d[0] * t, p[1] + d[1] * t, p[2] + d[2] * t];
        let offset = [(x[0] - ground.centre[0]).abs(), (x[2] - ground.centre[2]).abs()];
        if offset[0].max(offset[1]) > ground.half_side {
            return [0.0; 3];
        }
        let sky = (self.environment_over_pi)(d);
        let light = (self.ground_light)(x);
        std::array::from_fn(|c| ground.albedo[c] * (ground_environment[c] + light[c]) - PI * sky[c])
    }

    /// E_env(+y), and p's height above the ground for the gather (bounce.glsl's
    /// `bounce_height`: at least [`MIN_BOUNCE_HEIGHT`]); None without a ground.
    fn reach(&self, p: Vec3) -> Option<(Vec3, f64)> {
        let height = (p[1] - self.ground.centre[1]).max(MIN_BOUNCE_HEIGHT);
        (self.ground.half_side > 0.0).then(|| ((self.environment_over_pi)([0.0, 1.0, 0.0]).map(|e| PI * e), height))
    }

    /// bounce.glsl's `ground_bounce_irradiance` with `taps` taps: what the ground below p
    /// (unit normal n) adds to the environment's irradiance, the ground a Lambertian emitter
    /// of ρ_g/π (E_lights + E_env(+y)) in place of the environment's radiance E_env(d)/π
    /// along each tap d.
    pub fn irradiance(&self, p: Vec3, n: Vec3, taps: u32) -> Vec3 {
        let Some((ground_environment, height)) = self.reach(p).filter(|_| n[1] < 1.0) else {
            return [0.0; 3];
        };
        let basis = tangent_frame(n);
        let mut sum = [0.0; 3];
        for k in 0..taps {
            let d = to_world(&basis, cosine_hemisphere_tap(k, taps));
            if d[1] < 0.0 {
                let tap = self.tap(p, d, height, ground_environment);
                sum = std::array::from_fn(|c| sum[c] + tap[c]);
            }
        }
        sum.map(|s| s / f64::from(taps))
    }

    /// bounce.glsl's `ground_bounce_gradient` with `taps` taps: dE/dn of the irradiance at
    /// p, `[c]` channel c's, D/2 of the first-order spherical harmonics of ΔL, E(n) ≈ Φ/4 +
    /// D·n/2 (Ramamoorthi & Hanrahan 2001, eq. 8), D = ∫ ΔL l dl below the horizon.
    pub fn gradient(&self, p: Vec3, taps: u32) -> [Vec3; 3] {
        let Some((ground_environment, height)) = self.reach(p) else {
            return [[0.0; 3]; 3];
        };
        let mut sum = [[0.0; 3]; 3];
        for k in 0..taps {
            let d = lower_hemisphere_tap(k, taps);
            let tap = self.tap(p, d, height, ground_environment);
            for c in 0..3 {
                for (s, d) in sum[c].iter_mut().zip(d) {
                    *s += tap[c] * d;
                }
            }
        }
        sum.map(|column| column.map(|s| s / f64::from(taps)))
    }
}

/// bounce.glsl's `bounce_at_pixel`: the gather at the mesh's normal moved along its
/// gradient from the interpolated normal `n_geometric` to the shading normal n.
pub fn bounce_at_pixel(at_mesh_normal: Vec3, gradient: &[Vec3; 3], n: Vec3, n_geometric: Vec3) -> Vec3 {
    let moved = [n[0] - n_geometric[0], n[1] - n_geometric[1], n[2] - n_geometric[2]];
    std::array::from_fn(|c| at_mesh_normal[c] + super::dot(moved, gradient[c]))
}

/// shading.glsl's MIN_LIGHT_DISTANCE2.
const MIN_LIGHT_DISTANCE2: f64 = 1e-8;

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    /// An infinite ground under a uniform sky of radiance 1, no lights.
    fn open_ground(albedo: f64) -> Ground {
        Ground {
            centre: [0.0; 3],
            half_side: f64::INFINITY,
            albedo: [albedo; 3],
        }
    }

    fn under_the_sky(ground: &Ground) -> BounceSource<'_, impl Fn(Vec3) -> Vec3, impl Fn(Vec3) -> Vec3> {
        BounceSource {
            ground,
            ground_light: |_| [0.0; 3],
            environment_over_pi: |_| [1.0; 3],
        }
    }

    fn normal(theta: f64, phi: f64) -> Vec3 {
        [theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()]
    }

    const NORMALS: [(f64, f64); 6] = [(0.3, 0.0), (1.0, 0.7), (FRAC_PI_2, 2.0), (2.2, 0.0), (2.9, 0.7), (PI, 2.0)];

    /// Under a uniform sky the ground replaces the radiance 1 of the part of n's hemisphere
    /// below the horizon by ρ (its own irradiance π over π, times ρ): the gather converges to
    /// π (ρ − 1) (1 − n·y)/2, (1 − cos θ)/2 the view factor from a differential area tilted
    /// by θ from the plane's normal to the infinite plane below it.
    #[test]
    fn the_gather_converges_to_the_view_factor_of_the_ground() {
        let albedo = 0.5;
        let ground = open_ground(albedo);
        let source = under_the_sky(&ground);
        let mut worst_fixed: f64 = 0.0;
        for theta in [0.3, 1.0, FRAC_PI_2, 2.2, 2.9, PI] {
            for phi in [0.0, 0.7, 2.0] {
                let n = normal(theta, phi);
                let exact = PI * (albedo - 1.0) * (1.0 - n[1]) / 2.0;
                let many = source.irradiance([0.0, 1.0, 0.0], n, 1 << 16)[0];
                assert!((many - exact).abs() < 2e-3, "θ {theta} φ {phi}: {many} vs {exact}");
                let fixed = source.irradiance([0.0, 1.0, 0.0], n, BOUNCE_TAPS)[0];
                worst_fixed = worst_fixed.max((fixed - exact).abs() / (PI * (1.0 - albedo)));
            }
        }
        // The fixed tap set's own error in the view factor: worst where n is near the
        // horizon, 3 or 5 of 8 taps meeting the ground for a half (0.145 measured).
        eprintln!("{BOUNCE_TAPS} taps: view factor within {worst_fixed:.3}");
        assert!(
            worst_fixed < 0.15,
            "{BOUNCE_TAPS} taps miss the view factor by {worst_fixed}"
        );
        // Straight down every tap meets the ground: exact with any tap count.
        let down = source.irradiance([0.0, 1.0, 0.0], [0.0, -1.0, 0.0], BOUNCE_TAPS)[0];
        assert!((down - PI * (albedo - 1.0)).abs() < 1e-12);
    }

    /// The taps are unit, below the horizon, and weigh its directions evenly: their mean
    /// height is −½, that of the hemisphere's directions, exactly (a midpoint rule of a
    /// linear function), and their horizontal mean tends to 0.
    #[test]
    fn lower_hemisphere_taps_cover_it_evenly() {
        let mean = |n: u32| -> Vec3 {
            let mut sum = [0.0; 3];
            for k in 0..n {
                let d = lower_hemisphere_tap(k, n);
                assert!((super::super::dot(d, d) - 1.0).abs() < 1e-12 && d[1] < 0.0, "tap {k} of {n}: {d:?}");
                sum = std::array::from_fn(|c| sum[c] + d[c] / f64::from(n));
            }
            sum
        };
        let few = mean(BOUNCE_GRADIENT_TAPS);
        assert!((few[1] + 0.5).abs() < 1e-12, "{few:?}");
        assert!(few[0].hypot(few[2]) < 0.02, "{few:?}");
        let many = mean(1 << 14);
        assert!(many[0].hypot(many[2]) < 1e-4, "{many:?}");
    }

    /// Under a uniform sky the irradiance is linear in the normal (the view factor above),
    /// so its first-order harmonics are exact: the gradient is (0, −π (ρ − 1)/2, 0), to the
    /// horizontal mean of the taps, and moving the converged gather along it from one
    /// normal gives the gather at any other, within the two gathers' own 2e-3.
    #[test]
    fn the_gradient_moves_the_gather_exactly_under_a_uniform_sky() {
        let albedo = 0.5;
        let ground = open_ground(albedo);
        let source = under_the_sky(&ground);
        let p = [0.0, 1.0, 0.0];
        let gradient = source.gradient(p, BOUNCE_GRADIENT_TAPS)[0];
        let exact = [0.0, -PI * (albedo - 1.0) / 2.0, 0.0];
        assert!((gradient[1] - exact[1]).abs() < 1e-12, "{gradient:?}");
        // The taps' horizontal mean (< 0.02 above) times 2π |ρ − 1|/2.
        assert!(gradient[0].hypot(gradient[2]) < 0.02 * PI * (1.0 - albedo), "{gradient:?}");
        for (from, to) in NORMALS.iter().zip(NORMALS.iter().rev()) {
            let (n0, n1) = (normal(from.0, from.1), normal(to.0, to.1));
            let at_n0 = source.irradiance(p, n0, 1 << 16);
            let moved = bounce_at_pixel(at_n0, &source.gradient(p, 1 << 14), n1, n0)[0];
            let at_n1 = source.irradiance(p, n1, 1 << 16)[0];
            assert!((moved - at_n1).abs() < 4e-3, "{from:?} → {to:?}: {moved} vs {at_n1}");
        }
    }

    /// Nothing is gathered facing straight up or beyond the ground's square; on the ground
    /// and below it, what is gathered just above it.
    #[test]
    fn no_bounce_where_the_ground_is_not_seen() {
        let ground = open_ground(0.5);
        let source = under_the_sky(&ground);
        let down = [0.0, -1.0, 0.0];
        let just_above = source.irradiance([0.0, MIN_BOUNCE_HEIGHT, 0.0], down, 8);
        assert!(just_above.iter().all(|e| (e - PI * (0.5 - 1.0)).abs() < 1e-12), "{just_above:?}");
        assert_eq!(source.irradiance([0.0, 0.0, 0.0], down, 8), just_above);
        assert_eq!(source.irradiance([0.0, -1.0, 0.0], down, 8), just_above);
        assert_eq!(source.irradiance([0.0, 1.0, 0.0], [0.0, 1.0, 0.0], 8), [0.0; 3]);
        let small = Ground {
            centre: [10.0, 0.0, 0.0],
            half_side: 1.0,
            albedo: [0.5; 3],
        };
        let far = under_the_sky(&small);
        assert_eq!(far.irradiance([0.0, 1.0, 0.0], [0.0, -1.0, 0.0], 8), [0.0; 3]);
        // Below p, within a radius of 1e-3 of its height 1, no tap of the gradient's meets it.
        assert_eq!(far.gradient([0.0, 1.0, 0.0], BOUNCE_GRADIENT_TAPS), [[0.0; 3]; 3]);
    }

    /// A lit ground under a black sky: straight down, every tap meets the ground at the point
    /// below p's ray, lit by a light above with its inverse-square cosine; the light's share
    /// scales it.
    #[test]
    fn the_lights_reach_through_the_ground_and_its_visibility() {
        let ground = Ground {
            centre: [0.0; 3],
            half_side: f64::INFINITY,
            albedo: [0.5, 0.25, 1.0],
        };
        let light = BounceLight {
            position: [0.0, 1e6, 0.0],
            intensity: [1e12; 3],
        };
        let gather = |share: f64| {
            let source = BounceSource {
                ground: &ground,
                ground_light: |x| ground_lights_irradiance(x, &[light], |_, _| share),
                environment_over_pi: |_| [0.0; 3],
            };
            source.irradiance([0.0, 1.0, 0.0], [0.0, -1.0, 0.0], 64)
        };
        // A light 1e6 above: E ≈ 1e12/1e12 = 1 at every tap's point (they lie within 1e2).
        let full = gather(1.0);
        for c in 0..3 {
            assert!((full[c] - ground.albedo[c]).abs() < 1e-6, "{full:?}");
        }
        assert_eq!(gather(0.0), [0.0; 3]);
    }

    /// The map's texel centres cover the ground's square, and a point at a texel's centre
    /// falls there on the map.
    #[test]
    fn map_coordinates_invert_the_texel_centres() {
        let ground = Ground {
            centre: [1.5, -1.0, -2.0],
            half_side: 8.0,
            albedo: [0.5; 3],
        };
        let size = 256;
        for texel in [[0, 0], [17, 200], [255, 255]] {
            let x = ground_light_point(texel, size, &ground);
            assert_eq!(x[1], ground.centre[1]);
            let uv = ground_light_uv(x, &ground);
            for (t, u) in texel.into_iter().zip(uv) {
                assert!((u * f64::from(size) - (f64::from(t) + 0.5)).abs() < 1e-9, "{texel:?}: {uv:?}");
            }
        }
        let corner = ground_light_uv([-6.5, -1.0, 6.0], &ground);
        assert_eq!(corner, [0.0, 1.0]);
    }

    /// sampling.glsl's vogel_disk_step turns each tap's angle from the last by a complex
    /// product, in f32: over the most taps a filter takes (the ground's shadow map's), its
    /// taps stay on vogel_disk's to 1e-5 of the disk's radius.
    #[test]
    fn walked_taps_stay_on_the_vogel_disk() {
        let sampling = include_str!("../../shaders/lib/sampling.glsl");
        assert!(sampling.contains("const vec2 GOLDEN_TURN = vec2(cos(GOLDEN_ANGLE), sin(GOLDEN_ANGLE));"));
        let turn = [GOLDEN_ANGLE.cos() as f32, GOLDEN_ANGLE.sin() as f32];
        let n = crate::render::ground_maps::GROUND_SHADOW_TAPS_PER_TAP * crate::scene::SHADOW_TAPS_RANGE.end();
        let mut worst = 0.0f64;
        for rotation in [0.0f64, 1.0, 4.0, 6.2] {
            let mut direction = [rotation.cos() as f32, rotation.sin() as f32];
            for k in 0..n {
                let radius = ((k as f32 + 0.5) / n as f32).sqrt();
                let tap = [radius * direction[0], radius * direction[1]];
                direction = [
                    direction[0] * turn[0] - direction[1] * turn[1],
                    direction[0] * turn[1] + direction[1] * turn[0],
                ];
                let exact = vogel_disk(k, n, rotation);
                worst = worst.max((f64::from(tap[0]) - exact[0]).hypot(f64::from(tap[1]) - exact[1]));
            }
        }
        assert!(worst < 1e-5, "{worst:e}");
    }

    #[test]
    fn cosine_taps_are_unit_and_above_the_plane() {
        for k in 0..BOUNCE_TAPS {
            let d = cosine_hemisphere_tap(k, BOUNCE_TAPS);
            assert!((super::super::dot(d, d) - 1.0).abs() < 1e-12 && d[2] > 0.0);
        }
    }

    #[test]
    fn the_tap_counts_and_height_are_bounce_glsls() {
        let glsl = include_str!("../../shaders/lib/bounce.glsl");
        for (name, taps) in [("BOUNCE_TAPS", BOUNCE_TAPS), ("BOUNCE_GRADIENT_TAPS", BOUNCE_GRADIENT_TAPS)] {
            assert!(
                glsl.contains(&format!("const uint {name} = {taps}u;")),
                "bounce.glsl's {name} differs from src/brdf/bounce.rs's"
            );
        }
        assert!(glsl.contains(&format!("const float MIN_BOUNCE_HEIGHT = {MIN_BOUNCE_HEIGHT:e};")));
        let sampling = include_str!("../../shaders/lib/sampling.glsl");
        assert!(sampling.contains(&format!("const float GOLDEN_ANGLE = {GOLDEN_ANGLE};")));
    }
}

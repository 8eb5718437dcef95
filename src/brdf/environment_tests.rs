//! The environment twins against definitions and independent integrals.

use super::*;
use crate::brdf::diffuse::{diffuse_eon, diffuse_eon_albedo};
use crate::brdf::quadrature::{diffuse_albedo, directional_albedo, gauss_legendre};
use crate::brdf::shading::{DiffuseModel, ShadingModels, SpecularModel};

const ALBEDO_ORDER: usize = 24;
const DIFFUSE_ORDER: usize = 16;

fn close(a: Vec3, b: Vec3, tolerance: f64) -> bool {
    (0..3).all(|i| (a[i] - b[i]).abs() <= tolerance)
}

/// Vulkan's cube map face selection: the face and (a, b) = (2s − 1, 2t − 1) of d.
fn select_face(d: Vec3) -> (u32, f64, f64) {
    let [x, y, z] = d;
    let (face, sc, tc, ma) = if x.abs() >= y.abs() && x.abs() >= z.abs() {
        if x > 0.0 {
            (0, -z, -y, x)
        } else {
            (1, z, -y, x)
        }
    } else if y.abs() >= z.abs() {
        if y > 0.0 {
            (2, x, z, y)
        } else {
            (3, x, -z, y)
        }
    } else if z > 0.0 {
        (4, x, -y, z)
    } else {
        (5, -x, -y, z)
    };
    (face, sc / ma.abs(), tc / ma.abs())
}

#[test]
fn cube_directions_invert_vulkans_face_selection() {
    for face in 0..6 {
        for (a, b) in [(0.0, 0.0), (0.5, -0.25), (-0.9, 0.7), (0.99, 0.99)] {
            let (selected, sa, sb) = select_face(cube_direction(face, a, b));
            assert_eq!(selected, face, "face {face} ({a}, {b})");
            assert!(
                (sa - a).abs() < 1e-12 && (sb - b).abs() < 1e-12,
                "face {face}: ({a}, {b}) -> ({sa}, {sb})"
            );
        }
    }
    assert!(close(cube_direction(0, 0.0, 0.0), [1.0, 0.0, 0.0], 0.0));
    assert!(close(cube_direction(2, 0.0, 0.0), [0.0, 1.0, 0.0], 0.0));
    assert!(close(cube_direction(5, 0.0, 0.0), [0.0, 0.0, -1.0], 0.0));
}

#[test]
fn cube_texel_solid_angles_cover_the_sphere() {
    for size in [1, 2, 7, 32] {
        let total: f64 = (0..size)
            .flat_map(|y| (0..size).map(move |x| cube_texel_solid_angle(x, y, size)))
            .sum();
        assert!((6.0 * total - 4.0 * PI).abs() < 1e-12, "size {size}: {}", 6.0 * total);
    }
    // The centre texel of a large face approaches its planar area at unit distance, a
    // corner texel 1/(3√3) of it.
    let w = 1024;
    let centre = cube_texel_solid_angle(w / 2, w / 2, w);
    assert!((centre / (4.0 / f64::from(w * w)) - 1.0).abs() < 1e-5);
    assert!((cube_texel_solid_angle(0, w - 1, w) / centre * 27f64.sqrt() - 1.0).abs() < 1e-2);
    // The rectangle formula F(x1, y1) − F(x0, y1) − F(x1, y0) + F(x0, y0),
    // F(x, y) = atan2(xy, √(x² + y² + 1)), in f64 where its cancellation is harmless.
    let f = |a: f64, b: f64| (a * b).atan2((a * a + b * b + 1.0).sqrt());
    for (x, y, size) in [(0, 0, 1), (1, 0, 2), (3, 5, 7), (0, 31, 32), (200, 17, 512)] {
        let edge = |i: u32| f64::from(i) / f64::from(size) * 2.0 - 1.0;
        let (x0, x1, y0, y1) = (edge(x), edge(x + 1), edge(y), edge(y + 1));
        let rectangle = f(x1, y1) - f(x0, y1) - f(x1, y0) + f(x0, y0);
        let triangles = cube_texel_solid_angle(x, y, size);
        assert!(
            (triangles / rectangle - 1.0).abs() < 1e-9,
            "({x}, {y}) of {size}²: {triangles} vs {rectangle}"
        );
    }
}

#[test]
fn equirect_and_rotation_conventions() {
    let uv = |d| equirect_uv(d);
    assert!(close(
        [uv([0.0, 0.0, -1.0])[0], uv([0.0, 0.0, -1.0])[1], 0.0],
        [0.5, 0.5, 0.0],
        1e-15
    ));
    assert!((uv([1.0, 0.0, 0.0])[0] - 0.75).abs() < 1e-15);
    assert!((uv([-1.0, 0.0, 0.0])[0] - 0.25).abs() < 1e-15);
    assert_eq!(uv([0.0, 1.0, 0.0]), [0.5, 0.0]);
    assert_eq!(uv([0.0, -1.0, 0.0]), [0.5, 1.0]);
    // An environment rotated by 90° about +y (counter-clockwise from above) shows along −z
    // what it showed along +x.
    let looking = rotate_y([0.0, 0.0, -1.0], map_rotation(90.0));
    assert!(close(looking, [1.0, 0.0, 0.0], 1e-15), "{looking:?}");
    assert!(close(
        rotate_y([0.3, 0.4, 0.5], map_rotation(0.0)),
        [0.3, 0.4, 0.5],
        0.0
    ));
}

#[test]
fn seed_reflection_is_the_unit_mirror_direction() {
    let n = normalize([0.2, 0.9, 0.3]);
    let v = normalize([-0.5, 0.4, 0.7]);
    let r = seed_reflection(n, v);
    assert!((dot(r, r) - 1.0).abs() < 1e-15);
    assert!((dot(r, n) - dot(v, n)).abs() < 1e-15, "equal angles with n");
    assert!(dot(cross(n, v), r).abs() < 1e-15, "r in the plane of n and v");
    assert!(close(r, reflect_about(v, n), 1e-15));
}

/// θ = 0 is n, the mirror direction's own angle is r; a unit vector in the plane of n and v.
#[test]
fn lobe_direction_turns_from_n_towards_r() {
    let n = normalize([0.2, -0.3, 0.9]);
    let v = normalize([-0.5, 0.4, 0.7]);
    let r = seed_reflection(n, v);
    assert!(close(lobe_direction(n, v, 0.0), n, 1e-15));
    assert!(close(lobe_direction(n, v, dot(n, r).acos()), r, 1e-15));
    let d = lobe_direction(n, v, 0.3);
    assert!((dot(d, d) - 1.0).abs() < 1e-15);
    assert!((dot(d, n) - 0.3f64.cos()).abs() < 1e-15);
    assert!(dot(cross(n, v), d).abs() < 1e-15, "d in the plane of n and v");
    assert!(close(lobe_direction(n, n, 0.3), n, 0.0), "no plane of incidence head-on");
}

#[test]
fn lobe_mean_angle_weighs_the_parts_by_energy() {
    assert_eq!(lobe_mean_angle(0.0, 0.0, 0.4, 0.9), 0.0);
    assert_eq!(lobe_mean_angle(0.3, 0.0, 0.4, 0.9), 0.4);
    assert_eq!(lobe_mean_angle(0.0, 0.2, 0.4, 0.9), 0.9);
    assert!((lobe_mean_angle(0.3, 0.1, 0.4, 0.8) - 0.5).abs() < 1e-15);
}

/// Each mip's α reads that mip exactly; the lod rises with α, continuously at mip 1, where
/// the linear blend from the mirror meets the octaves.
#[test]
fn prefiltered_lod_inverts_the_level_alpha() {
    let last = 6;
    for level in 0..=last {
        let lod = prefiltered_lod(prefiltered_level_alpha(level, last), f64::from(last));
        assert!((lod - f64::from(level)).abs() < 1e-12, "level {level}: lod {lod}");
    }
    let lods: Vec<f64> = (0..=1000).map(|i| prefiltered_lod(f64::from(i) / 1000.0, 6.0)).collect();
    assert!(lods.windows(2).all(|w| w[0] < w[1]));
    let first = prefiltered_level_alpha(1, last);
    assert!((prefiltered_lod(first * (1.0 - 1e-9), 6.0) - 1.0).abs() < 1e-8);
}

#[test]
fn tangent_frames_are_orthonormal() {
    for n in [
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        normalize([0.3, -0.8, 0.1]),
        normalize([1.0, 1e-9, -1e-9]),
    ] {
        let f = tangent_frame(n);
        for i in 0..3 {
            for j in 0..3 {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((dot(f[i], f[j]) - expected).abs() < 1e-12, "{n:?}");
            }
        }
        assert!(close(cross(f[0], f[1]), n, 1e-12), "right-handed around {n:?}");
    }
}

#[test]
fn sh_basis_is_orthonormal_and_projection_recovers_it() {
    let size = 48;
    for k in 0..9 {
        let c = sh_project_cube(size, |face, x, y| {
            let (a, b) = cube_texel_ab(x, y, size);
            [sh_basis(cube_direction(face, a, b))[k]; 3]
        });
        for (j, cj) in c.iter().enumerate() {
            let expected = if j == k { 1.0 } else { 0.0 };
            // Midpoint rule over texels: O(h²).
            assert!((cj[0] - expected).abs() < 2e-3, "⟨Y{k}, Y{j}⟩ = {}", cj[0]);
        }
    }
}

/// A band-limited radiance L = 1 + 0.5 x + 0.3 (3z² − 1) has irradiance/π
/// 1 + (2/3) 0.5 x + (1/4) 0.3 (3z² − 1) (Ramamoorthi & Hanrahan 2001).
#[test]
fn sh_irradiance_of_a_band_limited_environment() {
    let radiance = |d: Vec3| 1.0 + 0.5 * d[0] + 0.3 * (3.0 * d[2] * d[2] - 1.0);
    let size = 32;
    let c = sh_project_cube(size, |face, x, y| {
        let (a, b) = cube_texel_ab(x, y, size);
        [radiance(cube_direction(face, a, b)); 3]
    });
    let mut worst: f64 = 0.0;
    for n in [
        [1.0, 0.0, 0.0],
        [0.0, 0.0, -1.0],
        normalize([0.3, 0.5, -0.8]),
        normalize([-1.0, 1.0, 1.0]),
    ] {
        let expected = 1.0 + 2.0 / 3.0 * 0.5 * n[0] + 0.25 * 0.3 * (3.0 * n[2] * n[2] - 1.0);
        let got = sh_convolve(&c, n, SH_IRRADIANCE_OVER_PI)[0];
        worst = worst.max((got - expected).abs());
    }
    println!("SH irradiance of a band-limited environment, 32² faces: max |error| {worst:.1e}");
    assert!(worst < 1e-3);
    // A constant: c00 = L √(4π), and exactly L back.
    let constant = sh_project_cube(4, |_, _, _| [2.0; 3]);
    assert!((constant[0][0] - 2.0 * (4.0 * PI).sqrt()).abs() < 1e-12);
    assert!((sh_convolve(&constant, [0.0, 1.0, 0.0], SH_IRRADIANCE_OVER_PI)[0] - 2.0).abs() < 1e-12);
}

/// The irradiance cube of a band-limited radiance is its SH irradiance, up to the
/// quadrature over the source's texels; of a constant L it is L. Of one bright texel it is
/// 0 on the far side, where the SH irradiance goes negative.
#[test]
fn irradiance_cube_agrees_with_sh_where_the_light_is_band_limited() {
    let radiance = |d: Vec3| 1.0 + 0.5 * d[0] + 0.3 * (3.0 * d[2] * d[2] - 1.0);
    let (out, size) = (8, 32);
    let source = |face, x, y| {
        let (a, b) = cube_texel_ab(x, y, size);
        [radiance(cube_direction(face, a, b)); 3]
    };
    let sh = sh_project_cube(size, source);
    let cube = irradiance_over_pi_cube(out, size, source);
    let constant = irradiance_over_pi_cube(out, size, |_, _, _| [2.0; 3]);
    let mut worst: f64 = 0.0;
    let mut worst_constant: f64 = 0.0;
    for (i, (got, uniform)) in cube.iter().zip(&constant).enumerate() {
        let (face, texel) = (i as u32 / (out * out), i as u32 % (out * out));
        let (a, b) = cube_texel_ab(texel % out, texel / out, out);
        let expected = sh_convolve(&sh, cube_direction(face, a, b), SH_IRRADIANCE_OVER_PI)[0];
        worst = worst.max((got[0] - expected).abs());
        worst_constant = worst_constant.max((uniform[0] - 2.0).abs());
    }
    println!("irradiance cube vs SH, 32² source faces: max |error| {worst:.1e}, constant {worst_constant:.1e}");
    assert!(worst < 5e-4 && worst_constant < 5e-4);
    // One bright texel at the centre of +z: every normal facing away from it.
    let bright = |face, x, y| [if face == 4 && x == 16 && y == 16 { 1e3 } else { 0.0 }; 3];
    let c = sh_project_cube(size, bright);
    let (mut cube_max, mut sh_min) = (0.0_f64, f64::INFINITY);
    for (i, got) in irradiance_over_pi_cube(out, size, bright).iter().enumerate() {
        let (face, texel) = (i as u32 / (out * out), i as u32 % (out * out));
        let (a, b) = cube_texel_ab(texel % out, texel / out, out);
        let n = cube_direction(face, a, b);
        if n[2] < -0.1 {
            cube_max = cube_max.max(got[0].abs());
            sh_min = sh_min.min(sh_convolve(&c, n, SH_IRRADIANCE_OVER_PI)[0]);
        }
    }
    assert!(cube_max == 0.0 && sh_min < 0.0, "far side: cube up to {cube_max}, SH down to {sh_min}");
}

#[test]
fn wrap_sh_kernel_matches_quadrature() {
    let rule = gauss_legendre(64);
    for (w1, w2) in [(0.5, 0.3), (0.0, 0.2), (1.0, 0.05), (0.3, 0.9), (0.8, 1e-5)] {
        // 2π ∫ s P_l over 4096 panels of [−1, 1].
        let panels = 4096;
        let mut reference = [0.0; 3];
        for p in 0..panels {
            let (lo, hi) = (
                -1.0 + 2.0 * p as f64 / panels as f64,
                -1.0 + 2.0 * (p + 1) as f64 / panels as f64,
            );
            for &(x, w) in &rule {
                let mu = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x;
                let s = w * 0.5 * (hi - lo) * wrap_seed(mu, w1, w2);
                reference = add(reference, [s, s * mu, s * 0.5 * (3.0 * mu * mu - 1.0)]);
            }
        }
        let reference = scale(reference, TWO_PI);
        let kernel = wrap_sh_kernel(w1, w2);
        // The reference's panels straddle the kinks of s, so it is the less exact one.
        assert!(
            close(kernel, reference, 1e-8),
            "w1 {w1} w2 {w2}: {kernel:?} vs {reference:?}"
        );
    }
}

/// E[g(l)/p(l)] = ∫ g for l drawn from p: each sampler against its pdf, by 2¹⁶ Hammersley
/// points, with g the cosine density (∫ = 1 over the upper hemisphere).
#[test]
fn samplers_match_their_pdfs() {
    let n = 1 << 16;
    let mean = |f: &dyn Fn([f64; 2]) -> f64| (0..n).map(|i| f(hammersley(i, n))).sum::<f64>() / f64::from(n);
    let cosine = mean(&|u| pdf_cosine(sample_cosine(u)[2]) / pdf_cosine(sample_cosine(u)[2]));
    assert!((cosine - 1.0).abs() < 1e-12);
    let uniform = mean(&|u| pdf_cosine(sample_uniform_sphere(u)[2]) / PDF_UNIFORM_SPHERE);
    assert!((uniform - 1.0).abs() < 1e-3, "uniform: {uniform}");
    for (alpha, theta) in [(0.25f64, 30.0f64), (0.5, 60.0), (0.9, 80.0)] {
        let v = [theta.to_radians().sin(), 0.0, theta.to_radians().cos()];
        let vndf = mean(&|u| {
            let h = sample_ggx_vndf(v, alpha, u);
            let l = reflect_about(v, h);
            let pdf = pdf_ggx_vndf(alpha, v[2], h[2], h[0] * h[0] + h[1] * h[1]);
            pdf_cosine(l[2]) / pdf
        });
        // The VNDF pdf integrates to 1 over the sphere of l (Heitz 2014's weak furnace).
        let total = mean(&|u| {
            let l = sample_uniform_sphere(u);
            let h = super::super::safe_half_vector(v, l, [0.0, 0.0, 1.0]);
            pdf_ggx_vndf(alpha, v[2], h[2].max(0.0), h[0] * h[0] + h[1] * h[1]) / PDF_UNIFORM_SPHERE
        });
        println!("α {alpha} θv {theta}°: E[cos/π / p_vndf] = {vndf:.5}, ∫ p_vndf = {total:.5}");
        assert!((vndf - 1.0).abs() < 5e-3, "α {alpha}: {vndf}");
        assert!((total - 1.0).abs() < 5e-3, "α {alpha}: {total}");
    }
}

#[test]
fn strategy_counts_cover_what_lights() {
    for total in [1, 2, 3, 7, 16, 64, 4096] {
        for (diffuse, specular, wrap) in [
            (true, true, true),
            (true, false, true),
            (false, true, false),
            (true, true, false),
            (false, false, true),
        ] {
            for environment in [false, true] {
                let [d, s, w, e] = strategy_counts(total, diffuse, specular, wrap, environment);
                assert_eq!(d + s + w + e, total);
                assert!(!wrap || w >= 1, "the wrap term reaches below the horizon");
                assert!(diffuse || d == 0);
                assert!(specular || s == 0);
                assert!(environment || e == 0);
                assert!(!(diffuse || specular) || d + s >= (total - w).min(1), "the lobes keep samples");
            }
        }
    }
    assert_eq!(strategy_counts(64, true, true, false, false), [32, 32, 0, 0]);
    assert_eq!(strategy_counts(64, true, true, true, false), [24, 24, 16, 0]);
    assert_eq!(strategy_counts(64, true, true, false, true), [8, 8, 0, 48]);
    assert_eq!(strategy_counts(1, true, true, false, true), [1, 0, 0, 0]);
    assert_eq!(strategy_counts(16, true, true, true, true), [2, 1, 4, 9]);
    assert_eq!(strategy_counts(8, false, false, false, true), [0, 0, 0, 0]);
}

#[test]
fn filtered_lod_matches_texel_and_sample_solid_angles() {
    let texel = 4.0 * PI / (6.0 * 64.0 * 64.0);
    // A sample covering 16 texels sits two levels up.
    assert!((filtered_lod(1.0 / (16.0 * texel), texel) - 2.0).abs() < 1e-12);
    assert_eq!(filtered_lod(1e9, texel), 0.0);
}

#[test]
fn lut_x_inverts() {
    for mu in [MIN_N_DOT_V, 0.3, 0.999, 1.0] {
        assert!((lut_n_dot_v(lut_x(mu)) - mu).abs() < 1e-15);
    }
    assert_eq!(lut_n_dot_v(1.0), MIN_N_DOT_V);
}

/// Texel i holds parameter i/(N − 1) and is read at its centre (i + ½)/N: the ends of
/// [0, 1] are the first and last texels' centres.
#[test]
fn lut_coordinates_are_texel_centres() {
    for size in [2, 32] {
        for i in 0..size {
            let centre = (f64::from(i) + 0.5) / f64::from(size);
            assert!((lut_coordinate(lut_parameter(i, size), size) - centre).abs() < 1e-15);
        }
        assert_eq!(lut_parameter(size - 1, size), 1.0);
    }
}

#[test]
fn lut_layers_round_trip() {
    for layer in 0..LUT_LAYER_OREN_NAYAR {
        assert_eq!(lut_layer(lut_layer_models(layer)), layer);
    }
    let models = ShadingModels {
        diffuse: DiffuseModel::Lambert,
        specular: SpecularModel::CookTorrance,
        distribution: Distribution::Beckmann,
        geometry: Geometry::SmithSeparable,
        subsurface: Subsurface::None,
    };
    assert_eq!(lut_layer(models), 3);
}

/// The tables' estimator (the compute shader's twin) against hemisphere quadrature of the
/// same lobes: ∫ f_s(F0 = 1) cos = A + B, ∫ f_s(F0 = 0) cos = B, ∫ f_ON cos, and the angles
/// of the parts' ∫ l f_s cos.
#[test]
fn brdf_table_estimates_match_quadrature() {
    const N: Vec3 = [0.0, 0.0, 1.0];
    let (mut worst, mut worst_angle): (f64, f64) = (0.0, 0.0);
    for layer in 0..LUT_LAYERS {
        // The tables' corners (n·v = 1 and its least, roughness or σ = 0 and 1) among them.
        for (x, y) in [
            (0.9, 0.3),
            (0.5, 0.6),
            (0.2, 0.9),
            (0.05, 0.5),
            (1.0, 0.0),
            (1.0, 1.0),
            (MIN_N_DOT_V, 0.0),
            (MIN_N_DOT_V, 1.0),
        ] {
            let estimate = brdf_lut_estimate(layer, x, y, 1024);
            let reference = if layer == LUT_LAYER_OREN_NAYAR {
                let m = lut_material(y, 0.0);
                [
                    diffuse_albedo(
                        |v, l| diffuse_lobe(DiffuseModel::OrenNayar, &m, N, v, l, x, l[2])[0],
                        x,
                        DIFFUSE_ORDER,
                    ),
                    0.0,
                    0.0,
                    0.0,
                ]
            } else {
                let models = lut_layer_models(layer);
                // ∫ w f cos for F0 = 0 and F0 = 1, w a weight per direction.
                let moment = |w: fn(Vec3) -> f64| {
                    [0.0, 1.0].map(|f0| {
                        let m = lut_material(y, f0);
                        directional_albedo(
                            |v, l| w(l) * specular_lobe(models, &m, N, v, l, v[2].max(MIN_N_DOT_V), l[2])[0],
                            x,
                            ALBEDO_ORDER,
                        )
                    })
                };
                let [b, a_plus_b] = moment(|_| 1.0);
                let [b_towards_mirror, a_plus_b_towards_mirror] = moment(|l| -l[0]);
                let [b_along_n, a_plus_b_along_n] = moment(|l| l[2]);
                [
                    a_plus_b - b,
                    b,
                    (a_plus_b_towards_mirror - b_towards_mirror).atan2(a_plus_b_along_n - b_along_n),
                    b_towards_mirror.atan2(b_along_n),
                ]
            };
            for i in 0..2 {
                let error = (estimate[i] - reference[i]).abs();
                worst = worst.max(error);
                assert!(
                    error < 4e-3,
                    "layer {layer} n·v {x} y {y}: {estimate:?} vs quadrature {reference:?}"
                );
            }
            // The mean directions' angles, where their part carries energy (measured: at
            // most 6.6e-3 rad, at grazing n·v; a part under 1e-3 weighs nothing).
            for i in (2..4).filter(|&i| reference[i - 2] >= 1e-3) {
                let error = (estimate[i] - reference[i]).abs();
                worst_angle = worst_angle.max(error);
                assert!(
                    error < 1e-2,
                    "layer {layer} n·v {x} y {y}: {estimate:?} vs quadrature {reference:?}"
                );
            }
        }
    }
    println!("BRDF tables, 1024 samples vs quadrature: max |error| {worst:.1e}, angles {worst_angle:.1e} rad");
}

#[test]
fn eon_albedo_matches_quadrature() {
    let rho = [0.9, 0.5, 0.1];
    for r in [0.2, 0.6, 1.0] {
        for mu in [0.95, 0.5, 0.15] {
            let albedo = diffuse_eon_albedo(rho, r, mu);
            for (c, a) in albedo.iter().enumerate() {
                let reference = diffuse_albedo(|v, l| diffuse_eon(rho, r, v[2], l[2], dot(v, l))[c], mu, DIFFUSE_ORDER);
                assert!(
                    (a - reference).abs() < 5e-3,
                    "r {r} μ {mu}: {a} vs quadrature {reference}"
                );
            }
        }
    }
}

#[test]
fn studio_is_a_lit_cyclorama() {
    let key = normalize([-0.55, 0.55, 0.63]);
    let at_key = studio_radiance(key);
    assert!(at_key[0] > 6.0 && at_key[0] < 6.5, "{at_key:?}");
    let floor = studio_radiance([0.0, -1.0, 0.0]);
    assert!(close(floor, STUDIO_FLOOR, 1e-12), "{floor:?}");
    for face in 0..6 {
        for (a, b) in [(0.0, 0.0), (0.7, -0.3), (-1.0, 1.0)] {
            let l = studio_radiance(cube_direction(face, a, b));
            assert!(l.iter().all(|c| c.is_finite() && *c >= 0.08), "{l:?}");
        }
    }
}

/// The frames of an accumulation rotate their sample sets by R2: the shader's steps are the
/// plastic number's, and the first K rotations stay about 1/√K apart on the torus (no two
/// frames draw nearly the same set), as a well-spread sequence does (0.63√K at worst here).
#[test]
fn r2_rotations_are_the_plastic_sequence_and_spread_evenly() {
    let glsl = include_str!("../../shaders/lib/env_math.glsl");
    let declared = format!("const uvec2 R2_STEP = uvec2({}u, {}u);", R2_STEP[0], R2_STEP[1]);
    assert!(glsl.contains(&declared), "env_math.glsl does not declare {declared}");
    let g = 1.324_717_957_244_746_f64;
    assert!((g * g * g - g - 1.0).abs() < 1e-14);
    let [x, y] = r2(1);
    assert!(
        (x - 1.0 / g).abs() < 1e-9 && (y - 1.0 / (g * g)).abs() < 1e-9,
        "{x}, {y}"
    );
    assert_eq!(r2(0), [0.0, 0.0]);
    for k in [16u32, 64, 256] {
        let points: Vec<[f64; 2]> = (0..k).map(r2).collect();
        let torus = |a: f64, b: f64| (a - b).abs().min(1.0 - (a - b).abs());
        let closest = points
            .iter()
            .enumerate()
            .flat_map(|(i, p)| {
                points[..i]
                    .iter()
                    .map(move |q| torus(p[0], q[0]).hypot(torus(p[1], q[1])))
            })
            .fold(f64::INFINITY, f64::min);
        assert!(closest * f64::from(k).sqrt() > 0.6, "{k} rotations: closest {closest}");
    }
}

/// The GGX lobe seen at n·v, mapped to the directions it reflects to (density D(h)/(4 v·h)),
/// is n·v times as narrow across the plane of incidence as along it, and an isotropic
/// prefiltered lobe (n = v) of α n·v, the taps' width where they need not widen, is as wide
/// as it across: half-maximum widths.
#[test]
fn the_lobe_narrows_across_the_plane_by_n_dot_v() {
    use crate::brdf::distribution::d_ggx;
    let density = |alpha: f64, v: Vec3, l: Vec3| {
        let h = normalize(add(v, l));
        let n_dot_h = h[2];
        d_ggx(alpha, n_dot_h, h[0] * h[0] + h[1] * h[1]) / (4.0 * dot(v, h))
    };
    // The angle from r along `axis` (rotating r in the plane of r and axis) where the density
    // falls to half its value at r.
    let half_width = |alpha: f64, v: Vec3, r: Vec3, axis: Vec3| {
        let peak = density(alpha, v, r);
        let at = |t: f64| normalize(add(scale(r, t.cos()), scale(axis, t.sin())));
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if density(alpha, v, at(mid)) > 0.5 * peak {
                lo = mid
            } else {
                hi = mid
            }
        }
        lo
    };
    for roughness in [0.2, 0.3, 0.45] {
        let alpha = roughness * roughness;
        let n = [0.0, 0.0, 1.0];
        for mu in [0.9_f64, 0.5, 0.2] {
            let v = [(1.0 - mu * mu).sqrt(), 0.0, mu];
            let r = seed_reflection(n, v);
            let along = cross([0.0, 1.0, 0.0], r);
            let (toward_n, away) = (
                half_width(alpha, v, r, along),
                half_width(alpha, v, r, scale(along, -1.0)),
            );
            let across = half_width(alpha, v, r, [0.0, 1.0, 0.0]);
            let [_, width, _] = prefiltered_taps(mu);
            let lookup = half_width(alpha * width, n, n, [1.0, 0.0, 0.0]);
            // To first order in α: measured within 0.98–1.0 for roughness 0.2, down to 0.89
            // at roughness 0.3 and 0.45 and n·v = 0.2, where the lobe is lopsided along the
            // plane; the lookup is 0.98–1.0 as wide as the lobe across.
            assert!(
                (across / (0.5 * (toward_n + away)) / mu - 1.0).abs() < 0.15,
                "roughness {roughness}, n·v {mu}"
            );
            assert!((lookup / across - 1.0).abs() < 0.05, "roughness {roughness}, n·v {mu}: {lookup} vs {across}");
        }
    }
}

/// The taps' mean has the lobe's variances, 2(α n·v)² across and 2α² min(1, 2 n·v) along, as
/// few taps as keep neighbours within two of a lookup's standard deviations, √2 α·width;
/// past PREFILTERED_MAX_TAPS (n·v < 0.22) they widen, the along variance kept.
#[test]
fn prefiltered_taps_have_the_lobes_variances() {
    let glsl = include_str!("../../shaders/lib/env_math.glsl");
    let declared = format!("const uint PREFILTERED_MAX_TAPS = {PREFILTERED_MAX_TAPS}u;");
    assert!(glsl.contains(&declared), "env_math.glsl does not declare {declared}");
    let neighbours_fit =
        |taps: f64, width: f64, spacing: f64| taps == 1.0 || spacing <= 2.0 * 2f64.sqrt() * width * (1.0 + 1e-12);
    for i in 1..=1000 {
        let mu = f64::from(i) / 1000.0;
        let [taps, width, spacing] = prefiltered_taps(mu);
        assert!(taps.fract() == 0.0 && (1.0..=f64::from(PREFILTERED_MAX_TAPS)).contains(&taps));
        let positions = spacing * spacing * (taps * taps - 1.0) / 12.0;
        let along = 2.0 * width * width + positions;
        assert!((along - 2.0 * (2.0 * mu).min(1.0)).abs() < 1e-12, "n·v {mu}: along {along}");
        assert!(neighbours_fit(taps, width, spacing), "n·v {mu}: {taps} taps {spacing} apart, width {width}");
        if taps < f64::from(PREFILTERED_MAX_TAPS) {
            assert!((width - mu).abs() < 1e-12, "n·v {mu}: width {width}");
        } else {
            assert!(width >= mu, "n·v {mu}: width {width}");
        }
        // One tap fewer at the lobe's width across would not do: one lookup that narrow
        // lacks the variance along, more would leave gaps.
        if taps > 1.0 && taps < f64::from(PREFILTERED_MAX_TAPS) {
            let fewer = taps - 1.0;
            let spacing = (24.0 * ((2.0 * mu).min(1.0) - mu * mu) / (fewer * fewer - 1.0)).sqrt();
            assert!(fewer == 1.0 || !neighbours_fit(fewer, mu, spacing), "n·v {mu}: {fewer} taps would do");
        }
    }
    assert_eq!(prefiltered_taps(1.0), [1.0, 1.0, 0.0]);
}

#[test]
fn equirect_directions_invert_equirect_uv() {
    for uv in [[0.5, 0.5], [0.75, 0.3], [0.1, 0.9], [0.99, 0.01]] {
        let back = equirect_uv(equirect_direction(uv));
        assert!(
            (back[0] - uv[0]).abs() < 1e-12 && (back[1] - uv[1]).abs() < 1e-12,
            "{uv:?} → {back:?}"
        );
    }
}

//! The scalar and colour terms `argil verify` checks, each declared once in [`TERMS`]: its
//! GLSL name, the equation it implements, its arguments, its inputs (random and stress),
//! its f64 twin, its cap and tolerance. `shaders/verify_brdf.comp`'s `term` switch calls
//! term k in its `case ku:` line; a test holds the two together.
//!
//! Adding a term: the GLSL function (shaders/lib/), its f64 twin (src/brdf/), one entry at
//! the end of [`TERMS`] and one `case` line in verify_brdf.comp.

use std::f64::consts::{FRAC_PI_2, PI};

use crate::brdf::antialiasing::{resolve_weight, specular_aa_roughness};
use crate::brdf::bounce::plane_point_irradiance;
use crate::brdf::diffuse::e_fon_approx;
use crate::brdf::distribution::{d_beckmann, d_ggx};
use crate::brdf::energy::{specular_energy_compensation, MIN_SPECULAR_ALBEDO};
use crate::brdf::environment::{octahedral_uv, prefiltered_lod, prefiltered_taps, sun_alpha, PREFILTERED_MAX_TAPS};
use crate::render::environment::sun::SUN_MAX_RADIUS_DEGREES;
use crate::render::environment::OCTAHEDRAL_SIDE;
use crate::brdf::fresnel::{f_schlick, f_schlick_scalar};
use crate::brdf::geometry::{
    g1_smith_ggx, g2_smith_correlated_beckmann, g2_smith_correlated_ggx, g2_smith_separable_beckmann,
    g2_smith_separable_ggx, g2_v_cavity, lambda_beckmann, lambda_ggx,
};
use crate::brdf::object_occlusion::{sphere_cap_irradiance, sphere_cap_partial_terms};
use crate::brdf::occlusion::{gtao_multi_bounce, gtao_slice_visibility, micro_shadowing, specular_occlusion};
use crate::brdf::shading::shadow_terminator;
use crate::brdf::specular::spec_blinn_phong;
use crate::brdf::subsurface::{wrap_energy_conserving_sh_kernel, PreintegratedTable};
use crate::brdf::tonemap::{srgb_oetf, srgb_oetf_rgb, tonemap_pbr_neutral};
use crate::brdf::wrap::{wrap_energy_conserving, wrap_seed};
use crate::brdf::{dot, safe_half_vector, MIN_N_DOT_V};

use super::composite::terminator_continuity;
use super::functions::{
    colour, direction, rgb, sample_cosine, sample_directions, sample_half_angle, sample_signed_cosine, uniform_sphere,
    Cap, Tolerance, Tuple, Values, DENORMAL, FP16, FP32, FP32_ARITHMETIC, NORMAL, SH_KERNEL, SLICE, STRESS_ALPHAS,
    STRESS_COLOURS, STRESS_COSINES, STRESS_RADIANCES, UNIT,
};
use super::Row;
use crate::rng::Rng;

/// One term of the harness. Its `FUNCTION` in verify_brdf.comp is its index in [`TERMS`].
pub struct TermSpec {
    /// The GLSL function's name (and the rows'); F and sRGB also evaluate their scalar
    /// overloads.
    pub name: &'static str,
    /// The equation (paper) it implements, as the GLSL function's comment names it; the
    /// note of its range row.
    pub equation: &'static str,
    /// Names of the scalar arguments in `Tuple::a`.
    pub arguments: &'static [&'static str],
    /// Name of the colour argument in `Tuple::d`, if any.
    pub colour: Option<&'static str>,
    /// How many of the four result channels hold a value.
    pub channels: usize,
    pub cap: Cap,
    pub tolerance: Tolerance,
    /// A weight of n·l for lighting, not a BRDF: reciprocity does not apply.
    pub lighting_weight: bool,
    /// The f64 twin on the tuple's (widened) f32 arguments.
    pub eval: fn(&Tuple) -> [f64; 4],
    /// A random tuple over the whole domain, given a random α (drawn for every term, so
    /// that each term's draws are the same whatever the others do), denser where the
    /// function is hard: near n·h = 1 inside narrow lobes, at grazing angles, near branch
    /// points.
    pub sample: fn(&mut Rng, f64) -> Tuple,
    /// Degenerate and extreme arguments.
    pub stress: fn() -> Vec<Tuple>,
    /// The relative error fp32 rounding of the arguments can cause beyond the term's own.
    pub rounding: Option<Rounding>,
    /// A row checking what the term promises besides its value.
    pub promise: Option<Promise>,
}

/// A row from every tuple and the GPU's and the f64 twin's values of it.
pub type Promise = fn(&[Tuple], &[Values<f32>], &[Values<f64>]) -> Row;

/// A bound on the error argument rounding causes on a tuple, and why.
pub struct Rounding {
    pub bound: fn(&Tuple) -> f64,
    pub reason: &'static str,
}

/// The tuple of scalar arguments `a`.
fn scalars(a: [f64; 4]) -> Tuple {
    Tuple {
        a: a.map(|x| x as f32),
        ..Tuple::default()
    }
}

/// The tuple of the colour argument `d`.
fn coloured(d: [f32; 4]) -> Tuple {
    Tuple { d, ..Tuple::default() }
}

fn scalar(value: f64) -> [f64; 4] {
    [value; 4]
}

fn rgb0([r, g, b]: [f64; 3]) -> [f64; 4] {
    [r, g, b, 0.0]
}

/// Every combination of the values of `axes` as scalar arguments, the first axis slowest.
fn grid(axes: &[&[f32]]) -> Vec<Tuple> {
    let mut out = vec![[0.0f32; 4]];
    for (k, axis) in axes.iter().enumerate() {
        out = out
            .into_iter()
            .flat_map(|a| {
                axis.iter().map(move |&x| {
                    let mut a = a;
                    a[k] = x;
                    a
                })
            })
            .collect();
    }
    out.into_iter().map(|a| Tuple { a, ..Tuple::default() }).collect()
}

/// Every combination of `values` as the three channels of the colour argument.
fn colour_grid(values: &[f32]) -> Vec<Tuple> {
    grid(&[values, values, values])
        .into_iter()
        .map(|t| coloured([t.a[0], t.a[1], t.a[2], 0.0]))
        .collect()
}

/// θh for D and Blinn-Phong: 3% below the horizon (0 there), else about the lobe of α.
fn sample_half_or_below(rng: &mut Rng, alpha: f64) -> f64 {
    if rng.uniform() < 0.03 {
        rng.range(FRAC_PI_2, PI)
    } else {
        sample_half_angle(rng, alpha)
    }
}

/// F0 or ρ from `STRESS_COLOURS`, the other channels 1 − it and half it.
fn stress_colour(c: f32) -> [f32; 4] {
    [c, 1.0 - c, c * 0.5, 0.0]
}

/// Each of `xs` as the first argument under each of `STRESS_COLOURS`.
fn each_stress_colour(xs: &[f32]) -> Vec<Tuple> {
    STRESS_COLOURS
        .iter()
        .flat_map(|&c| {
            xs.iter().map(move |&x| Tuple {
                a: [x, 0.0, 0.0, 0.0],
                d: stress_colour(c),
                ..Tuple::default()
            })
        })
        .collect()
}

/// A scalar uniform in [0, 1) and a random colour.
fn sample_unit_and_colour(rng: &mut Rng, _: f64) -> Tuple {
    Tuple {
        a: [rng.uniform() as f32, 0.0, 0.0, 0.0],
        d: colour(rng),
        ..Tuple::default()
    }
}

fn sample_d(rng: &mut Rng, alpha: f64) -> Tuple {
    let (sin, cos) = sample_half_or_below(rng, alpha).sin_cos();
    scalars([alpha, cos, sin * sin, 0.0])
}

fn stress_d() -> Vec<Tuple> {
    grid(&[STRESS_ALPHAS, STRESS_COSINES, STRESS_COSINES])
}

fn sample_lambda(rng: &mut Rng, alpha: f64) -> Tuple {
    scalars([alpha, sample_signed_cosine(rng), 0.0, 0.0])
}

fn stress_lambda() -> Vec<Tuple> {
    grid(&[STRESS_ALPHAS, STRESS_COSINES])
}

fn sample_g2(rng: &mut Rng, alpha: f64) -> Tuple {
    scalars([alpha, sample_signed_cosine(rng), sample_signed_cosine(rng), 0.0])
}

fn stress_g2() -> Vec<Tuple> {
    grid(&[STRESS_ALPHAS, STRESS_COSINES, STRESS_COSINES])
}

fn stress_radiances() -> Vec<Tuple> {
    colour_grid(STRESS_RADIANCES)
}

/// σκ and w: the stress α's and fp32's largest.
fn stress_cosine_and_weight() -> Vec<Tuple> {
    let weights: Vec<f32> = STRESS_ALPHAS.iter().copied().chain([f32::MAX]).collect();
    grid(&[STRESS_COSINES, &weights])
}

const SPECULAR_OCCLUSION_ROUNDING: &str = "rounding: (n·v + x)^k − 1 + x cancels where the \
    occlusion is small; bound 8·2^-24 of the summands' magnitude, relative to the value";

/// Where specular_occlusion's (n·v + x)^k − 1 + x cancels, fp32's pow and sum are good to a
/// few 2⁻²⁴ of the summands' magnitude, not of the (smaller) result.
fn specular_occlusion_rounding(t: &Tuple) -> f64 {
    let [n_dot_v, x, alpha, _] = t.a.map(f64::from);
    let k = (-16.0 * alpha.clamp(0.0, 1.0) - 1.0).exp2();
    let power = (n_dot_v.max(0.0) + x).powf(k);
    let value = specular_occlusion(n_dot_v, x, alpha);
    8.0 * f64::from(f32::EPSILON) * 0.5 * (power + 1.0 + x.abs()) / value.abs().max(super::sweep::RELATIVE_FLOOR)
}

const SPHERE_CAP_ROUNDING: &str = "rounding: the horizon-cut cap's cos θ acos y sin²α and \
    atan terms cancel where little of the cap is above the horizon; bound 4096 ulp (Vulkan's \
    precision of acos and atan) of the terms' magnitude, relative to the value";

/// Where sphere_cap_irradiance's partial branch cancels, the GPU's acos and atan, good to
/// 4096 ulp in Vulkan (2⁻¹¹ relative), bound the error by that of the terms' magnitude.
fn sphere_cap_rounding(t: &Tuple) -> f64 {
    let (cos_theta, sin_alpha) = (f64::from(t.a[0]).clamp(-1.0, 1.0), f64::from(t.a[1]).clamp(0.0, 1.0));
    let Some(terms) = sphere_cap_partial_terms(cos_theta, sin_alpha) else { return 0.0 };
    let magnitude = terms.iter().map(|v| v.abs()).sum::<f64>() / PI;
    let value = sphere_cap_irradiance(cos_theta, sin_alpha);
    4096.0 * f64::from(f32::EPSILON) * magnitude / value.abs().max(super::sweep::RELATIVE_FLOOR)
}

/// Every term, in the order of verify_brdf.comp's `case` lines and of the table.
pub static TERMS: &[TermSpec] = &[
    TermSpec {
        name: "d_ggx",
        equation: "seed eq. 7",
        arguments: &["α", "n·h", "|n×h|²"],
        colour: None,
        channels: 1,
        cap: FP32,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(d_ggx(f64::from(t.a[0]), f64::from(t.a[1]), f64::from(t.a[2]))),
        sample: sample_d,
        stress: stress_d,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "d_beckmann",
        equation: "seed eq. 6",
        arguments: &["α", "n·h", "|n×h|²"],
        colour: None,
        channels: 1,
        cap: FP32,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(d_beckmann(f64::from(t.a[0]), f64::from(t.a[1]), f64::from(t.a[2]))),
        sample: sample_d,
        stress: stress_d,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "lambda_ggx",
        equation: "Heitz 2014",
        arguments: &["α", "n·x"],
        colour: None,
        channels: 1,
        cap: FP32,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(lambda_ggx(f64::from(t.a[0]), f64::from(t.a[1]))),
        sample: sample_lambda,
        stress: stress_lambda,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "lambda_beckmann",
        equation: "Walter et al. 2007",
        arguments: &["α", "n·x"],
        colour: None,
        channels: 1,
        cap: FP32,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(lambda_beckmann(f64::from(t.a[0]), f64::from(t.a[1]))),
        sample: sample_lambda,
        stress: stress_lambda,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "g1_smith_ggx",
        equation: "seed eq. 8",
        arguments: &["α", "n·x"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(g1_smith_ggx(f64::from(t.a[0]), f64::from(t.a[1]))),
        sample: sample_lambda,
        stress: stress_lambda,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "g2_smith_separable_ggx",
        equation: "seed's G, eq. 8",
        arguments: &["α", "n·v", "n·l"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let [alpha, v, l, _] = t.a.map(f64::from);
            scalar(g2_smith_separable_ggx(alpha, v, l))
        },
        sample: sample_g2,
        stress: stress_g2,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "g2_smith_correlated_ggx",
        equation: "Heitz 2014",
        arguments: &["α", "n·v", "n·l"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let [alpha, v, l, _] = t.a.map(f64::from);
            scalar(g2_smith_correlated_ggx(alpha, v, l))
        },
        sample: sample_g2,
        stress: stress_g2,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "g2_smith_separable_beckmann",
        equation: "Heitz 2014",
        arguments: &["α", "n·v", "n·l"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let [alpha, v, l, _] = t.a.map(f64::from);
            scalar(g2_smith_separable_beckmann(alpha, v, l))
        },
        sample: sample_g2,
        stress: stress_g2,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "g2_smith_correlated_beckmann",
        equation: "Heitz 2014",
        arguments: &["α", "n·v", "n·l"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let [alpha, v, l, _] = t.a.map(f64::from);
            scalar(g2_smith_correlated_beckmann(alpha, v, l))
        },
        sample: sample_g2,
        stress: stress_g2,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "g2_v_cavity",
        equation: "Torrance & Sparrow 1967",
        arguments: &["n·h", "n·v", "n·l", "v·h"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let [h, v, l, vh] = t.a.map(f64::from);
            scalar(g2_v_cavity(h, v, l, vh))
        },
        sample: |rng, alpha| {
            let (v, l) = sample_directions(rng, alpha);
            let h = safe_half_vector(v, l, NORMAL);
            scalars([h[2], v[2], l[2], dot(v, h)])
        },
        stress: || grid(&[STRESS_COSINES, STRESS_COSINES, STRESS_COSINES, STRESS_COSINES]),
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "f_schlick",
        equation: "Schlick 1994, seed eq. 9",
        arguments: &["v·h"],
        colour: Some("F0"),
        channels: 4,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let (colour, v_dot_h) = (rgb(t.d), f64::from(t.a[0]));
            let [r, g, b] = f_schlick(colour, v_dot_h);
            [r, g, b, f_schlick_scalar(colour[0], v_dot_h)]
        },
        sample: |rng, _| {
            let v_dot_h = match rng.uniform() {
                u if u < 0.2 => rng.log_uniform(1e-7, 0.1), // grazing: F → 1
                u if u < 0.23 => 0.0,
                u if u < 0.26 => 1.0,
                u if u < 0.3 => -rng.uniform(),
                _ => rng.uniform(),
            };
            Tuple {
                a: [v_dot_h as f32, 0.0, 0.0, 0.0],
                d: colour(rng),
                ..Tuple::default()
            }
        },
        stress: || each_stress_colour(STRESS_COSINES),
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "e_fon_approx",
        equation: "Portsmouth et al. 2025",
        arguments: &["μ", "r"],
        colour: None,
        channels: 1,
        cap: FP32,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(e_fon_approx(f64::from(t.a[0]), f64::from(t.a[1]))),
        sample: |rng, _| scalars([sample_signed_cosine(rng), rng.uniform(), 0.0, 0.0]),
        // e_fon_approx(μ, r) takes the cosine first.
        stress: || {
            grid(&[STRESS_ALPHAS, STRESS_COSINES])
                .into_iter()
                .map(|t| scalars([f64::from(t.a[1]), f64::from(t.a[0]), 0.0, 0.0]))
                .collect()
        },
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "tonemap_pbr_neutral",
        equation: "Khronos 2024",
        arguments: &[],
        colour: Some("rgb"),
        channels: 3,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| rgb0(tonemap_pbr_neutral(rgb(t.d))),
        sample: |rng, _| {
            let mut channel = || match rng.uniform() {
                u if u < 0.05 => 0.0,
                u if u < 0.15 => rng.range(0.07, 0.09), // the toe's end, 0.08
                u if u < 0.25 => rng.range(0.75, 0.85), // compression start, 0.76 + offset
                _ => rng.log_uniform(1e-4, 1e3),
            };
            let c = [channel(), channel(), channel()];
            let grey = rng.uniform() < 0.1;
            let c = if grey { [c[0]; 3] } else { c };
            coloured([c[0] as f32, c[1] as f32, c[2] as f32, 0.0])
        },
        stress: stress_radiances,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "srgb_oetf",
        equation: "IEC 61966-2-1",
        arguments: &[],
        colour: Some("rgb"),
        channels: 4,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let colour = rgb(t.d);
            let [r, g, b] = srgb_oetf_rgb(colour);
            [r, g, b, srgb_oetf(colour[0])]
        },
        sample: |rng, _| {
            let mut channel = || match rng.uniform() {
                u if u < 0.2 => 0.0031308 * (1.0 + rng.range(-1e-3, 1e-3)), // the branch
                u if u < 0.3 => rng.uniform(),
                _ => rng.log_uniform(1e-7, 1.0),
            };
            let c = [channel(), channel(), channel()];
            coloured([c[0] as f32, c[1] as f32, c[2] as f32, 0.0])
        },
        stress: stress_radiances,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "wrap_seed",
        equation: "Seed eq. 18 (Fernando 2004)",
        arguments: &["n·l", "w1", "w2"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: true,
        eval: |t| {
            let [n_dot_l, w1, w2, _] = t.a.map(f64::from);
            scalar(wrap_seed(n_dot_l, w1, w2))
        },
        sample: |rng, _| scalars([rng.range(-1.0, 1.0), rng.uniform(), rng.log_uniform(1e-4, 1.0), 0.0]),
        stress: || grid(&[STRESS_COSINES, STRESS_ALPHAS, STRESS_ALPHAS]),
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "wrap_energy_conserving",
        equation: "saturate((n·l + w)/(1 + w)²)",
        arguments: &["n·l", "w"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: true,
        eval: |t| scalar(wrap_energy_conserving(f64::from(t.a[0]), f64::from(t.a[1]))),
        sample: |rng, _| scalars([rng.range(-1.0, 1.0), rng.uniform(), 0.0, 0.0]),
        stress: stress_cosine_and_weight,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "spec_blinn_phong",
        equation: "Blinn 1977 (seed eq. 5)",
        arguments: &["α", "n·h", "|n×h|²", "v·h"],
        colour: Some("F0"),
        channels: 3,
        cap: FP16,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let [alpha, n_dot_h, nxh2, v_dot_h] = t.a.map(f64::from);
            rgb0(spec_blinn_phong(alpha, n_dot_h, nxh2, rgb(t.d), v_dot_h))
        },
        sample: |rng, alpha| {
            let (sin, cos) = sample_half_or_below(rng, alpha).sin_cos();
            let a = [alpha, cos, sin * sin, sample_signed_cosine(rng)].map(|x| x as f32);
            Tuple {
                a,
                d: colour(rng),
                ..Tuple::default()
            }
        },
        stress: || {
            grid(&[STRESS_ALPHAS, STRESS_COSINES, STRESS_COSINES, STRESS_COSINES])
                .into_iter()
                .map(|t| Tuple {
                    d: [0.0, 1.0, 0.04, 0.0],
                    ..t
                })
                .collect()
        },
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "shadow_terminator",
        equation: "Chiang, Li & Burley 2019",
        arguments: &["n_g·l", "n_s·l", "n_g·n_s"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let [ng_l, ns_l, ng_ns, _] = t.a.map(f64::from);
            scalar(shadow_terminator(ng_l, ns_l, ng_ns))
        },
        sample: |rng, _| {
            let (ng_l, ns_l, ng_ns) = match rng.uniform() {
                // A bump: n_s up to 80° from n_g = +z, l anywhere about n_g.
                u if u < 0.4 => {
                    let ns = direction(rng.range(0.0, 80f64.to_radians()).cos(), rng.azimuth());
                    let l = direction(sample_signed_cosine(rng), rng.azimuth());
                    (l[2], dot(ns, l), ns[2])
                }
                // g = (n_g·l)/((n_s·l)(n_g·n_s)) within 1e-8 to 0.1 of 1, both sides.
                u if u < 0.7 => {
                    let (ns_l, ng_ns) = (sample_cosine(rng), sample_cosine(rng));
                    let g = 1.0 + rng.range(-1.0, 1.0) * rng.log_uniform(1e-8, 0.1);
                    ((g * ns_l * ng_ns.max(MIN_N_DOT_V)).min(1.0), ns_l, ng_ns)
                }
                // n_s at or beyond 90° from n_g: the MIN_N_DOT_V clamp.
                u if u < 0.8 => (
                    sample_signed_cosine(rng),
                    sample_signed_cosine(rng),
                    rng.range(-1.0, MIN_N_DOT_V),
                ),
                _ => (
                    sample_signed_cosine(rng),
                    sample_signed_cosine(rng),
                    sample_signed_cosine(rng),
                ),
            };
            scalars([ng_l, ns_l, ng_ns, 0.0])
        },
        stress: || grid(&[STRESS_COSINES, STRESS_COSINES, STRESS_COSINES]),
        rounding: None,
        promise: Some(terminator_continuity),
    },
    TermSpec {
        // r: D at (n·l, t); gba: the harness's preintegrated_kernel(t), the row's kernel at n·l = 0.
        name: "preintegrated_d",
        equation: "D(n·l, t) bilinear between the cell's four texels",
        arguments: &["n·l", "σκ"],
        colour: None,
        channels: 4,
        cap: SH_KERNEL,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: true,
        eval: |t| {
            let table = PreintegratedTable::get();
            let d = table.lookup(f64::from(t.a[0]), f64::from(t.a[1]))[0];
            let [_, k0, k1, k2] = table.lookup(0.0, f64::from(t.a[1]));
            [d, k0, k1, k2]
        },
        sample: |rng, _| {
            let t = if rng.uniform() < 0.1 {
                0.0
            } else {
                rng.log_uniform(1e-4, 1e4)
            };
            scalars([rng.range(-1.0, 1.0), t, 0.0, 0.0])
        },
        stress: stress_cosine_and_weight,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "wrap_energy_conserving_sh_kernel",
        equation: "Funk–Hecke",
        arguments: &["w"],
        colour: None,
        channels: 3,
        cap: SH_KERNEL,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: true,
        eval: |t| rgb0(wrap_energy_conserving_sh_kernel(f64::from(t.a[0]))),
        sample: |rng, _| scalars([rng.uniform(), 0.0, 0.0, 0.0]),
        stress: || grid(&[STRESS_ALPHAS]),
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "resolve_weight",
        equation: "Karis 2014",
        arguments: &[],
        colour: Some("rgb"),
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(resolve_weight(rgb(t.d))),
        // HDR radiance over many decades, some channels 0.
        sample: |rng, _| {
            let mut channel = || match rng.uniform() {
                u if u < 0.1 => 0.0,
                _ => rng.log_uniform(1e-4, 1e4) as f32,
            };
            coloured([channel(), channel(), channel(), 0.0])
        },
        stress: stress_radiances,
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "specular_aa_roughness",
        equation: "Tokuyoshi & Kaplanyan 2019",
        arguments: &["roughness", "|∂n/∂x|²+|∂n/∂y|²"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(specular_aa_roughness(f64::from(t.a[0]), f64::from(t.a[1]))),
        // The normal's change per pixel from none to the clamp and past it.
        sample: |rng, _| {
            let change = if rng.uniform() < 0.1 {
                0.0
            } else {
                rng.log_uniform(1e-8, 1e2)
            };
            scalars([rng.uniform(), change, 0.0, 0.0])
        },
        // The change is a sum of squares: never negative.
        stress: || {
            let changes: Vec<f32> = STRESS_ALPHAS
                .iter()
                .copied()
                .filter(|c| *c >= 0.0)
                .chain([f32::MAX])
                .collect();
            grid(&[STRESS_ALPHAS, &changes])
        },
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "gtao_slice_visibility",
        equation: "Jimenez et al. 2016 eq. 7",
        arguments: &["h0", "h1", "γ"],
        colour: None,
        channels: 1,
        cap: SLICE,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let [h0, h1, gamma, _] = t.a.map(f64::from);
            scalar(gtao_slice_visibility(h0, h1, gamma))
        },
        // Horizons as GTAO clamps them: within π/2 of the normal's angle γ.
        sample: |rng, _| {
            let gamma = rng.range(-FRAC_PI_2, FRAC_PI_2);
            let h0 = rng.range(gamma - FRAC_PI_2, 0.0);
            let h1 = rng.range(0.0, gamma + FRAC_PI_2);
            scalars([h0, h1, gamma, 0.0])
        },
        stress: || {
            let half = std::f32::consts::FRAC_PI_2;
            let mut out = Vec::new();
            for gamma in [-half, -0.5, 0.0, 0.5, half] {
                for h0 in [gamma - half, -1e-7, 0.0] {
                    for h1 in [0.0, 1e-7, gamma + half] {
                        out.extend(grid(&[&[h0.min(0.0)], &[h1.max(0.0)], &[gamma]]));
                    }
                }
            }
            out
        },
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "gtao_multi_bounce",
        equation: "Jimenez et al. 2016 eq. 10",
        arguments: &["x"],
        colour: Some("ρ"),
        channels: 3,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| rgb0(gtao_multi_bounce(f64::from(t.a[0]), rgb(t.d))),
        sample: sample_unit_and_colour,
        stress: || each_stress_colour(&[0.0, 1e-7, 0.5, 1.0]),
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "specular_occlusion",
        equation: "Lagarde & de Rousiers 2014 eq. 41",
        arguments: &["n·v", "x", "α"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let [n_dot_v, x, alpha, _] = t.a.map(f64::from);
            scalar(specular_occlusion(n_dot_v, x, alpha))
        },
        sample: |rng, alpha| scalars([sample_signed_cosine(rng), rng.uniform(), alpha, 0.0]),
        stress: || grid(&[STRESS_COSINES, &[0.0, 1e-7, 0.5, 1.0], STRESS_ALPHAS]),
        rounding: Some(Rounding {
            bound: specular_occlusion_rounding,
            reason: SPECULAR_OCCLUSION_ROUNDING,
        }),
        promise: None,
    },
    TermSpec {
        name: "plane_point_irradiance",
        equation: "the inverse-square law with Lambert's cosine",
        arguments: &["height", "d²"],
        colour: None,
        channels: 1,
        cap: FP32,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(plane_point_irradiance(f64::from(t.a[0]), f64::from(t.a[1]))),
        // A light from 1e-4 to 1e4 away, at any height (below the plane: 0).
        sample: |rng, _| {
            let distance = rng.log_uniform(1e-4, 1e4);
            scalars([distance * rng.range(-1.0, 1.0), distance * distance, 0.0, 0.0])
        },
        // Straight above, grazing, nearly in the plane, at MIN_LIGHT_DISTANCE2 and far.
        stress: || {
            let mut out = Vec::new();
            for distance in [1e-4f32, 1e-2, 1.0, 1e3, 1e4] {
                for h in [1.0, 0.5, 1e-3, 1e-7, 0.0, -0.5] {
                    out.extend(grid(&[&[distance * h], &[distance * distance]]));
                }
            }
            out
        },
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "specular_energy_compensation",
        equation: "Fdez-Agüera 2019",
        arguments: &["E"],
        colour: Some("F0"),
        channels: 3,
        cap: COMPENSATION,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| rgb0(specular_energy_compensation(f64::from(t.a[0]), rgb(t.d))),
        // E over the tables' range and below the clamp.
        sample: sample_unit_and_colour,
        stress: || each_stress_colour(&[-1.0, 0.0, DENORMAL, 0.05, 0.3, 0.99999994, 1.0, 2.0]),
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "sphere_cap_irradiance",
        equation: "Snyder 1996",
        arguments: &["cos θ", "sin α"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(sphere_cap_irradiance(f64::from(t.a[0]), f64::from(t.a[1]))),
        // Spheres from touching the point (sin α = 1) to 50 radii away, at any angle.
        sample: |rng, _| scalars([rng.range(-1.0, 1.0), rng.range(0.02, 1.0), 0.0, 0.0]),
        // On the horizon, at the branches' edges (cos θ = ±sin α), straight above and below.
        stress: || {
            let mut out = Vec::new();
            for sin_alpha in [0.02f32, 0.1, 0.5, 0.9, 1.0] {
                for cos_theta in [-1.0, -sin_alpha, 0.0, sin_alpha, 1.0] {
                    out.extend(grid(&[&[cos_theta], &[sin_alpha]]));
                }
            }
            out
        },
        rounding: Some(Rounding {
            bound: sphere_cap_rounding,
            reason: SPHERE_CAP_ROUNDING,
        }),
        promise: None,
    },
    TermSpec {
        name: "micro_shadowing",
        equation: "Filament, after Chan 2018",
        arguments: &["n·l", "ao"],
        colour: None,
        channels: 1,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(micro_shadowing(f64::from(t.a[0]), f64::from(t.a[1]))),
        sample: |rng, _| scalars([sample_signed_cosine(rng), rng.uniform(), 0.0, 0.0]),
        // Nothing open (ao = 0), nearly and fully open (the infinite aperture), outside
        // [0, 1], at the cone's edge n·l = √(1 − ao) and on both sides of the horizon.
        stress: || {
            let mut out = grid(&[STRESS_COSINES, &[-0.5, 0.0, DENORMAL, 1e-7, 0.5, 0.75, 0.99999994, 1.0, 1.5]]);
            for ao in [0.0f32, 0.19, 0.75, 0.96] {
                out.extend(grid(&[&[(1.0 - ao).sqrt()], &[ao]]));
            }
            out
        },
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "prefiltered_taps",
        equation: "Walter et al. 2007, eq. 14",
        arguments: &["n·v"],
        colour: None,
        channels: 3,
        cap: MAX_TAPS,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let [taps, width, spacing] = prefiltered_taps(f64::from(t.a[0]));
            [taps, width, spacing, 0.0]
        },
        sample: |rng, _| scalars([sample_signed_cosine(rng), 0.0, 0.0, 0.0]),
        // Below the horizon and its clamp, the widening taps, either side of ½, head-on and
        // past it.
        stress: || grid(&[&[-1.0, 0.0, 1e-7, 1e-4, 0.05, 0.2, 0.49999997, 0.5, 0.50000006, 0.9, 1.0, 1.5]]),
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "prefiltered_lod",
        equation: "α = 2^(k − last)",
        arguments: &["α", "last mip"],
        colour: None,
        channels: 1,
        cap: LAST_MIP,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(prefiltered_lod(f64::from(t.a[0]), f64::from(t.a[1]))),
        sample: |rng, _| scalars([rng.uniform(), 6.0, 0.0, 0.0]),
        // The mirror, either side of mip 1's α of 2^−5 (last mip 6), and 1; the cube's 7 mips,
        // a smaller and a larger one.
        stress: || grid(&[&[0.0, 1e-4, 0.031249998, 0.03125, 0.031250004, 0.5, 1.0], &[2.0, 6.0, 8.0]]),
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "sun_alpha",
        equation: "α'² = α² + θ²/8",
        arguments: &["α", "θ"],
        colour: None,
        channels: 1,
        cap: SUN_ALPHA,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| scalar(sun_alpha(f64::from(t.a[0]), f64::from(t.a[1]))),
        // α over its range, a sun up to the widest.
        sample: |rng, _| scalars([rng.uniform(), widest_sun() * rng.uniform(), 0.0, 0.0]),
        // The smallest α, a point, the bench's 1.5° sun and the widest.
        stress: || grid(&[&[0.002025, 0.01, 0.09, 1.0], &[0.0, 1e-6, 0.02618, widest_sun() as f32]]),
        rounding: None,
        promise: None,
    },
    TermSpec {
        name: "octahedral_uv",
        equation: "Engelhardt & Dachsbacher 2008",
        arguments: &["d.x", "d.y", "d.z", "side"],
        colour: None,
        channels: 2,
        cap: UNIT,
        tolerance: FP32_ARITHMETIC,
        lighting_weight: false,
        eval: |t| {
            let d = [t.a[0], t.a[1], t.a[2]].map(f64::from);
            let [u, v] = octahedral_uv(d, f64::from(t.a[3]));
            [u, v, 0.0, 0.0]
        },
        // Any direction, unit or not (the map reads the tap's sum), in the split sum's maps
        // and a smaller and a larger one.
        sample: |rng, _| {
            let [x, y, z] = uniform_sphere(rng);
            let length = if rng.uniform() < 0.5 { 1.0 } else { rng.range(0.5, 2.0) };
            let side = [130.0, f64::from(OCTAHEDRAL_SIDE), 1026.0][(rng.uniform() * 3.0) as usize % 3];
            scalars([x * length, y * length, z * length, side])
        },
        // The axes (the centre, the square's edges' midpoints, its corners at −z), the fold
        // z = 0, signed zeros.
        stress: || {
            let axis = [-1.0, -0.0, 0.0, 1.0];
            let mut out = grid(&[&axis, &axis, &axis, &[OCTAHEDRAL_SIDE as f32]]);
            out.retain(|t| t.a[..3].iter().any(|&c| c != 0.0));
            let fold = [&[0.6, -0.6][..], &[0.8, -0.8, DENORMAL], &[0.0, -0.0, -DENORMAL], &[OCTAHEDRAL_SIDE as f32]];
            out.extend(grid(&fold));
            out
        },
        rounding: None,
        promise: None,
    },
];

/// The last mip `prefiltered_lod` is asked about, which roughness 1 reads.
const LAST_MIP: Cap = Cap {
    value: 8.0,
    label: "<= the last mip (8 at most)",
};

/// The widest sun split sum lifts out of a map, in radians.
fn widest_sun() -> f64 {
    SUN_MAX_RADIUS_DEGREES.to_radians()
}

/// `sun_alpha` at α = 1 under the widest sun, with a few ulps to spare.
const SUN_ALPHA: Cap = Cap {
    value: 1.0 + 1e-3,
    label: "<= √(1 + θ²/8) at α = 1 under the widest sun",
};

/// The taps' largest channel, their count (width ≤ 1, spacing ≤ 2, at two taps).
const MAX_TAPS: Cap = Cap {
    value: PREFILTERED_MAX_TAPS as f64,
    label: "<= PREFILTERED_MAX_TAPS",
};

/// The energy compensation's largest factor, 1/MIN_SPECULAR_ALBEDO, with the few ulps
/// fp32's reciprocal may round it up by.
const COMPENSATION: Cap = Cap {
    value: 1.0 / MIN_SPECULAR_ALBEDO * (1.0 + 4.0 * f32::EPSILON as f64),
    label: "<= 1/MIN_SPECULAR_ALBEDO",
};

/// A term: its index in [`TERMS`], which is its `FUNCTION` in verify_brdf.comp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Term(usize);

impl Term {
    pub fn all() -> impl Iterator<Item = Term> {
        (0..TERMS.len()).map(Term)
    }

    pub fn spec(self) -> &'static TermSpec {
        &TERMS[self.0]
    }

    /// The harness's `FUNCTION`.
    pub fn id(self) -> u32 {
        self.0 as u32
    }

    pub fn sample(self, rng: &mut Rng) -> Tuple {
        let alpha = super::functions::sample_alpha(rng);
        (self.spec().sample)(rng, alpha)
    }

    /// The tuple's arguments, named, for messages.
    pub fn describe(self, t: &Tuple) -> String {
        let spec = self.spec();
        let mut parts: Vec<String> = spec
            .arguments
            .iter()
            .zip(t.a)
            .map(|(n, x)| format!("{n}={x:e}"))
            .collect();
        parts.extend(
            spec.colour
                .map(|name| format!("{name}=({:e}, {:e}, {:e})", t.d[0], t.d[1], t.d[2])),
        );
        parts.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HARNESS: &str = include_str!("../../shaders/verify_brdf.comp");

    /// The `case` lines of verify_brdf.comp's `term` switch: (FUNCTION, the line).
    fn glsl_cases() -> Vec<(u32, &'static str)> {
        let start = HARNESS
            .find("vec4 term(Tuple t) {")
            .expect("verify_brdf.comp defines term()");
        let body = &HARNESS[start..][..HARNESS[start..].find("\n}").expect("term() ends")];
        body.lines()
            .filter_map(|line| {
                let rest = line.trim().strip_prefix("case ")?;
                let (id, call) = rest.split_once("u:").expect("a case line is `case ku: return …;`");
                Some((id.parse().expect("a case's FUNCTION is a number"), call))
            })
            .collect()
    }

    /// Whether `line` calls the function `name` (not one whose name merely ends in it).
    fn calls(line: &str, name: &str) -> bool {
        line.match_indices(&format!("{name}(")).any(|(i, _)| {
            !line[..i]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_alphanumeric() || c == '_')
        })
    }

    #[test]
    fn the_harness_calls_each_term_at_its_index() {
        let cases = glsl_cases();
        let ids: Vec<u32> = cases.iter().map(|&(id, _)| id).collect();
        assert_eq!(
            ids,
            Term::all().map(Term::id).collect::<Vec<_>>(),
            "one case per term, in order"
        );
        for (term, (_, line)) in Term::all().zip(&cases) {
            let name = term.spec().name;
            assert!(calls(line, name), "case {}u does not call {name}: {line}", term.id());
        }
        // The models' FUNCTION values start above the terms'.
        let first_model = HARNESS
            .lines()
            .find_map(|l| l.strip_prefix("const uint FIRST_MODEL = ")?.strip_suffix("u;"))
            .expect("verify_brdf.comp declares FIRST_MODEL");
        assert!(TERMS.len() <= first_model.parse::<usize>().expect("a number"));
    }

    /// The comment above the GLSL definition of `name` in shaders/lib/, and its file's
    /// leading comment.
    fn glsl_comments(name: &str) -> Option<String> {
        let directory = concat!(env!("CARGO_MANIFEST_DIR"), "/shaders/lib");
        for entry in std::fs::read_dir(directory).expect("shaders/lib") {
            let text = std::fs::read_to_string(entry.expect("an entry").path()).expect("a shader");
            let lines: Vec<&str> = text.lines().collect();
            let definition = lines.iter().position(|l| {
                l.split_once(' ')
                    .is_some_and(|(ty, rest)| !ty.starts_with("//") && rest.starts_with(&format!("{name}(")))
            });
            if let Some(at) = definition {
                let comment = |lines: &mut dyn Iterator<Item = &str>| -> Vec<String> {
                    lines
                        .take_while(|l| l.starts_with("//"))
                        .map(|l| l.trim_start_matches('/').trim().to_owned())
                        .collect()
                };
                let mut above = comment(&mut lines[..at].iter().rev().copied());
                above.reverse();
                above.extend(comment(&mut lines.iter().copied()));
                return Some(above.join(" "));
            }
        }
        None
    }

    #[test]
    fn each_terms_equation_is_the_one_its_shader_names() {
        for spec in TERMS {
            let comments = glsl_comments(spec.name).unwrap_or_else(|| panic!("shaders/lib has no {}", spec.name));
            assert!(
                comments.contains(spec.equation),
                "{}: its shader's comment does not name {:?}: {comments}",
                spec.name,
                spec.equation
            );
        }
    }

    #[test]
    fn terms_are_named_once_and_fit_the_harness() {
        for (i, a) in TERMS.iter().enumerate() {
            assert!(TERMS[i + 1..].iter().all(|b| b.name != a.name), "{} twice", a.name);
            assert!((1..=4).contains(&a.channels) && a.arguments.len() <= 4, "{}", a.name);
            assert!(!(a.stress)().is_empty(), "{} has no stress inputs", a.name);
        }
    }
}

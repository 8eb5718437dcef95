//! What `argil verify` evaluates: every function of `shaders/lib/brdf.glsl` and
//! `tonemap.glsl` (and of `msaa_resolve.glsl` and `specular_aa.glsl`) that the harness `shaders/verify_brdf.comp` can call (and, through
//! `normals` and `composite`, those of `normal_mapping.glsl` and `shading.glsl`), the input
//! tuples it is fed (random over the whole domain, and stress inputs), and the f64 side of
//! the harness, which feeds the twins in `src/brdf` the very same f32 inputs.

use std::f64::consts::FRAC_PI_2;

use bytemuck::{Pod, Zeroable};

use crate::brdf::antialiasing::{resolve_weight, specular_aa_roughness};
use crate::brdf::bounce::plane_point_irradiance;
use crate::brdf::diffuse::{diffuse_eon, diffuse_lambert, diffuse_oren_nayar, e_fon_approx};
use crate::brdf::distribution::{d_beckmann, d_ggx};
use crate::brdf::fresnel::{f_schlick, f_schlick_scalar};
use crate::brdf::geometry::{
    g1_smith_ggx, g2_smith_correlated_beckmann, g2_smith_correlated_ggx, g2_smith_separable_beckmann,
    g2_smith_separable_ggx, g2_v_cavity, lambda_beckmann, lambda_ggx,
};
use crate::brdf::occlusion::{gtao_multi_bounce, gtao_slice_visibility, specular_occlusion};
use crate::brdf::shading::shadow_terminator;
use crate::brdf::specular::{spec_blinn_phong, spec_cook_torrance, spec_torrance_sparrow, Distribution, Geometry};
use crate::brdf::subsurface::{wrap_energy_conserving_sh_kernel, PreintegratedTable};
use crate::brdf::tonemap::{srgb_oetf, srgb_oetf_rgb, tonemap_pbr_neutral};
use crate::brdf::wrap::{wrap_energy_conserving, wrap_seed};
use crate::brdf::{cross, dot, safe_half_vector, Vec3, FP16_MAX, MAX_ALPHA, MIN_ALPHA, MIN_N_DOT_V};

use super::composite::Composite;
use super::normals::UnitVector;
use crate::rng::Rng;

/// One input of the harness, as `Tuple` in verify_brdf.comp. Terms: `a` holds the scalar
/// arguments and `d` a colour argument. Models: `a` = (n, p), `b` = (v, 0), `c` = (l, 0),
/// `d` = (F0 or ρ, 0), p being α, σ or r. Unit vectors and `brdf_cos`: see `UnitVector` and
/// `Composite`; only `brdf_cos`, whose material has four colours, uses `e`, `f`, `g` and `h`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct Tuple {
    pub a: [f32; 4],
    pub b: [f32; 4],
    pub c: [f32; 4],
    pub d: [f32; 4],
    pub e: [f32; 4],
    pub f: [f32; 4],
    pub g: [f32; 4],
    pub h: [f32; 4],
}

/// What the harness writes per tuple: the value (up to four channels) and, for models, the
/// value with v and l exchanged.
pub type Values<T> = [[T; 4]; 2];

/// Scalar and colour terms. The value is the GLSL `FUNCTION` of verify_brdf.comp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Term {
    DGgx = 0,
    DBeckmann = 1,
    LambdaGgx = 2,
    LambdaBeckmann = 3,
    G1SmithGgx = 4,
    G2SmithSeparableGgx = 5,
    G2SmithCorrelatedGgx = 6,
    G2SmithSeparableBeckmann = 7,
    G2SmithCorrelatedBeckmann = 8,
    G2VCavity = 9,
    FSchlick = 10,
    EFonApprox = 11,
    TonemapPbrNeutral = 12,
    SrgbOetf = 13,
    WrapSeed = 14,
    WrapEnergyConserving = 15,
    SpecBlinnPhong = 16,
    ShadowTerminator = 17,
    PreintegratedLookup = 18,
    WrapEnergyConservingShKernel = 19,
    ResolveWeight = 20,
    SpecularAaRoughness = 21,
    GtaoSliceVisibility = 22,
    GtaoMultiBounce = 23,
    SpecularOcclusion = 24,
    PlanePointIrradiance = 25,
}

/// BRDF models of directions. The value is the GLSL `FUNCTION` of verify_brdf.comp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    Lambert = 32,
    OrenNayar = 33,
    Eon = 34,
    BlinnPhong = 35,
    TorranceSparrow = 36,
    CookTorranceGgxSeparable = 37,
    CookTorranceGgxCorrelated = 38,
    CookTorranceBeckmannSeparable = 39,
    CookTorranceBeckmannCorrelated = 40,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    Term(Term),
    Model(Model),
    /// Unit vectors of normal_mapping.glsl and shading.glsl.
    UnitVector(UnitVector),
    /// `brdf_cos` of shading.glsl for one combination of models.
    Composite(Composite),
}

/// The largest value a function may return, and why.
#[derive(Clone, Copy, Debug)]
pub struct Cap {
    pub value: f64,
    pub label: &'static str,
}

/// What a function's values must be.
#[derive(Clone, Copy, Debug)]
pub enum Output {
    /// Every channel finite, ≥ 0 and under the cap.
    Capped(Cap),
    /// rgb a finite unit vector: ||n| − 1| ≤ `UNIT_TOLERANCE`.
    Unit,
}

/// ||n| − 1| allowed of a unit vector: fp32 normalisation is good to a few 1e-7.
pub const UNIT_TOLERANCE: f64 = 1e-5;

/// A fraction: masking, Fresnel, display values, wrap weights.
const UNIT: Cap = Cap {
    value: 1.0,
    label: "<= 1",
};
/// Lobes clamp D·G/(4 n·v n·l) to FP16_MAX, so an RGBA16F target stays finite.
const FP16: Cap = Cap {
    value: FP16_MAX,
    label: "<= FP16_MAX",
};
/// Funk–Hecke coefficients of a transfer ≤ 1 (k₀ ≤ 4π·max/π = 4 for the uniform 1/π).
const SH_KERNEL: Cap = Cap {
    value: 4.0,
    label: "<= 4",
};
/// GTAO's slice integral of cos(θ − γ)|sin θ| reaches ∫₀^π sin² = π/2 at γ = π/2 (fp32's
/// π/2, which rounds up).
const SLICE: Cap = Cap {
    value: std::f32::consts::FRAC_PI_2 as f64,
    label: "<= π/2",
};
/// Intermediates (D, Λ, E_FON) are never stored, and brdf_cos is scaled by the irradiance
/// before it is: only fp32 overflow matters.
const FP32: Cap = Cap {
    value: f32::MAX as f64,
    label: "<= fp32 max",
};

impl Term {
    pub const ALL: [Term; 26] = [
        Term::DGgx,
        Term::DBeckmann,
        Term::LambdaGgx,
        Term::LambdaBeckmann,
        Term::G1SmithGgx,
        Term::G2SmithSeparableGgx,
        Term::G2SmithCorrelatedGgx,
        Term::G2SmithSeparableBeckmann,
        Term::G2SmithCorrelatedBeckmann,
        Term::G2VCavity,
        Term::FSchlick,
        Term::EFonApprox,
        Term::TonemapPbrNeutral,
        Term::SrgbOetf,
        Term::WrapSeed,
        Term::WrapEnergyConserving,
        Term::SpecBlinnPhong,
        Term::ShadowTerminator,
        Term::PreintegratedLookup,
        Term::WrapEnergyConservingShKernel,
        Term::ResolveWeight,
        Term::SpecularAaRoughness,
        Term::GtaoSliceVisibility,
        Term::GtaoMultiBounce,
        Term::SpecularOcclusion,
        Term::PlanePointIrradiance,
    ];

    /// The GLSL function's name (F and sRGB also evaluate their scalar overloads).
    pub fn name(self) -> &'static str {
        match self {
            Term::DGgx => "d_ggx",
            Term::DBeckmann => "d_beckmann",
            Term::LambdaGgx => "lambda_ggx",
            Term::LambdaBeckmann => "lambda_beckmann",
            Term::G1SmithGgx => "g1_smith_ggx",
            Term::G2SmithSeparableGgx => "g2_smith_separable_ggx",
            Term::G2SmithCorrelatedGgx => "g2_smith_correlated_ggx",
            Term::G2SmithSeparableBeckmann => "g2_smith_separable_beckmann",
            Term::G2SmithCorrelatedBeckmann => "g2_smith_correlated_beckmann",
            Term::G2VCavity => "g2_v_cavity",
            Term::FSchlick => "f_schlick",
            Term::EFonApprox => "e_fon_approx",
            Term::TonemapPbrNeutral => "tonemap_pbr_neutral",
            Term::SrgbOetf => "srgb_oetf",
            Term::WrapSeed => "wrap_seed",
            Term::WrapEnergyConserving => "wrap_energy_conserving",
            Term::SpecBlinnPhong => "spec_blinn_phong",
            Term::ShadowTerminator => "shadow_terminator",
            Term::PreintegratedLookup => "preintegrated_lookup",
            Term::WrapEnergyConservingShKernel => "wrap_energy_conserving_sh_kernel",
            Term::ResolveWeight => "resolve_weight",
            Term::SpecularAaRoughness => "specular_aa_roughness",
            Term::GtaoSliceVisibility => "gtao_slice_visibility",
            Term::GtaoMultiBounce => "gtao_multi_bounce",
            Term::SpecularOcclusion => "specular_occlusion",
            Term::PlanePointIrradiance => "plane_point_irradiance",
        }
    }

    /// The wrap and subsurface terms: weights of n·l for lighting, not BRDFs.
    pub fn is_lighting_weight(self) -> bool {
        matches!(
            self,
            Term::WrapSeed
                | Term::WrapEnergyConserving
                | Term::PreintegratedLookup
                | Term::WrapEnergyConservingShKernel
        )
    }

    /// Names of the scalar arguments in `Tuple::a`, and of the colour argument in `Tuple::d`.
    fn arguments(self) -> (&'static [&'static str], Option<&'static str>) {
        match self {
            Term::DGgx | Term::DBeckmann => (&["α", "n·h", "|n×h|²"], None),
            Term::LambdaGgx | Term::LambdaBeckmann | Term::G1SmithGgx => (&["α", "n·x"], None),
            Term::G2SmithSeparableGgx
            | Term::G2SmithCorrelatedGgx
            | Term::G2SmithSeparableBeckmann
            | Term::G2SmithCorrelatedBeckmann => (&["α", "n·v", "n·l"], None),
            Term::G2VCavity => (&["n·h", "n·v", "n·l", "v·h"], None),
            Term::FSchlick => (&["v·h"], Some("F0")),
            Term::EFonApprox => (&["μ", "r"], None),
            Term::TonemapPbrNeutral | Term::SrgbOetf => (&[], Some("rgb")),
            Term::WrapSeed => (&["n·l", "w1", "w2"], None),
            Term::WrapEnergyConserving => (&["n·l", "w"], None),
            Term::SpecBlinnPhong => (&["α", "n·h", "|n×h|²", "v·h"], Some("F0")),
            Term::ShadowTerminator => (&["n_g·l", "n_s·l", "n_g·n_s"], None),
            Term::PreintegratedLookup => (&["n·l", "σκ"], None),
            Term::WrapEnergyConservingShKernel => (&["w"], None),
            Term::ResolveWeight => (&[], Some("rgb")),
            Term::SpecularAaRoughness => (&["roughness", "|∂n/∂x|²+|∂n/∂y|²"], None),
            Term::GtaoSliceVisibility => (&["h0", "h1", "γ"], None),
            Term::GtaoMultiBounce => (&["x"], Some("ρ")),
            Term::SpecularOcclusion => (&["n·v", "x", "α"], None),
            Term::PlanePointIrradiance => (&["height", "d²"], None),
        }
    }

    fn channels(self) -> usize {
        match self {
            Term::FSchlick | Term::SrgbOetf | Term::PreintegratedLookup => 4,
            Term::TonemapPbrNeutral
            | Term::SpecBlinnPhong
            | Term::WrapEnergyConservingShKernel
            | Term::GtaoMultiBounce => 3,
            _ => 1,
        }
    }

    fn cap(self) -> Cap {
        match self {
            Term::DGgx
            | Term::DBeckmann
            | Term::LambdaGgx
            | Term::LambdaBeckmann
            | Term::EFonApprox
            | Term::PlanePointIrradiance => FP32,
            Term::SpecBlinnPhong => FP16,
            Term::PreintegratedLookup | Term::WrapEnergyConservingShKernel => SH_KERNEL,
            Term::GtaoSliceVisibility => SLICE,
            _ => UNIT,
        }
    }

    /// The f64 twin on the tuple's (widened) f32 arguments.
    fn eval(self, t: &Tuple) -> [f64; 4] {
        let [x, y, z, w] = t.a.map(f64::from);
        let colour = rgb(t.d);
        let scalar = |value: f64| [value; 4];
        match self {
            Term::DGgx => scalar(d_ggx(x, y, z)),
            Term::DBeckmann => scalar(d_beckmann(x, y, z)),
            Term::LambdaGgx => scalar(lambda_ggx(x, y)),
            Term::LambdaBeckmann => scalar(lambda_beckmann(x, y)),
            Term::G1SmithGgx => scalar(g1_smith_ggx(x, y)),
            Term::G2SmithSeparableGgx => scalar(g2_smith_separable_ggx(x, y, z)),
            Term::G2SmithCorrelatedGgx => scalar(g2_smith_correlated_ggx(x, y, z)),
            Term::G2SmithSeparableBeckmann => scalar(g2_smith_separable_beckmann(x, y, z)),
            Term::G2SmithCorrelatedBeckmann => scalar(g2_smith_correlated_beckmann(x, y, z)),
            Term::G2VCavity => scalar(g2_v_cavity(x, y, z, w)),
            Term::FSchlick => {
                let [r, g, b] = f_schlick(colour, x);
                [r, g, b, f_schlick_scalar(colour[0], x)]
            }
            Term::EFonApprox => scalar(e_fon_approx(x, y)),
            Term::TonemapPbrNeutral => {
                let [r, g, b] = tonemap_pbr_neutral(colour);
                [r, g, b, 0.0]
            }
            Term::SrgbOetf => {
                let [r, g, b] = srgb_oetf_rgb(colour);
                [r, g, b, srgb_oetf(colour[0])]
            }
            Term::WrapSeed => scalar(wrap_seed(x, y, z)),
            Term::WrapEnergyConserving => scalar(wrap_energy_conserving(x, y)),
            Term::SpecBlinnPhong => {
                let [r, g, b] = spec_blinn_phong(x, y, z, colour, w);
                [r, g, b, 0.0]
            }
            Term::ShadowTerminator => scalar(shadow_terminator(x, y, z)),
            Term::PreintegratedLookup => PreintegratedTable::get().lookup(x, y),
            Term::WrapEnergyConservingShKernel => {
                let [k0, k1, k2] = wrap_energy_conserving_sh_kernel(x);
                [k0, k1, k2, 0.0]
            }
            Term::ResolveWeight => scalar(resolve_weight(colour)),
            Term::SpecularAaRoughness => scalar(specular_aa_roughness(x, y)),
            Term::GtaoSliceVisibility => scalar(gtao_slice_visibility(x, y, z)),
            Term::GtaoMultiBounce => {
                let [r, g, b] = gtao_multi_bounce(x, colour);
                [r, g, b, 0.0]
            }
            Term::SpecularOcclusion => scalar(specular_occlusion(x, y, z)),
            Term::PlanePointIrradiance => scalar(plane_point_irradiance(x, y)),
        }
    }

    /// A random tuple over the whole domain, denser where the function is hard: near
    /// n·h = 1 inside narrow lobes, at grazing angles, near branch points.
    fn sample(self, rng: &mut Rng) -> Tuple {
        let alpha = sample_alpha(rng);
        let scalars = |a: [f64; 4]| Tuple {
            a: a.map(|x| x as f32),
            ..Tuple::default()
        };
        match self {
            Term::DGgx | Term::DBeckmann => {
                let theta = if rng.uniform() < 0.03 {
                    rng.range(FRAC_PI_2, std::f64::consts::PI) // below the horizon: D = 0
                } else {
                    sample_half_angle(rng, alpha)
                };
                let (sin, cos) = theta.sin_cos();
                scalars([alpha, cos, sin * sin, 0.0])
            }
            Term::LambdaGgx | Term::LambdaBeckmann | Term::G1SmithGgx => {
                scalars([alpha, sample_signed_cosine(rng), 0.0, 0.0])
            }
            Term::EFonApprox => scalars([sample_signed_cosine(rng), rng.uniform(), 0.0, 0.0]),
            Term::G2SmithSeparableGgx
            | Term::G2SmithCorrelatedGgx
            | Term::G2SmithSeparableBeckmann
            | Term::G2SmithCorrelatedBeckmann => {
                scalars([alpha, sample_signed_cosine(rng), sample_signed_cosine(rng), 0.0])
            }
            Term::G2VCavity => {
                let (v, l) = sample_directions(rng, alpha);
                let h = safe_half_vector(v, l, NORMAL);
                scalars([h[2], v[2], l[2], dot(v, h)])
            }
            Term::FSchlick => {
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
            }
            Term::TonemapPbrNeutral => {
                let mut channel = || match rng.uniform() {
                    u if u < 0.05 => 0.0,
                    u if u < 0.15 => rng.range(0.07, 0.09), // the toe's end, 0.08
                    u if u < 0.25 => rng.range(0.75, 0.85), // compression start, 0.76 + offset
                    _ => rng.log_uniform(1e-4, 1e3),
                };
                let c = [channel(), channel(), channel()];
                let grey = rng.uniform() < 0.1;
                let c = if grey { [c[0]; 3] } else { c };
                Tuple {
                    d: [c[0] as f32, c[1] as f32, c[2] as f32, 0.0],
                    ..Tuple::default()
                }
            }
            Term::SrgbOetf => {
                let mut channel = || match rng.uniform() {
                    u if u < 0.2 => 0.0031308 * (1.0 + rng.range(-1e-3, 1e-3)), // the branch
                    u if u < 0.3 => rng.uniform(),
                    _ => rng.log_uniform(1e-7, 1.0),
                };
                let c = [channel(), channel(), channel()];
                Tuple {
                    d: [c[0] as f32, c[1] as f32, c[2] as f32, 0.0],
                    ..Tuple::default()
                }
            }
            Term::WrapSeed => scalars([rng.range(-1.0, 1.0), rng.uniform(), rng.log_uniform(1e-4, 1.0), 0.0]),
            Term::WrapEnergyConserving => scalars([rng.range(-1.0, 1.0), rng.uniform(), 0.0, 0.0]),
            Term::PreintegratedLookup => {
                let t = if rng.uniform() < 0.1 {
                    0.0
                } else {
                    rng.log_uniform(1e-4, 1e4)
                };
                scalars([rng.range(-1.0, 1.0), t, 0.0, 0.0])
            }
            Term::WrapEnergyConservingShKernel => scalars([rng.uniform(), 0.0, 0.0, 0.0]),
            Term::ResolveWeight => {
                // HDR radiance over many decades, some channels 0.
                let mut channel = || match rng.uniform() {
                    u if u < 0.1 => 0.0,
                    _ => rng.log_uniform(1e-4, 1e4) as f32,
                };
                Tuple {
                    d: [channel(), channel(), channel(), 0.0],
                    ..Tuple::default()
                }
            }
            Term::SpecularAaRoughness => {
                // The normal's change per pixel from none to the clamp and past it.
                let change = if rng.uniform() < 0.1 {
                    0.0
                } else {
                    rng.log_uniform(1e-8, 1e2)
                };
                scalars([rng.uniform(), change, 0.0, 0.0])
            }
            Term::SpecBlinnPhong => {
                let theta = if rng.uniform() < 0.03 {
                    rng.range(FRAC_PI_2, std::f64::consts::PI) // below the horizon: 0
                } else {
                    sample_half_angle(rng, alpha)
                };
                let (sin, cos) = theta.sin_cos();
                let a = [alpha, cos, sin * sin, sample_signed_cosine(rng)].map(|x| x as f32);
                Tuple {
                    a,
                    d: colour(rng),
                    ..Tuple::default()
                }
            }
            Term::ShadowTerminator => {
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
            }
            Term::GtaoSliceVisibility => {
                // Horizons as GTAO clamps them: within π/2 of the normal's angle γ.
                let gamma = rng.range(-FRAC_PI_2, FRAC_PI_2);
                let h0 = rng.range(gamma - FRAC_PI_2, 0.0);
                let h1 = rng.range(0.0, gamma + FRAC_PI_2);
                scalars([h0, h1, gamma, 0.0])
            }
            Term::GtaoMultiBounce => Tuple {
                a: [rng.uniform() as f32, 0.0, 0.0, 0.0],
                d: colour(rng),
                ..Tuple::default()
            },
            Term::SpecularOcclusion => scalars([sample_signed_cosine(rng), rng.uniform(), alpha, 0.0]),
            Term::PlanePointIrradiance => {
                // A light from 1e-4 to 1e4 away, at any height (below the plane: 0).
                let distance = rng.log_uniform(1e-4, 1e4);
                scalars([distance * rng.range(-1.0, 1.0), distance * distance, 0.0, 0.0])
            }
        }
    }

    /// Degenerate and extreme arguments: every combination of the stress values.
    fn stress(self) -> Vec<Tuple> {
        let mut out = Vec::new();
        let mut push = |a: [f32; 4], d: [f32; 4]| {
            out.push(Tuple {
                a,
                d,
                ..Tuple::default()
            })
        };
        match self {
            Term::DGgx | Term::DBeckmann => {
                for &alpha in STRESS_ALPHAS {
                    for &c in STRESS_COSINES {
                        for &s in STRESS_COSINES {
                            push([alpha, c, s, 0.0], [0.0; 4]);
                        }
                    }
                }
            }
            Term::LambdaGgx | Term::LambdaBeckmann | Term::G1SmithGgx | Term::EFonApprox => {
                for &p in STRESS_ALPHAS {
                    for &c in STRESS_COSINES {
                        // e_fon_approx(μ, r) takes the cosine first, the others (α, μ).
                        let a = if self == Term::EFonApprox {
                            [c, p, 0.0, 0.0]
                        } else {
                            [p, c, 0.0, 0.0]
                        };
                        push(a, [0.0; 4]);
                    }
                }
            }
            Term::G2SmithSeparableGgx
            | Term::G2SmithCorrelatedGgx
            | Term::G2SmithSeparableBeckmann
            | Term::G2SmithCorrelatedBeckmann => {
                for &alpha in STRESS_ALPHAS {
                    for &v in STRESS_COSINES {
                        for &l in STRESS_COSINES {
                            push([alpha, v, l, 0.0], [0.0; 4]);
                        }
                    }
                }
            }
            Term::ShadowTerminator => {
                for &ng_l in STRESS_COSINES {
                    for &ns_l in STRESS_COSINES {
                        for &ng_ns in STRESS_COSINES {
                            push([ng_l, ns_l, ng_ns, 0.0], [0.0; 4]);
                        }
                    }
                }
            }
            Term::G2VCavity => {
                for &h in STRESS_COSINES {
                    for &v in STRESS_COSINES {
                        for &l in STRESS_COSINES {
                            for &vh in STRESS_COSINES {
                                push([h, v, l, vh], [0.0; 4]);
                            }
                        }
                    }
                }
            }
            Term::FSchlick => {
                for &f0 in STRESS_COLOURS {
                    for &vh in STRESS_COSINES {
                        push([vh, 0.0, 0.0, 0.0], [f0, 1.0 - f0, f0 * 0.5, 0.0]);
                    }
                }
            }
            Term::TonemapPbrNeutral | Term::SrgbOetf => {
                for &r in STRESS_RADIANCES {
                    for &g in STRESS_RADIANCES {
                        for &b in STRESS_RADIANCES {
                            push([0.0; 4], [r, g, b, 0.0]);
                        }
                    }
                }
            }
            Term::WrapSeed => {
                for &n_dot_l in STRESS_COSINES {
                    for &w1 in STRESS_ALPHAS {
                        for &w2 in STRESS_ALPHAS {
                            push([n_dot_l, w1, w2, 0.0], [0.0; 4]);
                        }
                    }
                }
            }
            Term::WrapEnergyConserving | Term::PreintegratedLookup => {
                // σκ: the same extremes as w, and fp32's largest.
                for &n_dot_l in STRESS_COSINES {
                    for &w in STRESS_ALPHAS.iter().chain(&[f32::MAX]) {
                        push([n_dot_l, w, 0.0, 0.0], [0.0; 4]);
                    }
                }
            }
            Term::WrapEnergyConservingShKernel => {
                for &w in STRESS_ALPHAS {
                    push([w, 0.0, 0.0, 0.0], [0.0; 4]);
                }
            }
            Term::ResolveWeight => {
                for &r in STRESS_RADIANCES {
                    for &g in STRESS_RADIANCES {
                        for &b in STRESS_RADIANCES {
                            push([0.0; 4], [r, g, b, 0.0]);
                        }
                    }
                }
            }
            Term::GtaoSliceVisibility => {
                let half = std::f32::consts::FRAC_PI_2;
                for gamma in [-half, -0.5, 0.0, 0.5, half] {
                    for h0 in [gamma - half, -1e-7, 0.0] {
                        for h1 in [0.0, 1e-7, gamma + half] {
                            push([h0.min(0.0), h1.max(0.0), gamma, 0.0], [0.0; 4]);
                        }
                    }
                }
            }
            Term::SpecularAaRoughness => {
                // The change is a sum of squares: never negative.
                for &roughness in STRESS_ALPHAS {
                    for &change in STRESS_ALPHAS.iter().filter(|c| **c >= 0.0).chain(&[f32::MAX]) {
                        push([roughness, change, 0.0, 0.0], [0.0; 4]);
                    }
                }
            }
            Term::GtaoMultiBounce => {
                for &rho in STRESS_COLOURS {
                    for x in [0.0, 1e-7, 0.5, 1.0] {
                        push([x, 0.0, 0.0, 0.0], [rho, 1.0 - rho, rho * 0.5, 0.0]);
                    }
                }
            }
            Term::PlanePointIrradiance => {
                // Straight above, grazing, nearly in the plane, at MIN_LIGHT_DISTANCE2 and far.
                for distance in [1e-4f32, 1e-2, 1.0, 1e3, 1e4] {
                    for h in [1.0, 0.5, 1e-3, 1e-7, 0.0, -0.5] {
                        push([distance * h, distance * distance, 0.0, 0.0], [0.0; 4]);
                    }
                }
            }
            Term::SpecularOcclusion => {
                for &n_dot_v in STRESS_COSINES {
                    for x in [0.0, 1e-7, 0.5, 1.0] {
                        for &alpha in STRESS_ALPHAS {
                            push([n_dot_v, x, alpha, 0.0], [0.0; 4]);
                        }
                    }
                }
            }
            Term::SpecBlinnPhong => {
                for &alpha in STRESS_ALPHAS {
                    for &n_dot_h in STRESS_COSINES {
                        for &s in STRESS_COSINES {
                            for &v_dot_h in STRESS_COSINES {
                                push([alpha, n_dot_h, s, v_dot_h], [0.0, 1.0, 0.04, 0.0]);
                            }
                        }
                    }
                }
            }
        }
        out
    }
}

/// What a model's parameter p is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parameter {
    None,
    /// Microfacet roughness α.
    Alpha,
    /// Oren-Nayar's σ, radians.
    Sigma,
    /// EON's roughness r in [0, 1].
    Roughness,
}

impl Model {
    pub const ALL: [Model; 9] = [
        Model::Lambert,
        Model::OrenNayar,
        Model::Eon,
        Model::BlinnPhong,
        Model::TorranceSparrow,
        Model::CookTorranceGgxSeparable,
        Model::CookTorranceGgxCorrelated,
        Model::CookTorranceBeckmannSeparable,
        Model::CookTorranceBeckmannCorrelated,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Model::Lambert => "lambert",
            Model::OrenNayar => "oren-nayar",
            Model::Eon => "eon",
            Model::BlinnPhong => "blinn-phong",
            Model::TorranceSparrow => "torrance-sparrow",
            Model::CookTorranceGgxSeparable => "cook-torrance ggx smith-separable",
            Model::CookTorranceGgxCorrelated => "cook-torrance ggx smith-correlated",
            Model::CookTorranceBeckmannSeparable => "cook-torrance beckmann smith-separable",
            Model::CookTorranceBeckmannCorrelated => "cook-torrance beckmann smith-correlated",
        }
    }

    pub fn parameter(self) -> Parameter {
        match self {
            Model::Lambert => Parameter::None,
            Model::OrenNayar => Parameter::Sigma,
            Model::Eon => Parameter::Roughness,
            _ => Parameter::Alpha,
        }
    }

    fn cook_torrance(self) -> Option<(Distribution, Geometry)> {
        match self {
            Model::CookTorranceGgxSeparable => Some((Distribution::Ggx, Geometry::SmithSeparable)),
            Model::CookTorranceGgxCorrelated => Some((Distribution::Ggx, Geometry::SmithCorrelated)),
            Model::CookTorranceBeckmannSeparable => Some((Distribution::Beckmann, Geometry::SmithSeparable)),
            Model::CookTorranceBeckmannCorrelated => Some((Distribution::Beckmann, Geometry::SmithCorrelated)),
            _ => None,
        }
    }

    /// Where reciprocity is checked: v and l above the horizon of n, a BRDF's domain (below
    /// it the lobes are guarded, not symmetric, and the renderer does not shade), and |v + l|
    /// ≥ `MIN_RECIPROCAL_HALF_LEN`: v·h = (|v|² + v·l)/|v + l| and l·h = (|l|² + v·l)/|v + l|
    /// differ by the length error of unit vectors (1e-7 in fp32, 1e-16 in f64) over |v + l|.
    pub fn in_reciprocity_domain(self, t: &Tuple) -> bool {
        let (n, v, l) = (rgb(t.a), rgb(t.b), rgb(t.c));
        let sum = [v[0] + l[0], v[1] + l[1], v[2] + l[2]];
        dot(n, v) > 0.0 && dot(n, l) > 0.0 && dot(sum, sum) >= MIN_RECIPROCAL_HALF_LEN * MIN_RECIPROCAL_HALF_LEN
    }

    /// f(v, l) and f(l, v) in f64 for the tuple's directions made unit in f64, where
    /// reciprocity holds to rounding (the fp32 tuple is unit only to 1e-7).
    pub fn eval_unit_both_ways(self, t: &Tuple) -> Values<f64> {
        let (n, v, l, p, colour) = (
            rgb(t.a),
            normalize(rgb(t.b)),
            normalize(rgb(t.c)),
            f64::from(t.a[3]),
            rgb(t.d),
        );
        let [r, g, b] = self.eval(n, v, l, p, colour);
        let [sr, sg, sb] = self.eval(n, l, v, p, colour);
        [[r, g, b, 0.0], [sr, sg, sb, 0.0]]
    }

    /// f(n, v, l) without the cosine, p and `colour` (F0 or ρ) as in `Tuple`: the twin of
    /// `model` in verify_brdf.comp, which derives the arguments from the directions the
    /// same way.
    pub fn eval(self, n: Vec3, v: Vec3, l: Vec3, p: f64, colour: Vec3) -> Vec3 {
        let h = safe_half_vector(v, l, n);
        let n_cross_h = cross(n, h);
        let nxh2 = dot(n_cross_h, n_cross_h);
        let (nv, nl, nh, vh) = (dot(n, v), dot(n, l), dot(n, h), dot(v, h));
        if let Some((distribution, geometry)) = self.cook_torrance() {
            return spec_cook_torrance(p, nv, nl, nh, nxh2, colour, vh, distribution, geometry);
        }
        match self {
            Model::Lambert => [diffuse_lambert(); 3],
            Model::OrenNayar => [diffuse_oren_nayar(p, n, v, l); 3],
            Model::Eon => diffuse_eon(colour, p, nv, nl, dot(v, l)),
            Model::BlinnPhong => spec_blinn_phong(p, nh, nxh2, colour, vh),
            _ => spec_torrance_sparrow(p, nv, nl, nh, nxh2, colour, vh),
        }
    }

    /// Random directions about n = +z (the shading frame, where n × h is exact in fp32;
    /// other normals are the stress inputs' business), the parameter over its range and a
    /// random colour.
    fn sample(self, rng: &mut Rng) -> Tuple {
        let alpha = sample_alpha(rng);
        let p = match self.parameter() {
            Parameter::None => 0.0,
            Parameter::Alpha => alpha,
            Parameter::Sigma | Parameter::Roughness => rng.uniform(),
        };
        let (v, l) = sample_directions(rng, alpha);
        Tuple {
            a: [0.0, 0.0, 1.0, p as f32],
            b: vec4(v),
            c: vec4(l),
            d: colour(rng),
            ..Tuple::default()
        }
    }

    /// Zero-length, denormal and non-unit normals; n·v, n·l at and around the horizon; v = l,
    /// v = −l (no half vector), n·h = 1 exactly, denormal components; every stress parameter
    /// and colour.
    fn stress(self) -> Vec<Tuple> {
        let normals: [[f32; 3]; 7] = [
            [0.0, 0.0, 1.0],
            [0.0, 0.0, 0.0],
            [0.0, 0.0, 2.0],
            [0.0, 0.0, 0.5],
            [0.3, 0.1, 0.8],
            [0.0, 0.0, DENORMAL],
            [0.0, 0.0, 1e-20],
        ];
        let cosines = [-1e-3, 0.0, 1e-7, 1e-4, 1e-3, 1.0];
        let mut pairs = Vec::new();
        for &mu_v in &cosines {
            let v = vec4(direction(mu_v, 0.0));
            for &mu_l in &cosines {
                for phi in [0.0, FRAC_PI_2, std::f64::consts::PI] {
                    pairs.push((v, vec4(direction(mu_l, phi))));
                }
            }
            pairs.push((v, v));
            pairs.push((v, [-v[0], -v[1], -v[2], 0.0]));
            pairs.push((v, [-v[0], -v[1], v[2], 0.0]));
        }
        let denormal = [DENORMAL, DENORMAL, 1.0, 0.0];
        pairs.push((denormal, [-DENORMAL, 0.0, 1.0, 0.0]));
        pairs.push((denormal, [1.0, 0.0, DENORMAL, 0.0]));
        let colours = [[0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 1.0, 0.0], [0.0, 0.5, 1.0, 0.0]];
        let mut out = Vec::new();
        for n in normals {
            for &(b, c) in &pairs {
                for &p in STRESS_ALPHAS {
                    for d in colours {
                        out.push(Tuple {
                            a: [n[0], n[1], n[2], p],
                            b,
                            c,
                            d,
                            ..Tuple::default()
                        });
                    }
                }
            }
        }
        out
    }
}

impl Function {
    /// Every function: terms, models, unit vectors, then brdf_cos.
    pub fn all() -> impl Iterator<Item = Function> {
        Term::ALL
            .into_iter()
            .map(Function::Term)
            .chain(Model::ALL.into_iter().map(Function::Model))
            .chain(UnitVector::ALL.into_iter().map(Function::UnitVector))
            .chain(Composite::ALL.into_iter().map(Function::Composite))
    }

    /// The harness's `FUNCTION` specialization constant.
    pub fn id(self) -> u32 {
        match self {
            Function::Term(t) => t as u32,
            Function::Model(m) => m as u32,
            Function::UnitVector(n) => n as u32,
            Function::Composite(c) => c.id(),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Function::Term(t) => t.name(),
            Function::Model(m) => m.name(),
            Function::UnitVector(n) => n.name(),
            Function::Composite(c) => c.name,
        }
    }

    /// How many of the four result channels hold a value.
    pub fn channels(self) -> usize {
        match self {
            Function::Term(t) => t.channels(),
            Function::Model(_) | Function::UnitVector(_) | Function::Composite(_) => 3,
        }
    }

    pub fn output(self) -> Output {
        match self {
            Function::Term(t) => Output::Capped(t.cap()),
            Function::Model(_) => Output::Capped(FP16),
            Function::UnitVector(_) => Output::Unit,
            Function::Composite(_) => Output::Capped(FP32),
        }
    }

    pub fn sample(self, rng: &mut Rng) -> Tuple {
        match self {
            Function::Term(t) => t.sample(rng),
            Function::Model(m) => m.sample(rng),
            Function::UnitVector(n) => n.sample(rng),
            Function::Composite(c) => c.sample(rng),
        }
    }

    pub fn stress(self) -> Vec<Tuple> {
        match self {
            Function::Term(t) => t.stress(),
            Function::Model(m) => m.stress(),
            Function::UnitVector(n) => n.stress(),
            Function::Composite(c) => c.stress(),
        }
    }

    /// The tuple's arguments, named, for messages.
    pub fn describe(self, t: &Tuple) -> String {
        let colour = |name: &str| format!("{name}=({:e}, {:e}, {:e})", t.d[0], t.d[1], t.d[2]);
        match self {
            Function::Term(term) => {
                let (names, colour_name) = term.arguments();
                let mut parts: Vec<String> = names.iter().zip(t.a).map(|(n, x)| format!("{n}={x:e}")).collect();
                parts.extend(colour_name.map(colour));
                parts.join(", ")
            }
            Function::Model(m) => {
                let (n, v, l) = (rgb(t.a), rgb(t.b), rgb(t.c));
                let h = safe_half_vector(v, l, n);
                let p = match m.parameter() {
                    Parameter::None => String::new(),
                    Parameter::Alpha => format!("α={:e}, ", t.a[3]),
                    Parameter::Sigma => format!("σ={:e}, ", t.a[3]),
                    Parameter::Roughness => format!("r={:e}, ", t.a[3]),
                };
                format!(
                    "{p}n=({:e}, {:e}, {:e}), n·v={:e}, n·l={:e}, n·h={:e}, {}",
                    t.a[0],
                    t.a[1],
                    t.a[2],
                    dot(n, v),
                    dot(n, l),
                    dot(n, h),
                    colour("colour")
                )
            }
            Function::UnitVector(n) => n.describe(t),
            Function::Composite(c) => c.describe(t),
        }
    }

    /// Relative error that fp32 rounding of the arguments the harness (or brdf_cos) derives
    /// from the directions can cause on this tuple, beyond the function's own error: the
    /// terminator shadowing is proportional to n_g·l near n_g's horizon. 0 where it is benign.
    pub fn argument_rounding(self, t: &Tuple) -> f64 {
        match self {
            Function::Composite(c) => c.shadowing_rounding(t) + c.cancellation_rounding(t),
            Function::UnitVector(n) => n.argument_rounding(t),
            Function::Term(Term::SpecularOcclusion) => specular_occlusion_rounding(t),
            Function::Model(m) => half_vector_rounding(m, t),
            _ => 0.0,
        }
    }

    /// Why `argument_rounding` is not 0, for the table.
    pub fn argument_rounding_reason(self) -> String {
        match self {
            Function::Composite(c) if c.redistributes() => {
                format!(
                    "{}; {}",
                    Composite::SHADOWING_ROUNDING,
                    Composite::CANCELLATION_ROUNDING
                )
            }
            Function::Composite(_) => Composite::SHADOWING_ROUNDING.to_owned(),
            Function::UnitVector(n) => n.argument_rounding_reason().to_owned(),
            Function::Term(Term::SpecularOcclusion) => SPECULAR_OCCLUSION_ROUNDING.to_owned(),
            Function::Model(_) => HALF_VECTOR_ROUNDING.to_owned(),
            _ => String::new(),
        }
    }

    /// The f64 side of the harness: what verify_brdf.comp writes for `t`, from the twins.
    pub fn eval(self, t: &Tuple) -> Values<f64> {
        let vector = |[x, y, z]: Vec3| [[x, y, z, 0.0], [0.0; 4]];
        match self {
            Function::Term(term) => [term.eval(t), [0.0; 4]],
            Function::Model(m) => {
                let (n, v, l, p, colour) = (rgb(t.a), rgb(t.b), rgb(t.c), f64::from(t.a[3]), rgb(t.d));
                let [r, g, b] = m.eval(n, v, l, p, colour);
                let [sr, sg, sb] = m.eval(n, l, v, p, colour);
                [[r, g, b, 0.0], [sr, sg, sb, 0.0]]
            }
            Function::UnitVector(n) => vector(n.eval(t)),
            Function::Composite(c) => vector(c.eval(t)),
        }
    }
}

/// |v + l| below which v·h is too ill-conditioned in fp32 for reciprocity: v and l more than
/// 174° apart, both grazing.
pub const MIN_RECIPROCAL_HALF_LEN: f64 = 0.3;

/// The shading normal of the random tuples.
pub const NORMAL: Vec3 = [0.0, 0.0, 1.0];
/// A subnormal fp32 value (flushed to 0 where the GPU flushes denormals).
pub(super) const DENORMAL: f32 = 1e-40;
/// Roughness-like parameters (α, σ, r, wrap widths): 0, denormal, below MIN_ALPHA, both
/// clamps, beyond 1, negative.
const STRESS_ALPHAS: &[f32] = &[0.0, DENORMAL, 1e-4, 0.002025, 0.007921, 0.5, 1.0, 1.5, 100.0, -0.5];
/// Cosines: both sides of the horizon, denormal, the MIN_N_DOT_V clamp, one ulp below 1, and
/// beyond 1 (non-unit vectors).
const STRESS_COSINES: &[f32] = &[
    -1.0, -1e-3, -0.0, 0.0, DENORMAL, 1e-7, 1e-4, 1e-3, 0.5, 0.99999994, 1.0, 1.5,
];
/// F0: both ends of [0, 1] and outside it.
const STRESS_COLOURS: &[f32] = &[0.0, 1.0, 0.04, -0.5, 2.0];
/// Radiances for the display transforms: 0, denormal, the toe, compression, FP16_MAX, fp32
/// max, negative.
const STRESS_RADIANCES: &[f32] = &[0.0, DENORMAL, 1e-3, 0.08, 0.76, 1.0, 1e4, 65504.0, f32::MAX, -1.0];

fn normalize(x: Vec3) -> Vec3 {
    let inverse = 1.0 / dot(x, x).sqrt();
    x.map(|c| c * inverse)
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

const HALF_VECTOR_ROUNDING: &str = "rounding: where v and l are nearly opposite \
    (|v + l| < 0.3), the fp32 sum v + l is good to a few 2^-24 of |v| = 1, which turns h by that \
    over |v + l|; bound the f64 model's own change when l moves by 4·2^-24 along each axis";

/// The error the GPU's h = (v + l)/|v + l| carries into a model where v and l are nearly
/// opposite: turning h as the sum's rounding does is moving l by that rounding, so the
/// bound is the f64 model's largest relative change under such a move. Elsewhere h is
/// well conditioned and the tolerance holds as it is.
fn half_vector_rounding(model: Model, t: &Tuple) -> f64 {
    let (n, v, l, p, colour) = (rgb(t.a), rgb(t.b), rgb(t.c), f64::from(t.a[3]), rgb(t.d));
    let sum = [v[0] + l[0], v[1] + l[1], v[2] + l[2]];
    if dot(sum, sum).sqrt() >= MIN_RECIPROCAL_HALF_LEN {
        return 0.0;
    }
    let value = model.eval(n, v, l, p, colour);
    let step = 4.0 * f64::from(f32::EPSILON) * 0.5;
    let mut worst: f64 = 0.0;
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut moved = l;
            moved[axis] += sign * step;
            let changed = model.eval(n, v, normalize(moved), p, colour);
            for c in 0..3 {
                let change = (changed[c] - value[c]).abs() / value[c].abs().max(super::sweep::RELATIVE_FLOOR);
                worst = worst.max(change);
            }
        }
    }
    worst
}

pub(super) fn rgb(x: [f32; 4]) -> Vec3 {
    [x[0], x[1], x[2]].map(f64::from)
}

pub(super) fn vec4(x: Vec3) -> [f32; 4] {
    [x[0] as f32, x[1] as f32, x[2] as f32, 0.0]
}

/// The direction of cosine `mu` to n = +z at azimuth `phi`.
pub(super) fn direction(mu: f64, phi: f64) -> Vec3 {
    let sin = (1.0 - mu * mu).max(0.0).sqrt();
    [sin * phi.cos(), sin * phi.sin(), mu]
}

/// A direction uniform over the sphere.
pub(super) fn uniform_sphere(rng: &mut Rng) -> Vec3 {
    direction(rng.range(-1.0, 1.0), rng.azimuth())
}

/// `local`, a vector about +z, turned so that +z becomes the unit vector `n` (the
/// orthonormal basis of Duff et al. 2017).
pub(super) fn about(n: Vec3, local: Vec3) -> Vec3 {
    let sign = 1f64.copysign(n[2]);
    let a = -1.0 / (sign + n[2]);
    let b = n[0] * n[1] * a;
    let t = [1.0 + sign * n[0] * n[0] * a, sign * b, -sign * n[0]];
    let bitangent = [b, sign + n[1] * n[1] * a, -n[1]];
    [0, 1, 2].map(|i| t[i] * local[0] + bitangent[i] * local[1] + n[i] * local[2])
}

/// α over [MIN_ALPHA, MAX_ALPHA], log-uniform (every decade of lobe width alike), plus both ends.
pub(super) fn sample_alpha(rng: &mut Rng) -> f64 {
    match rng.uniform() {
        u if u < 0.05 => MIN_ALPHA,
        u if u < 0.1 => MAX_ALPHA,
        _ => rng.log_uniform(MIN_ALPHA, MAX_ALPHA),
    }
}

/// A cosine above the horizon, dense at grazing angles and near the normal.
pub(super) fn sample_cosine(rng: &mut Rng) -> f64 {
    match rng.uniform() {
        u if u < 0.2 => rng.log_uniform(1e-6, 0.1),
        u if u < 0.3 => 1.0 - rng.log_uniform(1e-8, 1e-2),
        u if u < 0.32 => 1.0,
        _ => 1.0 - rng.uniform(),
    }
}

/// `sample_cosine`, or 5% of the time one below the horizon.
fn sample_signed_cosine(rng: &mut Rng) -> f64 {
    if rng.uniform() < 0.05 {
        -rng.log_uniform(1e-6, 1.0)
    } else {
        sample_cosine(rng)
    }
}

/// θh of a half vector: mostly within a few lobe widths α of n (n·h near 1; 2% exactly
/// 1), otherwise anywhere in the hemisphere.
fn sample_half_angle(rng: &mut Rng, alpha: f64) -> f64 {
    match rng.uniform() {
        u if u < 0.02 => 0.0,
        u if u < 0.7 => (alpha * rng.log_uniform(1e-4, 30.0)).min(FRAC_PI_2),
        _ => rng.range(0.0, FRAC_PI_2),
    }
}

/// v and l about n = +z: l reflected about a half vector near the lobe of `alpha`,
/// independent, equal to v, mirrored (n·h = 1 exactly) or opposite (no half vector).
pub(super) fn sample_directions(rng: &mut Rng, alpha: f64) -> (Vec3, Vec3) {
    let view = sample_signed_cosine(rng);
    let v = direction(view, rng.azimuth());
    let l = match rng.uniform() {
        u if u < 0.5 => {
            let h = direction(sample_half_angle(rng, alpha).cos(), rng.azimuth());
            let v_dot_h = dot(v, h);
            [0, 1, 2].map(|i| 2.0 * v_dot_h * h[i] - v[i])
        }
        u if u < 0.9 => direction(sample_signed_cosine(rng), rng.azimuth()),
        u if u < 0.94 => v,
        u if u < 0.98 => [-v[0], -v[1], v[2]],
        _ => v.map(|x| -x),
    };
    (v, l)
}

/// F0 or ρ: uniform per channel, with both ends of [0, 1].
pub(super) fn colour(rng: &mut Rng) -> [f32; 4] {
    let mut channel = || match rng.uniform() {
        u if u < 0.05 => 0.0,
        u if u < 0.1 => 1.0,
        _ => rng.uniform() as f32,
    };
    [channel(), channel(), channel(), 0.0]
}

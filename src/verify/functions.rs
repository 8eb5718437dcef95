//! What `argil verify` evaluates: the terms of `shaders/lib/` declared in `terms`, the BRDF
//! models of `brdf.glsl` (and, through `normals` and `composite`, the unit vectors of
//! `normal_mapping.glsl` and `shading.glsl` and its `brdf_cos`), the input tuples the harness
//! `shaders/verify_brdf.comp` is fed (random over the whole domain, and stress inputs), and
//! the f64 side of the harness, which feeds the twins in `src/brdf` the very same f32 inputs.

use std::f64::consts::FRAC_PI_2;

use bytemuck::{Pod, Zeroable};

use crate::brdf::diffuse::{diffuse_eon, diffuse_lambert, diffuse_oren_nayar};
use crate::brdf::specular::{spec_blinn_phong, spec_cook_torrance, spec_torrance_sparrow, Distribution, Geometry};
use crate::brdf::{cross, dot, safe_half_vector, Vec3, FP16_MAX, MAX_ALPHA, MIN_ALPHA};

use super::composite::Composite;
use super::normals::UnitVector;
use super::terms::Term;
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

/// BRDF models of directions. The value is the GLSL `FUNCTION` of verify_brdf.comp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    Lambert = 36,
    OrenNayar = 37,
    Eon = 38,
    BlinnPhong = 39,
    TorranceSparrow = 40,
    CookTorranceGgxSeparable = 41,
    CookTorranceGgxCorrelated = 42,
    CookTorranceBeckmannSeparable = 43,
    CookTorranceBeckmannCorrelated = 44,
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

/// How far a function's values may be from its f64 twin's, relative (p99 and max).
#[derive(Clone, Copy, Debug)]
pub struct Tolerance {
    pub p99: f64,
    pub max: f64,
}

/// The error of fp32 arithmetic on smooth functions, from the brief.
pub const FP32_ARITHMETIC: Tolerance = Tolerance { p99: 1e-5, max: 1e-4 };

/// ||n| − 1| allowed of a unit vector: fp32 normalisation is good to a few 1e-7.
pub const UNIT_TOLERANCE: f64 = 1e-5;

/// A fraction: masking, Fresnel, display values, wrap weights.
pub(super) const UNIT: Cap = Cap {
    value: 1.0,
    label: "<= 1",
};
/// Lobes clamp D·G/(4 n·v n·l) to FP16_MAX, so an RGBA16F target stays finite.
pub(super) const FP16: Cap = Cap {
    value: FP16_MAX,
    label: "<= FP16_MAX",
};
/// Funk–Hecke coefficients of a transfer ≤ 1 (k₀ ≤ 4π·max/π = 4 for the uniform 1/π).
pub(super) const SH_KERNEL: Cap = Cap {
    value: 4.0,
    label: "<= 4",
};
/// GTAO's slice integral of cos(θ − γ)|sin θ| reaches ∫₀^π sin² = π/2 at γ = π/2 (fp32's
/// π/2, which rounds up).
pub(super) const SLICE: Cap = Cap {
    value: std::f32::consts::FRAC_PI_2 as f64,
    label: "<= π/2",
};
/// Intermediates (D, Λ, E_FON) are never stored, and brdf_cos is scaled by the irradiance
/// before it is: only fp32 overflow matters.
pub(super) const FP32: Cap = Cap {
    value: f32::MAX as f64,
    label: "<= fp32 max",
};

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
        Term::all()
            .map(Function::Term)
            .chain(Model::ALL.into_iter().map(Function::Model))
            .chain(UnitVector::ALL.into_iter().map(Function::UnitVector))
            .chain(Composite::ALL.into_iter().map(Function::Composite))
    }

    /// The harness's `FUNCTION` specialization constant.
    pub fn id(self) -> u32 {
        match self {
            Function::Term(t) => t.id(),
            Function::Model(m) => m as u32,
            Function::UnitVector(n) => n as u32,
            Function::Composite(c) => c.id(),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Function::Term(t) => t.spec().name,
            Function::Model(m) => m.name(),
            Function::UnitVector(n) => n.name(),
            Function::Composite(c) => c.name,
        }
    }

    /// How many of the four result channels hold a value.
    pub fn channels(self) -> usize {
        match self {
            Function::Term(t) => t.spec().channels,
            Function::Model(_) | Function::UnitVector(_) | Function::Composite(_) => 3,
        }
    }

    /// The formula a term implements, for the table; empty for the others (their rows name
    /// the formula).
    pub fn equation(self) -> String {
        match self {
            Function::Term(t) => format!("formula: {}", t.spec().equation),
            Function::Model(_) | Function::UnitVector(_) | Function::Composite(_) => String::new(),
        }
    }

    /// The largest p99 and max relative errors against the f64 twin.
    pub fn tolerance(self) -> Tolerance {
        match self {
            Function::Term(t) => t.spec().tolerance,
            Function::Model(_) | Function::UnitVector(_) | Function::Composite(_) => FP32_ARITHMETIC,
        }
    }

    pub fn output(self) -> Output {
        match self {
            Function::Term(t) => Output::Capped(t.spec().cap),
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
            Function::Term(t) => (t.spec().stress)(),
            Function::Model(m) => m.stress(),
            Function::UnitVector(n) => n.stress(),
            Function::Composite(c) => c.stress(),
        }
    }

    /// The tuple's arguments, named, for messages.
    pub fn describe(self, t: &Tuple) -> String {
        let colour = |name: &str| format!("{name}=({:e}, {:e}, {:e})", t.d[0], t.d[1], t.d[2]);
        match self {
            Function::Term(term) => term.describe(t),
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
            Function::Term(term) => term.spec().rounding.as_ref().map_or(0.0, |r| (r.bound)(t)),
            Function::Model(m) => half_vector_rounding(m, t),
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
            Function::Term(term) => term.spec().rounding.as_ref().map_or("", |r| r.reason).to_owned(),
            Function::Model(_) => HALF_VECTOR_ROUNDING.to_owned(),
        }
    }

    /// The f64 side of the harness: what verify_brdf.comp writes for `t`, from the twins.
    pub fn eval(self, t: &Tuple) -> Values<f64> {
        let vector = |[x, y, z]: Vec3| [[x, y, z, 0.0], [0.0; 4]];
        match self {
            Function::Term(term) => [(term.spec().eval)(t), [0.0; 4]],
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
pub(super) const STRESS_ALPHAS: &[f32] = &[0.0, DENORMAL, 1e-4, 0.002025, 0.007921, 0.5, 1.0, 1.5, 100.0, -0.5];
/// Cosines: both sides of the horizon, denormal, the MIN_N_DOT_V clamp, one ulp below 1, and
/// beyond 1 (non-unit vectors).
pub(super) const STRESS_COSINES: &[f32] = &[
    -1.0, -1e-3, -0.0, 0.0, DENORMAL, 1e-7, 1e-4, 1e-3, 0.5, 0.99999994, 1.0, 1.5,
];
/// F0: both ends of [0, 1] and outside it.
pub(super) const STRESS_COLOURS: &[f32] = &[0.0, 1.0, 0.04, -0.5, 2.0];
/// Radiances for the display transforms: 0, denormal, the toe, compression, FP16_MAX, fp32
/// max, negative.
pub(super) const STRESS_RADIANCES: &[f32] = &[0.0, DENORMAL, 1e-3, 0.08, 0.76, 1.0, 1e4, 65504.0, f32::MAX, -1.0];

fn normalize(x: Vec3) -> Vec3 {
    let inverse = 1.0 / dot(x, x).sqrt();
    x.map(|c| c * inverse)
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
pub(super) fn sample_signed_cosine(rng: &mut Rng) -> f64 {
    if rng.uniform() < 0.05 {
        -rng.log_uniform(1e-6, 1.0)
    } else {
        sample_cosine(rng)
    }
}

/// θh of a half vector: mostly within a few lobe widths α of n (n·h near 1; 2% exactly
/// 1), otherwise anywhere in the hemisphere.
pub(super) fn sample_half_angle(rng: &mut Rng, alpha: f64) -> f64 {
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

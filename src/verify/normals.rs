//! The functions of `shaders/lib/normal_mapping.glsl`, `shading.glsl` and `env_math.glsl`
//! whose value is a unit vector: their tuples, their f64 side, and what they promise beyond
//! accuracy and unit length (decoded normals above the surface, shading normals facing the
//! viewer).

use crate::brdf::normal_mapping::{
    blend_rnm, blend_seed, blend_udn, blend_whiteout, decode_normal, tangent_to_world, MIN_TANGENT_SIN2, MIN_TANGENT_Z,
};
use crate::brdf::environment::octahedral_direction;
use crate::brdf::shading::{view_facing_normal, MIN_SHADING_N_DOT_V};
use crate::brdf::{dot, Vec3};
use crate::render::environment::OCTAHEDRAL_SIDE;

use super::functions::{
    about, direction, rgb, sample_cosine, uniform_sphere, vec4, Tuple, Values, DENORMAL, NORMAL, UNIT_TOLERANCE,
};
use super::sweep::RELATIVE_FLOOR;
use super::{Row, Status};
use crate::rng::Rng;

/// Unit-vector functions. The value is the GLSL `FUNCTION` of verify_brdf.comp. Tuples:
/// decode_normal a = (texel, strength), b.x = green_down (0 or 1); the blends a = base,
/// b = detail; tangent_to_world a = n_ts, b = normal, c = tangent (w the handedness);
/// view_facing_normal a = n, b = v; octahedral_direction a.xy = p.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnitVector {
    DecodeNormal = 48,
    BlendRnm = 49,
    BlendUdn = 50,
    BlendWhiteout = 51,
    BlendSeed = 52,
    TangentToWorld = 53,
    ViewFacingNormal = 54,
    OctahedralDirection = 55,
}

/// Strengths are checked in [0, 8]: normal maps are not in the scene format yet, so nothing
/// else bounds them.
const MAX_STRENGTH: f64 = 8.0;
/// fp32 rounding of n·v (inputs unit to 2^-23, a dot product, the bend, its
/// normalisation): a few 1e-7, so 1e-6 is 0.1% of MIN_SHADING_N_DOT_V.
const N_DOT_V_ROUNDING: f64 = 1e-6;
/// Roundings of 2⁻²⁴ in a component that fp32 computes as a sum of O(1) products (a row of
/// RNM's rotation or of the TBN frame, the bend towards v): the component is good to a few
/// 2⁻²⁴ absolute, as the fp32 inputs themselves are, however small it is.
const COMPONENT_ROUNDINGS: f64 = 8.0;

/// Texels: the corners, flat-but-below (0.5, 0.5, 0) and a zero vector (0.5, 0.5, 0.5),
/// slopes along one axis, denormal.
const STRESS_TEXELS: [[f32; 3]; 9] = [
    [0.0, 0.0, 0.0],
    [1.0, 1.0, 1.0],
    [0.5, 0.5, 0.0],
    [0.5, 0.5, 1.0],
    [0.5, 0.5, 0.5],
    [1.0, 0.0, 0.5],
    [0.0, 1.0, 0.5],
    [1.0, 1.0, 0.0],
    [DENORMAL, DENORMAL, DENORMAL],
];
const STRESS_STRENGTHS: [f32; 5] = [0.0, DENORMAL, 1e-4, 1.0, MAX_STRENGTH as f32];

impl UnitVector {
    pub const ALL: [UnitVector; 8] = [
        UnitVector::DecodeNormal,
        UnitVector::BlendRnm,
        UnitVector::BlendUdn,
        UnitVector::BlendWhiteout,
        UnitVector::BlendSeed,
        UnitVector::TangentToWorld,
        UnitVector::ViewFacingNormal,
        UnitVector::OctahedralDirection,
    ];

    pub fn name(self) -> &'static str {
        match self {
            UnitVector::DecodeNormal => "decode_normal",
            UnitVector::BlendRnm => "blend_rnm",
            UnitVector::BlendUdn => "blend_udn",
            UnitVector::BlendWhiteout => "blend_whiteout",
            UnitVector::BlendSeed => "blend_seed",
            UnitVector::TangentToWorld => "tangent_to_world",
            UnitVector::ViewFacingNormal => "view_facing_normal",
            UnitVector::OctahedralDirection => "octahedral_direction",
        }
    }

    /// The detail blends, which share their tuples.
    fn blend(self) -> Option<fn(Vec3, Vec3) -> Vec3> {
        match self {
            UnitVector::BlendRnm => Some(blend_rnm),
            UnitVector::BlendUdn => Some(blend_udn),
            UnitVector::BlendWhiteout => Some(blend_whiteout),
            UnitVector::BlendSeed => Some(blend_seed),
            _ => None,
        }
    }

    /// The f64 twin on the tuple's (widened) f32 arguments.
    pub fn eval(self, t: &Tuple) -> Vec3 {
        let (a, b) = (rgb(t.a), rgb(t.b));
        if let Some(blend) = self.blend() {
            return blend(a, b);
        }
        match self {
            UnitVector::DecodeNormal => decode_normal(a, t.b[0] != 0.0, f64::from(t.a[3])),
            UnitVector::TangentToWorld => tangent_to_world(a, b, t.c.map(f64::from)),
            UnitVector::OctahedralDirection => octahedral_direction([a[0], a[1]]),
            _ => view_facing_normal(a, b),
        }
    }

    pub fn sample(self, rng: &mut Rng) -> Tuple {
        let vectors = |a: Vec3, b: Vec3| Tuple {
            a: vec4(a),
            b: vec4(b),
            ..Tuple::default()
        };
        match self {
            UnitVector::DecodeNormal => {
                let texel = sample_texel(rng);
                let strength = sample_strength(rng);
                let green_down = if rng.uniform() < 0.5 { 0.0 } else { 1.0 };
                Tuple {
                    a: [texel[0], texel[1], texel[2], strength as f32],
                    b: [green_down, 0.0, 0.0, 0.0],
                    ..Tuple::default()
                }
            }
            UnitVector::TangentToWorld => {
                let normal = uniform_sphere(rng);
                Tuple {
                    c: sample_tangent(rng, normal),
                    ..vectors(sample_tangent_space_normal(rng), normal)
                }
            }
            UnitVector::ViewFacingNormal => {
                let n = uniform_sphere(rng);
                let n_dot_v = match rng.uniform() {
                    u if u < 0.3 => rng.range(-1.0, 1.0),
                    // Grazing, both sides: n·v = 0 gives the least n·v after the bend.
                    u if u < 0.5 => rng.log_uniform(1e-8, 0.1).copysign(rng.range(-1.0, 1.0)),
                    // Around the bend's threshold.
                    u if u < 0.6 => MIN_SHADING_N_DOT_V * (1.0 + rng.range(-1.0, 1.0) * rng.log_uniform(1e-7, 0.1)),
                    // Near v = −n, where n + v·(m − n·v) is a difference of near-opposites.
                    u if u < 0.7 => -rng.log_uniform(1e-6, 0.3).cos(),
                    _ => sample_cosine(rng),
                };
                vectors(n, about(n, direction(n_dot_v, rng.azimuth())))
            }
            UnitVector::OctahedralDirection => {
                // The square and its border texels' centres, half a texel past the edges
                // (1/256 at 256²); a third of the points near an edge or the fold |x| + |y| = 1.
                let p = match rng.uniform() {
                    u if u < 0.67 => [rng.range(-1.01, 1.01), rng.range(-1.01, 1.01)],
                    u if u < 0.84 => [rng.range(-1.0, 1.0), 1.0 + rng.range(-0.01, 0.01)],
                    _ => {
                        let x = rng.range(-1.0, 1.0);
                        [x, 1.0 - x.abs() + rng.range(-1e-3, 1e-3)]
                    }
                };
                let [x, y] = if rng.uniform() < 0.5 { p } else { [p[1], -p[0]] };
                Tuple {
                    a: [x as f32, y as f32, 0.0, 0.0],
                    ..Tuple::default()
                }
            }
            _ => vectors(sample_tangent_space_normal(rng), sample_tangent_space_normal(rng)),
        }
    }

    /// The stress texels and strengths, both green conventions; blends of every pair of
    /// stress normals; degenerate tangents; v = −n, n·v = 0 exactly, denormals.
    pub fn stress(self) -> Vec<Tuple> {
        let mut out = Vec::new();
        let mut push = |a: [f32; 4], b: [f32; 4], c: [f32; 4]| {
            out.push(Tuple {
                a,
                b,
                c,
                ..Tuple::default()
            })
        };
        match self {
            UnitVector::DecodeNormal => {
                for [x, y, z] in STRESS_TEXELS {
                    for strength in STRESS_STRENGTHS {
                        for green_down in [0.0, 1.0] {
                            push([x, y, z, strength], [green_down, 0.0, 0.0, 0.0], [0.0; 4]);
                        }
                    }
                }
            }
            UnitVector::TangentToWorld => {
                let normals: [Vec3; 4] = [
                    NORMAL,
                    [0.0, 0.0, -1.0],
                    [0.6, 0.0, 0.8],
                    [f64::from(DENORMAL), 0.0, 1.0],
                ];
                let n_ts = [
                    NORMAL,
                    [0.6, 0.0, 0.8],
                    decode_normal([1.0, 0.0, 0.5], false, MAX_STRENGTH),
                ];
                for n in normals {
                    let [x, y, z] = n;
                    let tangents: [[f64; 3]; 9] = [
                        [0.0; 3],
                        [f64::from(DENORMAL); 3],
                        [1e-20, 0.0, 0.0],
                        n,
                        [-x, -y, -z],
                        [1e-3 * x, 1e-3 * y, 1e-3 * z],
                        [x + 1e-7, y, z],
                        [1.0, 0.0, 0.0],
                        [0.0, 1.0, 0.0],
                    ];
                    for tangent in tangents {
                        for w in [1.0, -1.0, 0.0] {
                            for m in n_ts {
                                let [tx, ty, tz, _] = vec4(tangent);
                                push(vec4(m), vec4(n), [tx, ty, tz, w]);
                            }
                        }
                    }
                }
            }
            UnitVector::ViewFacingNormal => {
                // Each n with a v exactly perpendicular in fp32.
                let frames: [(Vec3, Vec3); 4] = [
                    (NORMAL, [1.0, 0.0, 0.0]),
                    ([0.6, 0.8, 0.0], [0.8, -0.6, 0.0]),
                    ([0.0, 0.6, 0.8], [0.0, 0.8, -0.6]),
                    ([f64::from(DENORMAL), 0.0, 1.0], [1.0, 0.0, 0.0]),
                ];
                for (n, p) in frames {
                    let along = |c: f64| {
                        let s = (1.0 - c * c).sqrt();
                        [0, 1, 2].map(|i| c * n[i] + s * p[i])
                    };
                    let m = MIN_SHADING_N_DOT_V;
                    let vs = [
                        n.map(|x| -x),
                        n,
                        p,
                        p.map(|x| -x),
                        along(m),
                        along(-m),
                        along(1e-7),
                        along(-1e-7),
                        along(-1.0 + 1e-7),
                    ];
                    for v in vs {
                        push(vec4(n), vec4(v), [0.0; 4]);
                    }
                }
            }
            UnitVector::OctahedralDirection => {
                // The centre (+z), the corners (−z), edges and their midpoints, the fold,
                // border points past edges and corners, signed zeros and denormals.
                // The split sum's maps' border texels' centres, half a texel past the edges.
                let border = 1.0 + 1.0 / (OCTAHEDRAL_SIDE - 2) as f32;
                let values = [-border, -1.0, -0.5, -DENORMAL, -0.0, 0.0, DENORMAL, 0.5, 1.0, border];
                for x in values {
                    for y in values {
                        push([x, y, 0.0, 0.0], [0.0; 4], [0.0; 4]);
                    }
                }
            }
            _ => {
                let mut normals = vec![NORMAL, [f64::from(DENORMAL), f64::from(DENORMAL), 1.0]];
                for texel in STRESS_TEXELS {
                    for strength in [1.0, MAX_STRENGTH] {
                        normals.push(decode_normal(texel.map(f64::from), false, strength));
                    }
                }
                for &base in &normals {
                    for &detail in &normals {
                        push(vec4(base), vec4(detail), [0.0; 4]);
                    }
                }
            }
        }
        out
    }

    /// The relative error (with the floor) fp32 may make in the smallest component, where
    /// the components are sums of O(1) products: `COMPONENT_ROUNDINGS`·2⁻²⁴ absolute, times
    /// 1 + |n_ts.xy|/sin θ for the TBN frame, whose T − N(N·T) is good to 2⁻²³·|T| and its
    /// direction to 2⁻²³/sin θ, θ between T and N. 0 for the others.
    pub fn argument_rounding(self, t: &Tuple) -> f64 {
        let condition = match self {
            UnitVector::BlendRnm | UnitVector::OctahedralDirection => 1.0,
            // Bent, or so near the bend that fp32's n·v (a sum of three products, good to
            // 2·2^-24) may fall below m and bend it on the GPU alone.
            UnitVector::ViewFacingNormal
                if dot(rgb(t.a), rgb(t.b)) < MIN_SHADING_N_DOT_V + 2.0 * f64::from(f32::EPSILON) =>
            {
                1.0
            }
            UnitVector::TangentToWorld => {
                let (normal, tangent) = (rgb(t.b), rgb(t.c));
                let along = dot(normal, tangent);
                let across = [0, 1, 2].map(|i| tangent[i] - normal[i] * along);
                let (across2, length2) = (dot(across, across), dot(tangent, tangent));
                if across2 <= MIN_TANGENT_SIN2 * length2 {
                    return 0.0; // N itself, exactly, on both sides
                }
                1.0 + f64::from(t.a[0]).hypot(f64::from(t.a[1])) / (across2 / length2).sqrt()
            }
            _ => return 0.0,
        };
        let smallest = self.eval(t).iter().fold(f64::INFINITY, |m, c| m.min(c.abs()));
        COMPONENT_ROUNDINGS * f64::from(f32::EPSILON) * 0.5 * condition / smallest.max(RELATIVE_FLOOR)
    }

    /// Why `argument_rounding` is not 0, for the table.
    pub fn argument_rounding_reason(self) -> &'static str {
        match self {
            UnitVector::BlendRnm => {
                "rounding: a component of the rotated detail is a sum of O(1) products, good to \
                 a few 2^-24 absolute in fp32; bound 8·2^-24/max(|c|, floor); the angle row is \
                 the direction's bound"
            }
            UnitVector::ViewFacingNormal => {
                "rounding: a component of the bent n + v·(m − n·v) is a sum of O(1) terms, good \
                 to a few 2^-24 absolute in fp32; bound 8·2^-24/max(|c|, floor); the angle row \
                 is the direction's bound"
            }
            UnitVector::OctahedralDirection => {
                "rounding: a component of the point on the octahedron (1 − |x| − |y|, the fold's \
                 1 − |y|, the border's 2 − |x|) is a sum of O(1) terms, good to a few 2^-24 \
                 absolute in fp32; bound 8·2^-24/max(|c|, floor); the angle row is the \
                 direction's bound"
            }
            UnitVector::TangentToWorld => {
                "rounding: T − N(N·T) is good to 2^-23·|T| in fp32, so its direction to \
                 2^-23/sin θ, and the TBN sum to a few 2^-24; bound 8·2^-24·(1 + |n_ts.xy|/sin θ)/\
                 max(|c|, floor); the angle row is the direction's bound"
            }
            _ => "",
        }
    }

    /// The tuple's arguments, named, for messages.
    pub fn describe(self, t: &Tuple) -> String {
        let v = |x: [f32; 4]| format!("({:e}, {:e}, {:e})", x[0], x[1], x[2]);
        match self {
            UnitVector::DecodeNormal => {
                format!("texel={}, strength={:e}, green_down={}", v(t.a), t.a[3], t.b[0] != 0.0)
            }
            UnitVector::TangentToWorld => format!(
                "n_ts={}, normal={}, tangent=({:e}, {:e}, {:e}, {:e})",
                v(t.a),
                v(t.b),
                t.c[0],
                t.c[1],
                t.c[2],
                t.c[3]
            ),
            UnitVector::ViewFacingNormal => format!("n={}, v={}, n·v={:e}", v(t.a), v(t.b), dot(rgb(t.a), rgb(t.b))),
            UnitVector::OctahedralDirection => format!("p=({:e}, {:e})", t.a[0], t.a[1]),
            _ => format!("base={}, detail={}", v(t.a), v(t.b)),
        }
    }
}

/// A texel of a tangent-space normal map: uniform in [0, 1]³, clustered near flat
/// (0.5, 0.5, 1), 8-bit, or with z < 0.5, where the decoded z is clamped.
fn sample_texel(rng: &mut Rng) -> [f32; 3] {
    let texel = match rng.uniform() {
        u if u < 0.4 => [rng.uniform(), rng.uniform(), rng.uniform()],
        u if u < 0.75 => {
            let spread = rng.log_uniform(1e-4, 0.1);
            [
                0.5 + spread * rng.range(-1.0, 1.0),
                0.5 + spread * rng.range(-1.0, 1.0),
                1.0 - spread * rng.uniform(),
            ]
        }
        u if u < 0.9 => [0; 3].map(|_| (rng.uniform() * 256.0).floor().min(255.0) / 255.0),
        _ => [rng.uniform(), rng.uniform(), rng.range(0.0, 0.5)],
    };
    texel.map(|x| x as f32)
}

/// A strength in [0, 8], with both ends and 1.
fn sample_strength(rng: &mut Rng) -> f64 {
    match rng.uniform() {
        u if u < 0.1 => 0.0,
        u if u < 0.2 => 1.0,
        u if u < 0.25 => MAX_STRENGTH,
        _ => rng.range(0.0, MAX_STRENGTH),
    }
}

/// A tangent-space normal as the blends and the TBN frame get it: a decoded texel, or flat.
fn sample_tangent_space_normal(rng: &mut Rng) -> Vec3 {
    if rng.uniform() < 0.05 {
        return NORMAL;
    }
    let texel = sample_texel(rng).map(f64::from);
    decode_normal(texel, false, sample_strength(rng))
}

/// A vertex tangent for `normal`: near its tangent plane (interpolation bends it), anywhere,
/// or nearly parallel to it; unit or not (interpolated); handedness ±1. None with sin θ
/// within 1e-3 of the degenerate tangents' threshold: the fallback to the normal is a step
/// there, and within fp32 rounding of it (1e-5) the GPU and f64 may take different sides, an
/// O(1) difference that is an error of neither.
fn sample_tangent(rng: &mut Rng, normal: Vec3) -> [f32; 4] {
    let local = loop {
        let local = match rng.uniform() {
            u if u < 0.6 => direction(rng.range(-0.5, 0.5), rng.azimuth()),
            u if u < 0.85 => uniform_sphere(rng),
            // sin θ from the normal (or its opposite) log-uniform in [1e-7, 0.1].
            _ => {
                let sin = rng.log_uniform(1e-7, 0.1);
                let cos = (1.0 - sin * sin).sqrt().copysign(rng.range(-1.0, 1.0));
                direction(cos, rng.azimuth())
            }
        };
        let sin2 = local[0] * local[0] + local[1] * local[1];
        if (sin2 / MIN_TANGENT_SIN2 - 1.0).abs() > 2e-3 {
            break local;
        }
    };
    let length = if rng.uniform() < 0.5 { 1.0 } else { rng.range(0.25, 2.0) };
    let [x, y, z] = about(normal, local).map(|c| c * length);
    let w = if rng.uniform() < 0.5 { 1.0 } else { -1.0 };
    [x as f32, y as f32, z as f32, w]
}

/// What `normal` promises beyond accuracy and unit length, on every tuple, random and
/// stress, GPU and f64.
pub fn rows(normal: UnitVector, tuples: &[Tuple], gpu: &[Values<f32>], cpu: &[Values<f64>]) -> Vec<Row> {
    let both = || {
        tuples.iter().zip(gpu.iter().zip(cpu)).flat_map(|(t, (g, c))| {
            let g = [g[0][0], g[0][1], g[0][2]].map(f64::from);
            [(t, g), (t, [c[0][0], c[0][1], c[0][2]])]
        })
    };
    // The least value of `f` and where it is; NaN is the least.
    let least = |f: &dyn Fn(&Tuple, Vec3) -> f64| {
        both()
            .map(|(t, n)| {
                let x = f(t, n);
                (if x.is_nan() { f64::NEG_INFINITY } else { x }, t)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
    };
    let row = |check: &str, measured: String, tolerance: String, ok: bool, note: String| Row {
        model: normal.name().to_owned(),
        check: check.to_owned(),
        measured,
        tolerance,
        status: if ok { Status::Pass } else { Status::Fail },
        note,
    };
    match normal {
        UnitVector::DecodeNormal => {
            let Some((z, t)) = least(&|_, n| n[2]) else {
                return Vec::new();
            };
            // MIN_TANGENT_Z over the longest (x, y, MIN_TANGENT_Z): at strength 8, texel (1, 1, 0).
            let bound = MIN_TANGENT_Z / (2.0 * MAX_STRENGTH.powi(2) + MIN_TANGENT_Z.powi(2)).sqrt();
            vec![row(
                "z > 0 (above the surface)",
                format!("min z {z:.4e}"),
                format!(">= {bound:.4e} > 0"),
                z >= bound * (1.0 - UNIT_TOLERANCE),
                format!(
                    "MIN_TANGENT_Z {MIN_TANGENT_Z:e} over |(8, 8, MIN_TANGENT_Z)|; all tuples, gpu and f64; at {}",
                    normal.describe(t)
                ),
            )]
        }
        UnitVector::ViewFacingNormal => {
            let Some((n_dot_v, t)) = least(&|t, n| dot(n, rgb(t.b))) else {
                return Vec::new();
            };
            let m = MIN_SHADING_N_DOT_V;
            let bound = m / (1.0 + m * m).sqrt();
            vec![row(
                "n·v >= m/√(1+m²) after the bend",
                format!("min n·v {n_dot_v:.7e}"),
                format!(">= {bound:.7e} − {N_DOT_V_ROUNDING:e}"),
                n_dot_v >= bound - N_DOT_V_ROUNDING,
                format!(
                    "m = MIN_SHADING_N_DOT_V; unit n, v: n + v·(m − n·v) has n·v = m and length \
                     √(1 + 2m·k − k²), k = m − n·v, largest at n·v = 0; all tuples, gpu and f64; at {}",
                    normal.describe(t)
                ),
            )]
        }
        _ => Vec::new(),
    }
}

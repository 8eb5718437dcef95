//! Environment lighting in f64: twins of `shaders/lib/env_math.glsl` (directions,
//! spherical harmonics, sampling and pdfs, the BRDF tables) and `env_studio.glsl`, plus
//! the spherical-harmonic projection of a cube map, which the renderer runs here on the
//! CPU from a read-back mip.

use super::distribution::d_ggx;
use super::geometry::g1_smith_ggx;
use super::shading::{diffuse_lobe, specular_lobe, DiffuseModel, ShadingModels, ShadingParams, SpecularModel};
use super::specular::{Distribution, Geometry};
use super::subsurface::Subsurface;
use super::wrap::{hermite_step, wrap_seed, MIN_WRAP_WIDTH};
use super::{clamp_alpha, cross, dot, Vec3, MIN_N_DOT_V, PI};

const TWO_PI: f64 = 2.0 * PI;

fn scale(a: Vec3, s: f64) -> Vec3 {
    a.map(|x| x * s)
}

fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn normalize(a: Vec3) -> Vec3 {
    scale(a, 1.0 / dot(a, a).sqrt())
}

// ---- Directions ----

/// The point (a, b) in [−1, 1]² on cube face `face` (+x, −x, +y, −y, +z, −z) of the cube
/// of half-side 1: the inverse of Vulkan's cube map face selection, a = 2s − 1,
/// b = 2t − 1. Its major component is ±1: the ray through it per unit major-axis distance.
pub fn cube_face_point(face: u32, a: f64, b: f64) -> Vec3 {
    match face {
        0 => [1.0, -b, -a],
        1 => [-1.0, -b, a],
        2 => [a, 1.0, b],
        3 => [a, -1.0, -b],
        4 => [a, -b, 1.0],
        _ => [-a, -b, -1.0],
    }
}

/// The unit direction through (a, b) on cube face `face` ([`cube_face_point`]).
pub fn cube_direction(face: u32, a: f64, b: f64) -> Vec3 {
    normalize(cube_face_point(face, a, b))
}

/// +1 or −1 per component, +1 at zero: the octahedral fold's quadrant.
fn sign_not_zero(p: [f64; 2]) -> [f64; 2] {
    p.map(|x| if x >= 0.0 { 1.0 } else { -1.0 })
}

/// Where split sum reads direction d in an octahedral map (Engelhardt & Dachsbacher 2008)
/// `side` texels across: d's point p in [−1, 1]² (the octahedron |x| + |y| + |z| = 1
/// projected onto z = 0, its lower half folded out over the square's corners) inside a
/// border of one texel ([`octahedral_direction`]).
pub fn octahedral_uv(d: Vec3, side: f64) -> [f64; 2] {
    let norm = d[0].abs() + d[1].abs() + d[2].abs();
    let mut p = [d[0] / norm, d[1] / norm];
    if d[2] < 0.0 {
        let s = sign_not_zero(p);
        p = [(1.0 - p[1].abs()) * s[0], (1.0 - p[0].abs()) * s[1]];
    }
    p.map(|x| ((x + 1.0) * (0.5 * (side - 2.0)) + 1.0) / side)
}

/// The unit direction of point p of an octahedral map, [`octahedral_uv`]'s inverse; a
/// point past the square's edge (a border texel's) is its neighbour across the edge, the
/// point mirrored about the edge's midpoint.
pub fn octahedral_direction(p: [f64; 2]) -> Vec3 {
    let [mut x, mut y] = p;
    if x.abs() > 1.0 {
        (x, y) = (sign_not_zero([x, y])[0] * (2.0 - x.abs()), -y);
    }
    if y.abs() > 1.0 {
        (x, y) = (-x, sign_not_zero([x, y])[1] * (2.0 - y.abs()));
    }
    let z = 1.0 - x.abs() - y.abs();
    if z < 0.0 {
        let s = sign_not_zero([x, y]);
        (x, y) = ((1.0 - y.abs()) * s[0], (1.0 - x.abs()) * s[1]);
    }
    normalize([x, y, z])
}

/// The point of an octahedral map `side` texels across, a border of one included, at the
/// centre of texel `i` along one axis: the border texels' half a texel past the square's
/// edges.
pub fn octahedral_texel_point(i: u32, side: u32) -> f64 {
    (f64::from(i) - 0.5) * 2.0 / f64::from(side - 2) - 1.0
}

/// (a, b) of the centre of texel (x, y) on a face of `size`² texels.
pub fn cube_texel_ab(x: u32, y: u32, size: u32) -> (f64, f64) {
    let at = |i: u32| (f64::from(i) + 0.5) / f64::from(size) * 2.0 - 1.0;
    (at(x), at(y))
}

/// The solid angle of triangle (a, b, c) seen from the origin, given its triple product
/// a·(b×c) (Van Oosterom & Strackee 1983).
fn triangle_solid_angle(a: Vec3, b: Vec3, c: Vec3, triple: f64) -> f64 {
    let (la, lb, lc) = (dot(a, a).sqrt(), dot(b, b).sqrt(), dot(c, c).sqrt());
    2.0 * triple.atan2(la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la)
}

/// The exact solid angle of texel (x, y) on a face of `size`² texels, the face being
/// [−1, 1]² at unit distance: its two triangles, whose triple product is the texel's area.
pub fn cube_texel_solid_angle(x: u32, y: u32, size: u32) -> f64 {
    let edge = |i: u32| f64::from(i) / f64::from(size) * 2.0 - 1.0;
    let (x0, x1, y0, y1) = (edge(x), edge(x + 1), edge(y), edge(y + 1));
    let (a, b, c, d) = ([x0, y0, 1.0], [x1, y0, 1.0], [x1, y1, 1.0], [x0, y1, 1.0]);
    let area = (x1 - x0) * (y1 - y0);
    triangle_solid_angle(a, b, c, area) + triangle_solid_angle(a, c, d, area)
}

/// Equirectangular (u, v) of unit d: u = 0.5 looks along −z and grows towards +x, v = 0
/// is +y. Straight up or down, u = 0.5.
pub fn equirect_uv(d: Vec3) -> [f64; 2] {
    let horizontal2 = d[0] * d[0] + d[2] * d[2];
    let u = if horizontal2 > 0.0 {
        0.5 + d[0].atan2(-d[2]) / TWO_PI
    } else {
        0.5
    };
    [u, d[1].clamp(-1.0, 1.0).acos() / PI]
}

/// The direction of equirectangular (u, v): the inverse of `equirect_uv`.
pub fn equirect_direction(uv: [f64; 2]) -> Vec3 {
    let theta = uv[1] * PI;
    let phi = (uv[0] - 0.5) * TWO_PI;
    let (sin_t, cos_t) = theta.sin_cos();
    [sin_t * phi.sin(), cos_t, -sin_t * phi.cos()]
}

/// d rotated about +y by the angle whose (cos, sin) is `cs`.
pub fn rotate_y(d: Vec3, cs: [f64; 2]) -> Vec3 {
    [d[0] * cs[0] + d[2] * cs[1], d[1], -d[0] * cs[1] + d[2] * cs[0]]
}

/// (cos, sin) of the rotation that takes world directions into an environment rotated by
/// `degrees` about +y (counter-clockwise seen from above): the inverse rotation, −degrees.
pub fn map_rotation(degrees: f64) -> [f64; 2] {
    let (sin, cos) = (-degrees.to_radians()).sin_cos();
    [cos, sin]
}

/// The report's eq. 17: uv = n(2(n·v)) − v, normalised; the mirror direction of v.
pub fn seed_reflection(n: Vec3, v: Vec3) -> Vec3 {
    normalize(add(scale(n, 2.0 * dot(n, v)), scale(v, -1.0)))
}

/// The mean angle from n of a specular lobe F0 A + B whose parts' mean directions lie at
/// θ_A and θ_B (the BRDF tables' z and w): their mean weighted by `f0_a` = F0 A and `b` = B.
pub fn lobe_mean_angle(f0_a: f64, b: f64, theta_a: f64, theta_b: f64) -> f64 {
    let energy = f0_a + b;
    if energy > 0.0 {
        (f0_a * theta_a + b * theta_b) / energy
    } else {
        0.0
    }
}

/// The direction at angle θ from n towards the mirror direction of v, in the plane of
/// incidence; n where v is n.
pub fn lobe_direction(n: Vec3, v: Vec3, theta: f64) -> Vec3 {
    let towards_mirror = add(scale(n, dot(n, v)), scale(v, -1.0));
    let len = dot(towards_mirror, towards_mirror).sqrt();
    if len < 1e-6 {
        return n;
    }
    add(scale(n, theta.cos()), scale(towards_mirror, theta.sin() / len))
}

/// The prefiltered cube's mip for a lobe of α: α = 2^(lod − last) from mip 1 up, an octave
/// a mip; linear in α from the mirror at mip 0 up to mip 1.
pub fn prefiltered_lod(alpha: f64, last_level: f64) -> f64 {
    let first = (1.0 - last_level).exp2();
    if alpha < first {
        alpha / first
    } else {
        last_level + alpha.log2()
    }
}

/// The α mip `level` is prefiltered for, `prefiltered_lod`'s inverse.
pub fn prefiltered_level_alpha(level: u32, last_level: u32) -> f64 {
    if level == 0 {
        0.0
    } else {
        (f64::from(level) - f64::from(last_level)).exp2()
    }
}

/// The α of a GGX lobe of α lighting a disc of angular radius θ as its centre's
/// direction: α'² = α² + θ²/8. Near its peak a lobe of l has the variance 2α² across each
/// axis (twice the slopes' α²/2, as l turns twice as fast as h), and the disc θ²/4, so
/// their convolution is the lobe of α'.
pub fn sun_alpha(alpha: f64, angular_radius: f64) -> f64 {
    (alpha * alpha + angular_radius * angular_radius / 8.0).sqrt()
}

/// Most lookups of one lobe; shaders/lib/env_math.glsl declares the same.
pub const PREFILTERED_MAX_TAPS: u32 = 8;

/// The split sum's lookups of a lobe seen at n·v (Walter et al. 2007, eq. 14: n·v times
/// as narrow across the plane of incidence as along it): (lookups, width, spacing), the
/// lookups isotropic lobes of α·width spaced evenly along the plane, α·spacing apart, whose
/// mean has variance 2(α n·v)² across and 2α² min(1, 2 n·v) along, with neighbours within
/// two of a lookup's standard deviations (2√2 α·width); past `PREFILTERED_MAX_TAPS` they
/// widen.
pub fn prefiltered_taps(n_dot_v: f64) -> [f64; 3] {
    let mu = n_dot_v.clamp(1e-4, 1.0);
    // Variances over 2α².
    let along = (2.0 * mu).min(1.0);
    let across = mu * mu;
    let taps = (3.0 * along / across - 2.0)
        .max(1.0)
        .sqrt()
        .ceil()
        .clamp(1.0, f64::from(PREFILTERED_MAX_TAPS));
    let widest = 3.0 * along / (taps * taps + 2.0);
    // along − across, factored so that nothing cancels near n·v = 1.
    let spare = if mu >= 0.5 { (1.0 - mu) * (1.0 + mu) } else { mu * (2.0 - mu) };
    let spacing2 = if across < widest {
        24.0 * along / (taps * taps + 2.0)
    } else {
        24.0 * spare / (taps * taps - 1.0).max(1.0)
    };
    [taps, across.max(widest).sqrt(), if taps > 1.0 { spacing2.sqrt() } else { 0.0 }]
}

/// An orthonormal frame (t, b, n) around unit n (Duff et al. 2017).
pub fn tangent_frame(n: Vec3) -> [Vec3; 3] {
    let s = if n[2] >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (s + n[2]);
    let b = n[0] * n[1] * a;
    [
        [1.0 + s * n[0] * n[0] * a, s * b, -s * n[0]],
        [b, s + n[1] * n[1] * a, -n[1]],
        n,
    ]
}

/// `frame * local`: an n-space direction in world space.
pub fn to_world(frame: &[Vec3; 3], local: Vec3) -> Vec3 {
    add(
        add(scale(frame[0], local[0]), scale(frame[1], local[1])),
        scale(frame[2], local[2]),
    )
}

// ---- Spherical harmonics (real, bands 0–2) ----

/// Nine SH coefficients of an RGB function.
pub type Sh9 = [Vec3; 9];

/// Funk–Hecke coefficients of max(μ, 0)/π: irradiance over π (Ramamoorthi & Hanrahan 2001).
pub const SH_IRRADIANCE_OVER_PI: Vec3 = [1.0, 2.0 / 3.0, 0.25];

/// Y_lm(d), ordered (0,0), (1,−1), (1,0), (1,1), (2,−2), (2,−1), (2,0), (2,1), (2,2).
pub fn sh_basis(d: Vec3) -> [f64; 9] {
    let [x, y, z] = d;
    let c0 = 0.5 / PI.sqrt();
    let c1 = (3.0 / (4.0 * PI)).sqrt();
    let c2 = (15.0 / (4.0 * PI)).sqrt();
    let c20 = (5.0 / (16.0 * PI)).sqrt();
    let c22 = (15.0 / (16.0 * PI)).sqrt();
    [
        c0,
        c1 * y,
        c1 * z,
        c1 * x,
        c2 * x * y,
        c2 * y * z,
        c20 * (3.0 * z * z - 1.0),
        c2 * x * z,
        c22 * (x * x - y * y),
    ]
}

/// ∫ L(l) k(d·l) dl from L's SH coefficients `c` and the Funk–Hecke coefficients
/// `kernel` of the zonal kernel k, per band.
pub fn sh_convolve(c: &Sh9, d: Vec3, kernel: Vec3) -> Vec3 {
    let y = sh_basis(d);
    (0..9).fold([0.0; 3], |sum, i| {
        let band = if i == 0 {
            0
        } else if i < 4 {
            1
        } else {
            2
        };
        add(sum, scale(c[i], kernel[band] * y[i]))
    })
}

/// The SH coefficients of a cube map given texel by texel (`texel(face, x, y)`, faces of
/// `size`²): Σ L Y_lm Ω over texels, with each texel's exact solid angle.
pub fn sh_project_cube(size: u32, texel: impl Fn(u32, u32, u32) -> Vec3) -> Sh9 {
    let mut c = [[0.0; 3]; 9];
    for face in 0..6 {
        for y in 0..size {
            for x in 0..size {
                let (a, b) = cube_texel_ab(x, y, size);
                let basis = sh_basis(cube_direction(face, a, b));
                let radiance = scale(texel(face, x, y), cube_texel_solid_angle(x, y, size));
                for (ci, yi) in c.iter_mut().zip(basis) {
                    *ci = add(*ci, scale(radiance, yi));
                }
            }
        }
    }
    c
}

/// Irradiance over π, (1/π) ∫ L(l) max(n·l, 0) dl, towards the centre of every texel of a
/// cube with `out`² faces (face-major, rows from the top, as `texel` numbers them), from a
/// cube map of `size`² faces given texel by texel: quadrature over its texels with their
/// exact solid angles. Three SH bands smooth a bright source into lobes that go negative
/// on its far side (clamped, a dark crescent past the terminator); this does not ring.
pub fn irradiance_over_pi_cube(out: u32, size: u32, texel: impl Fn(u32, u32, u32) -> Vec3) -> Vec<Vec3> {
    use rayon::prelude::*;
    let cube = |size: u32| (0..6).flat_map(move |face| (0..size * size).map(move |i| (face, i % size, i / size)));
    let sources: Vec<(Vec3, Vec3)> = cube(size)
        .filter_map(|(face, x, y)| {
            let radiance = texel(face, x, y);
            let (a, b) = cube_texel_ab(x, y, size);
            let weight = cube_texel_solid_angle(x, y, size) / PI;
            (radiance != [0.0; 3]).then(|| (cube_direction(face, a, b), scale(radiance, weight)))
        })
        .collect();
    let normals: Vec<Vec3> = cube(out)
        .map(|(face, x, y)| {
            let (a, b) = cube_texel_ab(x, y, out);
            cube_direction(face, a, b)
        })
        .collect();
    normals
        .par_iter()
        .map(|&n| {
            sources.iter().fold([0.0; 3], |sum, &(l, weighted)| {
                let cos = dot(n, l);
                if cos > 0.0 {
                    add(sum, scale(weighted, cos))
                } else {
                    sum
                }
            })
        })
        .collect()
}

/// Funk–Hecke coefficients 2π ∫ s(μ) P_l(μ) dμ of the report's wrap term s = `wrap_seed`,
/// exact by 3-point Gauss-Legendre on each of its two cubic pieces.
pub fn wrap_sh_kernel(w1: f64, w2: f64) -> Vec3 {
    let wa = w1.clamp(0.0, 1.0);
    let wb = w2.max(MIN_WRAP_WIDTH);
    let edges = [-wa, wb * (1.0 + wa) - wa, 2.0 * wb * (1.0 + wa) - wa];
    let node = 0.6f64.sqrt();
    let rule = [(-node, 5.0 / 9.0), (0.0, 8.0 / 9.0), (node, 5.0 / 9.0)];
    let mut k = [0.0; 3];
    for piece in edges.windows(2) {
        let (lo, hi) = (piece[0].clamp(-1.0, 1.0), piece[1].clamp(-1.0, 1.0));
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        for (x, w) in rule {
            let mu = mid + half * x;
            let s = w * half * wrap_seed(mu, w1, w2);
            k = add(k, [s, s * mu, s * 0.5 * (3.0 * mu * mu - 1.0)]);
        }
    }
    scale(k, TWO_PI)
}

// ---- Sampling, in n-space (n = +z) ----

/// Point i of the n-point Hammersley set: ((i + ½)/n, radical inverse of i in base 2).
pub fn hammersley(i: u32, n: u32) -> [f64; 2] {
    [
        (f64::from(i) + 0.5) / f64::from(n),
        f64::from(i.reverse_bits()) / 4294967296.0,
    ]
}

/// The R2 sequence's steps 1/g and 1/g² (g the plastic number, the real root of
/// x³ = x + 1) in 0.32 fixed point (Roberts 2018), as `R2_STEP` in env_math.glsl.
pub const R2_STEP: [u32; 2] = [3_242_174_889, 2_447_445_414];

/// Point k of the R2 sequence, frac(k/g, k/g²): the rotation of the `sampled` reflection's
/// sample sets in frame k of an accumulation.
pub fn r2(k: u32) -> [f64; 2] {
    R2_STEP.map(|step| f64::from(k.wrapping_mul(step)) / 4294967296.0)
}

/// Cosine-weighted hemisphere (Malley's method); pdf = n·l/π.
pub fn sample_cosine(u: [f64; 2]) -> Vec3 {
    let r = u[0].sqrt();
    let phi = TWO_PI * u[1];
    [r * phi.cos(), r * phi.sin(), (1.0 - u[0]).max(0.0).sqrt()]
}

pub fn pdf_cosine(n_dot_l: f64) -> f64 {
    n_dot_l.max(0.0) / PI
}

/// Uniform on the sphere; pdf = 1/(4π).
pub fn sample_uniform_sphere(u: [f64; 2]) -> Vec3 {
    let z = 1.0 - 2.0 * u[0];
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = TWO_PI * u[1];
    [r * phi.cos(), r * phi.sin(), z]
}

pub const PDF_UNIFORM_SPHERE: f64 = 0.25 / PI;

/// A GGX visible normal seen from v (v.z > 0), by Dupuy & Benyoub 2023 (spherical caps).
pub fn sample_ggx_vndf(v: Vec3, alpha: f64, u: [f64; 2]) -> Vec3 {
    let vs = normalize([v[0] * alpha, v[1] * alpha, v[2]]);
    let phi = TWO_PI * u[0];
    let z = (1.0 - u[1]) * (1.0 + vs[2]) - vs[2];
    let r = (1.0 - z * z).clamp(0.0, 1.0).sqrt();
    let h = [r * phi.cos() + vs[0], r * phi.sin() + vs[1], z + vs[2]];
    normalize([h[0] * alpha, h[1] * alpha, h[2]])
}

/// The pdf of l = reflect(−v, h) for h from `sample_ggx_vndf`: G1(v) D(h)/(4 n·v)
/// (Heitz 2018, eq. 17).
pub fn pdf_ggx_vndf(alpha: f64, n_dot_v: f64, n_dot_h: f64, n_cross_h_len2: f64) -> f64 {
    let nv = n_dot_v.max(MIN_N_DOT_V);
    g1_smith_ggx(alpha, nv) * d_ggx(alpha, n_dot_h, n_cross_h_len2) / (4.0 * nv)
}

/// l = reflect(−v, h) = 2(v·h)h − v.
pub fn reflect_about(v: Vec3, h: Vec3) -> Vec3 {
    add(scale(h, 2.0 * dot(v, h)), scale(v, -1.0))
}

/// Filtered importance sampling (Colbert & Křivánek 2007, eq. 13 without its bias): the
/// mip whose texel solid angle matches 1/(N p); `n_pdf` = N p.
pub fn filtered_lod(n_pdf: f64, texel_solid_angle: f64) -> f64 {
    (0.5 * (1.0 / (n_pdf.max(1e-30) * texel_solid_angle)).log2()).max(0.0)
}

/// Samples per strategy (cosine, GGX VNDF, uniform sphere, the environment's luminance)
/// out of `total`.
pub fn strategy_counts(total: u32, diffuse: bool, specular: bool, wrap: bool, environment: bool) -> [u32; 4] {
    if !diffuse && !specular {
        return [0, 0, if wrap { total } else { 0 }, 0];
    }
    let n_wrap = if wrap { (total / 4).max(1) } else { 0 };
    let rest = total - n_wrap.min(total);
    let n_environment = if environment { 3 * rest / 4 } else { 0 };
    let rest = rest - n_environment;
    let n_specular = match (specular, diffuse) {
        (false, _) => 0,
        (true, true) => rest / 2,
        (true, false) => rest,
    };
    [rest - n_specular, n_specular, n_wrap, n_environment]
}

// ---- BRDF tables ----

pub const LUT_LAYER_TORRANCE_SPARROW: u32 = 4;
pub const LUT_LAYER_BLINN_PHONG: u32 = 5;
pub const LUT_LAYER_OREN_NAYAR: u32 = 6;
pub const LUT_LAYERS: u32 = 7;

/// The tables' x of n·v: √(1 − n·v), in which Oren-Nayar's albedo (∝ sin θv near the
/// normal) is smooth.
pub fn lut_x(n_dot_v: f64) -> f64 {
    (1.0 - n_dot_v).max(0.0).sqrt()
}

/// The n·v of table x, down to `MIN_N_DOT_V` at x = 1 (the least n·v the shading uses).
pub fn lut_n_dot_v(x: f64) -> f64 {
    (1.0 - x * x).max(MIN_N_DOT_V)
}

/// The parameter of texel `texel` of a table of `size`: i/(size − 1), both ends included.
pub fn lut_parameter(texel: u32, size: u32) -> f64 {
    f64::from(texel) / f64::from(size - 1)
}

/// The texel-centre coordinate at which parameter x in [0, 1] is read:
/// (x (size − 1) + ½)/size.
pub fn lut_coordinate(x: f64, size: u32) -> f64 {
    (x * f64::from(size - 1) + 0.5) / f64::from(size)
}

/// The table layer of a material's specular lobe.
pub fn lut_layer(models: ShadingModels) -> u32 {
    match models.specular {
        SpecularModel::CookTorrance => models.distribution as u32 * 2 + models.geometry as u32,
        SpecularModel::TorranceSparrow => LUT_LAYER_TORRANCE_SPARROW,
        SpecularModel::BlinnPhong | SpecularModel::None => LUT_LAYER_BLINN_PHONG,
    }
}

/// The specular models of a specular layer.
pub fn lut_layer_models(layer: u32) -> ShadingModels {
    let (specular, distribution, geometry) = match layer {
        0..=3 => (
            SpecularModel::CookTorrance,
            if layer / 2 == 0 {
                Distribution::Ggx
            } else {
                Distribution::Beckmann
            },
            if layer % 2 == 0 {
                Geometry::SmithCorrelated
            } else {
                Geometry::SmithSeparable
            },
        ),
        LUT_LAYER_TORRANCE_SPARROW => (
            SpecularModel::TorranceSparrow,
            Distribution::Ggx,
            Geometry::SmithCorrelated,
        ),
        _ => (SpecularModel::BlinnPhong, Distribution::Ggx, Geometry::SmithCorrelated),
    };
    ShadingModels {
        diffuse: DiffuseModel::None,
        specular,
        distribution,
        geometry,
        subsurface: Subsurface::None,
    }
}

/// The white material the tables are computed for: roughness and σ = `y`.
fn lut_material(y: f64, f0: f64) -> ShadingParams {
    ShadingParams {
        base_color: [1.0; 3],
        specular_color: [1.0; 3],
        wrap_color: [0.0; 3],
        wrap_intensity: 0.0,
        roughness: y,
        f0,
        diffuse_roughness: y,
        wrap: 0.0,
        wrap_width: 1.0,
        scatter_color: [0.0; 3],
        scatter_radius: 0.0,
        metallic: 0.0,
    }
}

/// The view direction at n·v = `n_dot_v` with n = +z.
pub fn lut_view(n_dot_v: f64) -> Vec3 {
    [(1.0 - n_dot_v * n_dot_v).sqrt(), 0.0, n_dot_v]
}

/// One texel of `layer` at n·v = `n_dot_v`, roughness (σ) = y, as env_brdf_lut.comp
/// estimates it with `samples` Hammersley points: (A, B, θ_A, θ_B) for specular layers, the
/// angles being those of each part's mean direction ∫ l f_s cos from n towards the mirror
/// direction; (albedo, 0, 0, 0) for Oren-Nayar. Torrance-Sparrow draws normals by D(h)(n·h)
/// rather than as visible from v: its V-cavity masking G ≤ 2(n·h)(n·v)/(v·h) keeps those
/// weights bounded at grazing n·v, where Smith's visible normals leave them heavy-tailed
/// (2× off at n·v = 1e-4).
pub fn brdf_lut_estimate(layer: u32, n_dot_v: f64, y: f64, samples: u32) -> [f64; 4] {
    const N: Vec3 = [0.0, 0.0, 1.0];
    let v = lut_view(n_dot_v);
    let mut sum = [0.0; 2];
    // Each part's ∫ l f_s cos as (towards the mirror direction, along n).
    let mut means = [[0.0; 2]; 2];
    if layer == LUT_LAYER_OREN_NAYAR {
        let m = lut_material(y, 0.0);
        for i in 0..samples {
            let l = sample_cosine(hammersley(i, samples));
            sum[0] += PI * diffuse_lobe(DiffuseModel::OrenNayar, &m, N, v, l, n_dot_v, l[2])[0];
        }
    } else {
        let models = lut_layer_models(layer);
        let alpha = clamp_alpha(y * y);
        let (m0, m1) = (lut_material(y, 0.0), lut_material(y, 1.0));
        let by_d = layer == LUT_LAYER_TORRANCE_SPARROW;
        for i in 0..samples {
            let h = sample_ggx_vndf(if by_d { N } else { v }, alpha, hammersley(i, samples));
            let l = reflect_about(v, h);
            if l[2] <= 0.0 {
                continue;
            }
            let n_cross_h_len2 = h[0] * h[0] + h[1] * h[1];
            let pdf = if by_d {
                pdf_ggx_vndf(alpha, 1.0, h[2], n_cross_h_len2) * h[2] / dot(v, h)
            } else {
                pdf_ggx_vndf(alpha, n_dot_v, h[2], n_cross_h_len2)
            };
            let b = specular_lobe(models, &m0, N, v, l, n_dot_v, l[2])[0];
            let a_plus_b = specular_lobe(models, &m1, N, v, l, n_dot_v, l[2])[0];
            let weights = [(a_plus_b - b) * l[2] / pdf, b * l[2] / pdf];
            for (part, w) in weights.into_iter().enumerate() {
                sum[part] += w;
                means[part][0] -= w * l[0];
                means[part][1] += w * l[2];
            }
        }
    }
    let angle = |[towards_mirror, along_n]: [f64; 2]| towards_mirror.atan2(along_n);
    let n = f64::from(samples);
    [sum[0] / n, sum[1] / n, angle(means[0]), angle(means[1])]
}

// ---- The studio ----

const STUDIO_FLOOR: Vec3 = [0.09, 0.085, 0.08];
const STUDIO_HORIZON: Vec3 = [0.34, 0.33, 0.32];
const STUDIO_CEILING: Vec3 = [0.15, 0.16, 0.19];
const STUDIO_FLOOR_FADE: f64 = 0.3;
const STUDIO_CEILING_FADE: f64 = 0.6;

/// (radiance, centre, half-size, softness) of the key, fill and rim boxes.
const STUDIO_BOXES: [(Vec3, Vec3, [f64; 2], f64); 3] = [
    ([6.0, 5.75, 5.3], [-0.55, 0.55, 0.63], [0.45, 0.3], 0.06),
    ([1.5, 1.65, 1.9], [0.85, 0.2, 0.35], [0.1, 0.55], 0.04),
    ([4.0, 3.9, 3.7], [0.25, 0.6, -0.75], [0.35, 0.2], 0.05),
];

fn mix(a: Vec3, b: Vec3, t: f64) -> Vec3 {
    add(scale(a, 1.0 - t), scale(b, t))
}

/// How much of a soft box direction d sees (see env_studio.glsl).
pub fn soft_box(d: Vec3, centre: Vec3, half_size: [f64; 2], softness: f64) -> f64 {
    let q = dot(d, centre);
    if q <= 0.0 {
        return 0.0;
    }
    let t = normalize(cross(centre, [0.0, 1.0, 0.0]));
    let b = cross(t, centre);
    let p = [dot(d, t).abs() / q, dot(d, b).abs() / q];
    (0..2)
        .map(|i| 1.0 - hermite_step(half_size[i] - softness, half_size[i] + softness, p[i]))
        .product()
}

/// The studio's radiance arriving from unit direction d.
pub fn studio_radiance(d: Vec3) -> Vec3 {
    let background = if d[1] < 0.0 {
        mix(
            STUDIO_HORIZON,
            STUDIO_FLOOR,
            hermite_step(0.0, STUDIO_FLOOR_FADE, -d[1]),
        )
    } else {
        mix(
            STUDIO_HORIZON,
            STUDIO_CEILING,
            hermite_step(0.0, STUDIO_CEILING_FADE, d[1]),
        )
    };
    STUDIO_BOXES
        .iter()
        .fold(background, |sum, &(radiance, centre, half_size, softness)| {
            add(
                sum,
                scale(radiance, soft_box(d, normalize(centre), half_size, softness)),
            )
        })
}

#[cfg(test)]
#[path = "environment_tests.rs"]
mod tests;

//! Sampling a material's lobes, in the frame of the shading normal (n = +z): cosine for
//! the diffuse lobe, visible normals for GGX (Dupuy & Benyoub 2023, the same routine as
//! the shader's `sampled` mode) and Beckmann (Heitz & d'Eon 2014, by numerical inversion as
//! in pbrt-v3), the normalised Blinn-Phong distribution, and the uniform sphere for the
//! subsurface term, which lights below the horizon too. One sample picks a strategy by the
//! lobes' weights; its pdf is the mixture's (one-sample MIS with the balance heuristic).

use std::f64::consts::PI;

use glam::DVec3;

use crate::brdf::distribution::d_beckmann;
use crate::brdf::environment::{pdf_ggx_vndf, sample_cosine, sample_ggx_vndf, sample_uniform_sphere};
use crate::brdf::geometry::{erf, lambda_beckmann_exact};
use crate::brdf::shading::{DiffuseModel, ShadingModels, ShadingParams, SpecularModel};
use crate::brdf::specular::{log_n_dot_h, Distribution};
use crate::brdf::tonemap::luminance;
use crate::brdf::{clamp_alpha, MIN_N_DOT_V};

/// How the specular lobe's half vectors are drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpecularSampling {
    GgxVisible,
    BeckmannVisible,
    /// h ∝ (n·h)ⁿ (n·h): the Blinn-Phong distribution with exponent n.
    BlinnPhong(f64),
}

/// The lobes a sample can come from, with the probability of each strategy.
#[derive(Clone, Copy, Debug)]
pub struct Lobes {
    pub alpha: f64,
    pub specular: Option<SpecularSampling>,
    /// Probabilities of cosine, specular and uniform-sphere sampling; they sum to 1.
    pub weights: [f64; 3],
}

impl Lobes {
    /// The strategies for a material seen at `n_dot_v` (the shading normal's). The
    /// weights only shape the variance; any positive weights give the same expectation.
    /// Specular sampling needs the view above the horizon, where visible normals exist.
    pub fn new(models: ShadingModels, m: &ShadingParams, n_dot_v: f64, subsurface_lights: bool) -> Self {
        let alpha = clamp_alpha(m.roughness * m.roughness);
        let specular = match models.specular {
            SpecularModel::None => None,
            _ if n_dot_v < MIN_N_DOT_V => None,
            SpecularModel::BlinnPhong => Some(SpecularSampling::BlinnPhong(2.0 / (alpha * alpha) - 2.0)),
            SpecularModel::TorranceSparrow => Some(SpecularSampling::BeckmannVisible),
            SpecularModel::CookTorrance => Some(match models.distribution {
                Distribution::Ggx => SpecularSampling::GgxVisible,
                Distribution::Beckmann => SpecularSampling::BeckmannVisible,
            }),
        };
        let diffuse = if models.diffuse == DiffuseModel::None {
            0.0
        } else {
            luminance(m.diffuse_color()).max(1e-3)
        };
        let specular_weight = if specular.is_some() {
            // Schlick's Fresnel at n·v, so grazing views favour the specular lobe.
            let f0 = luminance(m.specular_f0());
            let f = f0 + (1.0 - f0) * (1.0 - n_dot_v.clamp(0.0, 1.0)).powi(5);
            (luminance(m.specular_color) * f).max(1e-3).max(0.1 * diffuse)
        } else {
            0.0
        };
        let sphere = if subsurface_lights {
            0.25 * (diffuse + specular_weight).max(1e-3)
        } else {
            0.0
        };
        let total = diffuse + specular_weight + sphere;
        let weights = if total > 0.0 {
            [diffuse / total, specular_weight / total, sphere / total]
        } else {
            // A black material still needs a direction to continue a path.
            [1.0, 0.0, 0.0]
        };
        Self {
            alpha,
            specular,
            weights,
        }
    }

    /// A direction l (n-space) for the view v (n-space), from uniform numbers u; none
    /// where a half vector faces away from v (Blinn-Phong's, which ignore v): that
    /// strategy's pdf is then a sub-density, which keeps the mixture's estimate unbiased.
    pub fn sample(&self, v: DVec3, u: [f64; 3]) -> Option<DVec3> {
        let [w_diffuse, w_specular, _] = self.weights;
        let u2 = [u[1], u[2]];
        if u[0] < w_diffuse {
            return Some(DVec3::from(sample_cosine(u2)));
        }
        if let (Some(specular), true) = (self.specular, u[0] < w_diffuse + w_specular) {
            let h = match specular {
                SpecularSampling::GgxVisible => DVec3::from(sample_ggx_vndf(v.to_array(), self.alpha, u2)),
                SpecularSampling::BeckmannVisible => sample_beckmann_vndf(v, self.alpha, u2),
                SpecularSampling::BlinnPhong(exponent) => sample_blinn_phong(exponent, u2),
            };
            let v_dot_h = v.dot(h);
            return (v_dot_h > 0.0).then(|| 2.0 * v_dot_h * h - v);
        }
        Some(DVec3::from(sample_uniform_sphere(u2)))
    }

    /// The mixture's pdf of l (n-space) for the view v (n-space), per steradian.
    pub fn pdf(&self, v: DVec3, l: DVec3) -> f64 {
        let [w_diffuse, w_specular, w_sphere] = self.weights;
        let mut pdf = w_sphere * 0.25 / PI;
        if w_diffuse > 0.0 && l.z > 0.0 {
            pdf += w_diffuse * l.z / PI;
        }
        if let (Some(specular), true) = (self.specular, w_specular > 0.0) {
            pdf += w_specular * specular_pdf(specular, self.alpha, v, l);
        }
        pdf
    }
}

/// The pdf of l = reflect(−v, h) for the half vectors `specular` draws.
fn specular_pdf(specular: SpecularSampling, alpha: f64, v: DVec3, l: DVec3) -> f64 {
    let h = v + l;
    if h.length_squared() < 1e-20 {
        return 0.0;
    }
    let h = h.normalize();
    let n_dot_h = h.z;
    let len2 = h.x * h.x + h.y * h.y;
    match specular {
        _ if v.dot(h) <= 0.0 => 0.0,
        SpecularSampling::GgxVisible => pdf_ggx_vndf(alpha, v.z, n_dot_h.max(0.0), len2),
        SpecularSampling::BeckmannVisible => {
            // Heitz 2018 eq. 17 with Beckmann's exact Smith G1.
            let g1 = 1.0 / (1.0 + lambda_beckmann_exact(alpha, v.z));
            g1 * d_beckmann(alpha, n_dot_h, len2) / (4.0 * v.z)
        }
        SpecularSampling::BlinnPhong(exponent) => {
            let v_dot_h = v.dot(h);
            if n_dot_h <= 0.0 {
                return 0.0;
            }
            let d = (exponent + 2.0) / (2.0 * PI) * (exponent * log_n_dot_h(n_dot_h, len2)).exp();
            d * n_dot_h / (4.0 * v_dot_h)
        }
    }
}

/// cos θh = u^(1/(n+2)): the pdf (n+2)/(2π) (n·h)ⁿ⁺¹ of half vectors.
fn sample_blinn_phong(exponent: f64, u: [f64; 2]) -> DVec3 {
    let cos = u[0].powf(1.0 / (exponent + 2.0));
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    DVec3::new(sin * phi.cos(), sin * phi.sin(), cos)
}

/// The inverse of erf on (−1, 1), by Newton's method from Giles 2010's single-precision
/// approximation ("Approximating the erfinv function", GPU Computing Gems).
fn erf_inv(y: f64) -> f64 {
    let y = y.clamp(-1.0 + 1e-15, 1.0 - 1e-15);
    let w = -((1.0 - y) * (1.0 + y)).ln();
    let mut x = if w < 5.0 {
        let w = w - 2.5;
        let mut p = 2.810_226_36e-08;
        for c in [
            3.432_739_39e-07,
            -3.523_387_7e-06,
            -4.391_506_54e-06,
            0.000_218_580_87,
            -0.001_253_725_03,
            -0.004_177_681_64,
            0.246_640_727,
            1.501_409_41,
        ] {
            p = c + p * w;
        }
        p * y
    } else {
        let w = w.sqrt() - 3.0;
        let mut p = -0.000_200_214_257;
        for c in [
            0.000_100_950_558,
            0.001_349_343_22,
            -0.003_673_428_44,
            0.005_739_507_73,
            -0.007_622_461_3,
            0.009_438_870_47,
            1.001_674_06,
            2.832_976_82,
        ] {
            p = c + p * w;
        }
        p * y
    };
    let two_over_sqrt_pi = 2.0 / PI.sqrt();
    for _ in 0..4 {
        let step = (erf(x) - y) / (two_over_sqrt_pi * (-x * x).exp());
        x -= step;
        if step.abs() <= 1e-14 * x.abs().max(1.0) {
            break;
        }
    }
    x
}

/// Slopes (x, y) of a visible normal of the unit-roughness Beckmann distribution seen at
/// cos θ = `cos_theta` from the x direction (Heitz & d'Eon 2014): the x slope inverts
/// the visible-slope CDF C(x) = (1 + erf(x) + tanθ e^(−x²)/√π) / (1 + erf(cot θ) + tanθ
/// e^(−cot²θ)/√π) on the erf domain b = erf(x), by safeguarded Newton steps (pbrt-v3's
/// BeckmannSample11, to a tighter tolerance); the y slope is a plain Gaussian.
fn beckmann_visible_slopes(cos_theta: f64, u: [f64; 2]) -> (f64, f64) {
    if cos_theta > 0.999_999_9 {
        let r = (-(1.0 - u[0]).ln()).sqrt();
        let phi = 2.0 * PI * u[1];
        return (r * phi.cos(), r * phi.sin());
    }
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let tan_theta = sin_theta / cos_theta;
    let cot_theta = 1.0 / tan_theta;
    let inv_sqrt_pi = 1.0 / PI.sqrt();
    let (mut lo, mut hi) = (-1.0, erf(cot_theta));
    let target = u[0].max(1e-12);
    let normalization = 1.0 / (1.0 + hi + inv_sqrt_pi * tan_theta * (-cot_theta * cot_theta).exp());
    let theta = cos_theta.acos();
    let fit = 1.0 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta));
    let mut b = hi - (1.0 + hi) * (1.0 - target).powf(fit);
    for _ in 0..64 {
        if !(b >= lo && b <= hi) {
            b = 0.5 * (lo + hi);
        }
        let x = erf_inv(b);
        let value = normalization * (1.0 + b + inv_sqrt_pi * tan_theta * (-x * x).exp()) - target;
        if value.abs() < 1e-13 {
            break;
        }
        if value > 0.0 {
            hi = b;
        } else {
            lo = b;
        }
        let derivative = normalization * (1.0 - x * tan_theta);
        b -= value / derivative;
        if hi - lo < 1e-15 {
            break;
        }
    }
    (erf_inv(b), erf_inv(2.0 * u[1].clamp(1e-12, 1.0 - 1e-12) - 1.0))
}

/// A Beckmann visible normal seen from v (v.z > 0): stretch, sample the unit-roughness
/// slopes, rotate to v's azimuth, unstretch (Heitz & d'Eon 2014, §4).
fn sample_beckmann_vndf(v: DVec3, alpha: f64, u: [f64; 2]) -> DVec3 {
    let stretched = DVec3::new(alpha * v.x, alpha * v.y, v.z).normalize();
    let (sx, sy) = beckmann_visible_slopes(stretched.z, u);
    let r = stretched.x.hypot(stretched.y);
    let (cos_phi, sin_phi) = if r > 0.0 {
        (stretched.x / r, stretched.y / r)
    } else {
        (1.0, 0.0)
    };
    let (x, y) = (cos_phi * sx - sin_phi * sy, sin_phi * sx + cos_phi * sy);
    DVec3::new(-alpha * x, -alpha * y, 1.0).normalize()
}

/// The balance of two strategies under the power heuristic with β = 2 (Veach 1997, §9.2.4):
/// the weight of the one whose pdf is `a`.
pub fn power_heuristic(a: f64, b: f64) -> f64 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

#[cfg(test)]
#[path = "sampling_tests.rs"]
mod tests;

/// A direction from `p` towards a sphere of `radius` about `center`, sampled uniformly in
/// the cone of directions it subtends (pbrt-v4 `Sphere::Sample(ctx, u)`, PBR 4th ed.,
/// §6.2.4): the unit direction, the distance to the sphere's near side along it, and its
/// solid-angle pdf 1/(2π(1 − cos θmax)). None from inside the sphere.
pub fn sample_sphere_light(center: DVec3, radius: f64, p: DVec3, u: [f64; 2]) -> Option<(DVec3, f64, f64)> {
    let to_center = center - p;
    let distance2 = to_center.length_squared();
    if distance2 <= radius * radius {
        return None;
    }
    let distance = distance2.sqrt();
    let sin2_max = radius * radius / distance2;
    let sin_max = sin2_max.sqrt();
    let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
    // 1 − cos θ without cancellation, where pbrt-v4 switches to a Taylor expansion below
    // 1.5° (whose error, sin²θmax/4 relative, a 0.01 sphere at 2 shows at 6e-6): uniform
    // in cos θ ∈ [cos θmax, 1] is t = u(1 − cos θmax), sin²θ = t(2 − t).
    let one_minus_cos_max = sin2_max / (1.0 + cos_max);
    let t = u[0] * one_minus_cos_max;
    let cos_theta = 1.0 - t;
    let sin2_theta = t * (2.0 - t);
    // The angle α at the sphere's centre between −(its direction) and the point hit.
    let cos_alpha = sin2_theta / sin_max + cos_theta * (1.0 - sin2_theta / sin2_max).max(0.0).sqrt();
    let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    let frame = crate::brdf::environment::tangent_frame((-to_center / distance).to_array()).map(DVec3::from);
    let on_sphere = center
        + radius * (frame[0] * (sin_alpha * phi.cos()) + frame[1] * (sin_alpha * phi.sin()) + frame[2] * cos_alpha);
    let to_point = on_sphere - p;
    let length = to_point.length();
    Some((to_point / length, length, 1.0 / (2.0 * PI * one_minus_cos_max)))
}

//! The material's lobes put together: twins of `shaders/lib/shading.glsl`.

use serde::{Deserialize, Serialize};

use super::diffuse::{diffuse_eon, diffuse_lambert, diffuse_oren_nayar};
use super::specular::{spec_blinn_phong, spec_cook_torrance, spec_torrance_sparrow, Distribution, Geometry};
use super::subsurface::{subsurface_transfer, Subsurface};
use super::wrap::wrap_seed;
use super::{clamp_alpha, cross, dot, safe_half_vector, Vec3, MIN_N_DOT_V, PI};

// The `as u32` values of these enums are shader specialization constants (the
// `DIFFUSE_*`/`SPECULAR_*` constants of shading.glsl): never reorder or renumber.

/// Diffuse lobe. `diffuse_roughness` is σ in radians for Oren-Nayar and the roughness r
/// of EON (energy-preserving Oren-Nayar).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum DiffuseModel {
    #[default]
    Lambert = 0,
    OrenNayar = 1,
    Eon = 2,
    None = 3,
}

/// Specular lobe.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum SpecularModel {
    #[default]
    CookTorrance = 0,
    TorranceSparrow = 1,
    BlinnPhong = 2,
    None = 3,
}

/// How light near the shading normal's horizon is treated. The value is the `HORIZON`
/// specialization constant of forward.frag: never renumber.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[repr(u32)]
pub enum Horizon {
    /// `brdf_cos` with a view-facing shading normal and the terminator's shadowing.
    #[default]
    Smooth = 0,
    /// The report's composition and hard cutoff (`brdf_cos_seed`), for comparison.
    Seed = 1,
}

/// The models of a material (`ShadingModels` in GLSL).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShadingModels {
    pub diffuse: DiffuseModel,
    pub specular: SpecularModel,
    pub distribution: Distribution,
    pub geometry: Geometry,
    pub subsurface: Subsurface,
}

/// A material's parameters in f64 (`Material` in GLSL).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingParams {
    pub base_color: Vec3,
    pub specular_color: Vec3,
    pub wrap_color: Vec3,
    pub wrap_intensity: f64,
    pub roughness: f64,
    pub f0: f64,
    pub diffuse_roughness: f64,
    pub wrap: f64,
    pub wrap_width: f64,
    /// Per-channel reach of the energy-conserving wrap and pre-integrated models.
    pub scatter_color: Vec3,
    /// The pre-integrated model's profile σ at scatter_color 1, in scene units.
    pub scatter_radius: f64,
    /// 0 dielectric, 1 metal: see [`ShadingParams::specular_f0`].
    pub metallic: f64,
}

impl ShadingParams {
    /// glTF 2.0's metallic-roughness blend (glTF 2.0 specification, appendix B): the
    /// albedo of the diffuse lobes and of the subsurface terms, base_color·(1 − metallic).
    pub fn diffuse_color(&self) -> Vec3 {
        scale(self.base_color, 1.0 - self.metallic)
    }

    /// The specular lobe's F0 in the same blend, mix(f0, base_color, metallic): a metal
    /// reflects its base colour. Both are linear in metallic, so is the BRDF: the blend's
    /// energy is (1 − metallic) E_dielectric + metallic E_metal.
    pub fn specular_f0(&self) -> Vec3 {
        self.base_color
            .map(|c| self.f0 * (1.0 - self.metallic) + c * self.metallic)
    }
}

/// Smallest n·v of a shading normal after it is turned towards the viewer.
pub const MIN_SHADING_N_DOT_V: f64 = 1e-3;

fn scale(a: Vec3, s: f64) -> Vec3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn add(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn mul(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] * b[0], a[1] * b[1], a[2] * b[2]]
}

/// A visible point's shading normal cannot face away from the eye: one that does (normal
/// maps, interpolated normals at silhouettes) is turned towards v, continuously, until
/// n·v = m = `MIN_SHADING_N_DOT_V` before normalisation; after it, for unit n and v,
/// n·v ≥ m/√(1 + m²). As in GLSL, n + v·(m − n·v) is computed as s + v·(m − |s|²/2),
/// s = n + v, which keeps its digits as v → −n.
pub fn view_facing_normal(n: Vec3, v: Vec3) -> Vec3 {
    let n_dot_v = dot(n, v);
    if n_dot_v >= MIN_SHADING_N_DOT_V {
        return n;
    }
    let s = add(n, v);
    let bent = add(s, scale(v, MIN_SHADING_N_DOT_V - 0.5 * dot(s, s)));
    scale(bent, 1.0 / dot(bent, bent).sqrt())
}

/// Chiang, Li & Burley 2019 ("Taming the Shadow Terminator"): the shadowing of a bumped
/// surface whose shading normal n_s leans away from its geometric normal n_g,
/// G = min(1, (n_g·l)/((n_s·l)(n_g·n_s))), smoothed as −G³ + G² + G; 0 below n_g's horizon.
pub fn shadow_terminator(ng_dot_l: f64, ns_dot_l: f64, ng_dot_ns: f64) -> f64 {
    if ng_dot_l <= 0.0 || ns_dot_l <= 0.0 {
        return 0.0;
    }
    let g = (ng_dot_l / (ns_dot_l * ng_dot_ns.max(MIN_N_DOT_V))).min(1.0);
    g * (1.0 + g * (1.0 - g))
}

/// The diffuse lobe f_d (without the cosine), albedo included.
pub fn diffuse_lobe(
    model: DiffuseModel,
    m: &ShadingParams,
    n: Vec3,
    v: Vec3,
    l: Vec3,
    n_dot_v: f64,
    n_dot_l: f64,
) -> Vec3 {
    match model {
        DiffuseModel::Lambert => scale(m.diffuse_color(), diffuse_lambert()),
        DiffuseModel::OrenNayar => scale(m.diffuse_color(), diffuse_oren_nayar(m.diffuse_roughness, n, v, l)),
        DiffuseModel::Eon => diffuse_eon(m.diffuse_color(), m.diffuse_roughness, n_dot_v, n_dot_l, dot(v, l)),
        DiffuseModel::None => [0.0; 3],
    }
}

/// The specular lobe f_s (without the cosine), tinted by the specular colour.
pub fn specular_lobe(
    models: ShadingModels,
    m: &ShadingParams,
    n: Vec3,
    v: Vec3,
    l: Vec3,
    n_dot_v: f64,
    n_dot_l: f64,
) -> Vec3 {
    if models.specular == SpecularModel::None {
        return [0.0; 3];
    }
    let alpha = clamp_alpha(m.roughness * m.roughness);
    let h = safe_half_vector(v, l, n);
    let n_cross_h = cross(n, h);
    let n_dot_h = dot(n, h).max(0.0);
    let len2 = dot(n_cross_h, n_cross_h);
    let v_dot_h = dot(v, h).max(0.0);
    let f0 = m.specular_f0();
    let f = match models.specular {
        SpecularModel::CookTorrance => spec_cook_torrance(
            alpha,
            n_dot_v,
            n_dot_l,
            n_dot_h,
            len2,
            f0,
            v_dot_h,
            models.distribution,
            models.geometry,
        ),
        SpecularModel::TorranceSparrow => spec_torrance_sparrow(alpha, n_dot_v, n_dot_l, n_dot_h, len2, f0, v_dot_h),
        SpecularModel::BlinnPhong | SpecularModel::None => spec_blinn_phong(alpha, n_dot_h, len2, f0, v_dot_h),
    };
    mul(m.specular_color, f)
}

/// Whether the subsurface term lights anything: only it reaches below the horizon.
pub fn subsurface_lights(models: ShadingModels, m: &ShadingParams) -> bool {
    match models.subsurface {
        Subsurface::Seed => m.wrap_intensity > 0.0,
        model => model.redistributes() && models.diffuse != DiffuseModel::None,
    }
}

/// The reach of a redistributing model per channel: w · scatter_color for the
/// energy-conserving wrap, t = σκ with σ = scatter_radius · scatter_color for the
/// pre-integrated model, κ the surface's curvature (concave counts as flat).
pub fn subsurface_reach(model: Subsurface, m: &ShadingParams, curvature: f64) -> Vec3 {
    if model == Subsurface::EnergyConservingWrap {
        return scale(m.scatter_color, m.wrap);
    }
    scale(m.scatter_color, m.scatter_radius * curvature.max(0.0))
}

/// The subsurface term, per unit irradiance: the report's wrap (eq. 18, colour ×
/// intensity/π × s) for `Seed`, or ρ/π (K − max(0, n·l)) for the models that move light
/// across the terminator (`subsurface_transfer`).
pub fn subsurface_cos(models: ShadingModels, m: &ShadingParams, n_dot_l: f64, curvature: f64) -> Vec3 {
    if !subsurface_lights(models, m) {
        return [0.0; 3];
    }
    if models.subsurface == Subsurface::Seed {
        return scale(
            m.wrap_color,
            m.wrap_intensity / PI * wrap_seed(n_dot_l, m.wrap, m.wrap_width),
        );
    }
    let reach = subsurface_reach(models.subsurface, m, curvature);
    let transfer = subsurface_transfer(models.subsurface, n_dot_l, reach);
    let (lambert, albedo) = (n_dot_l.max(0.0), m.diffuse_color());
    std::array::from_fn(|c| albedo[c] / PI * (transfer[c] - lambert))
}

/// Reflected radiance per unit irradiance E⊥ arriving along l, for shading normal `n`
/// (already facing the viewer) on a surface of geometric normal `n_geometric` and
/// curvature `curvature`: f(n, v, l)(n·l) times the terminator shadowing, plus the
/// subsurface term, which lights where n·l ≤ 0 too.
pub fn brdf_cos(
    models: ShadingModels,
    m: &ShadingParams,
    n: Vec3,
    n_geometric: Vec3,
    v: Vec3,
    l: Vec3,
    curvature: f64,
) -> Vec3 {
    let n_dot_l = dot(n, l);
    let subsurface = subsurface_cos(models, m, n_dot_l, curvature);
    if n_dot_l <= 0.0 {
        return subsurface;
    }
    let n_dot_v = dot(n, v).max(MIN_N_DOT_V);
    let f = add(
        diffuse_lobe(models.diffuse, m, n, v, l, n_dot_v, n_dot_l),
        specular_lobe(models, m, n, v, l, n_dot_v, n_dot_l),
    );
    let shadowing = shadow_terminator(dot(n_geometric, l), n_dot_l, dot(n_geometric, n));
    with_subsurface(models, add(scale(f, n_dot_l * shadowing), subsurface))
}

/// `lit` (the lobes plus the subsurface term), clamped at 0 for the models that take light
/// away: where the lobes are shadowed or below Lambert, less may be left than they move.
/// A NaN is kept, not clamped, so that checks still see it.
fn with_subsurface(models: ShadingModels, lit: Vec3) -> Vec3 {
    if models.subsurface.redistributes() {
        lit.map(|x| if x < 0.0 { 0.0 } else { x })
    } else {
        lit
    }
}

/// The report's composition, for comparison (`horizon = "seed"`): i = d + s (seed eq. 3)
/// with d the diffuse lobe times n·l and s the specular BRDF of eq. 11 without a cosine,
/// hard-coded to 0 where n·l ≤ 0 (the report's fix of its figure 5a); the subsurface term
/// is added as in `brdf_cos`.
pub fn brdf_cos_seed(models: ShadingModels, m: &ShadingParams, n: Vec3, v: Vec3, l: Vec3, curvature: f64) -> Vec3 {
    let n_dot_l = dot(n, l);
    let subsurface = subsurface_cos(models, m, n_dot_l, curvature);
    if n_dot_l <= 0.0 {
        return subsurface;
    }
    let n_dot_v = dot(n, v).max(MIN_N_DOT_V);
    let lobes = add(
        scale(diffuse_lobe(models.diffuse, m, n, v, l, n_dot_v, n_dot_l), n_dot_l),
        specular_lobe(models, m, n, v, l, n_dot_v, n_dot_l),
    );
    with_subsurface(models, add(lobes, subsurface))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_normal_facing_away_is_bent_no_further_than_it_must() {
        let m = MIN_SHADING_N_DOT_V;
        let least = m / (1.0 + m * m).sqrt();
        let n = [0.0, 0.0, 1.0];
        // Facing normals are kept; n·v = 0 gives the least n·v after the bend; v = −n gives v.
        assert_eq!(view_facing_normal(n, [0.6, 0.0, 0.8]), n);
        assert!((dot(view_facing_normal(n, [1.0, 0.0, 0.0]), [1.0, 0.0, 0.0]) - least).abs() < 1e-15);
        let away = view_facing_normal(n, [0.0, 0.0, -1.0]);
        assert!((away[2] + 1.0).abs() < 1e-12, "{away:?}");
        for i in 0..=2000 {
            let c = -1.0 + f64::from(i) * 1e-3;
            let v = [(1.0 - c * c).sqrt(), 0.0, c];
            let bent = view_facing_normal(n, v);
            assert!(dot(bent, v) >= least - 1e-15, "n·v {c}: {}", dot(bent, v));
            assert!((dot(bent, bent) - 1.0).abs() < 1e-12);
        }
    }
}

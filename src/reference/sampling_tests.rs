//! χ² tests of every lobe's sampling routine against its pdf (see `chi2.rs`).

use super::*;
use crate::brdf::shading::ShadingModels;
use crate::brdf::specular::{Distribution, Geometry};
use crate::brdf::subsurface::Subsurface;
use crate::reference::chi2::{chi2, direction};

fn params(roughness: f64) -> ShadingParams {
    ShadingParams {
        base_color: [0.5, 0.4, 0.3],
        specular_color: [1.0; 3],
        wrap_color: [1.0; 3],
        wrap_intensity: 0.0,
        roughness,
        f0: 0.04,
        diffuse_roughness: 0.3,
        wrap: 0.3,
        wrap_width: 0.3,
        scatter_color: [1.0; 3],
        scatter_radius: 0.1,
    }
}

fn view(cos: f64) -> DVec3 {
    direction(cos, 0.7)
}

/// One specular strategy alone (all weight on it), at two roughnesses and three views.
fn specular_sampling_matches_its_pdf(specular: SpecularModel, distribution: Distribution, label: &str) {
    for roughness in [0.35, 0.8] {
        // Blinn-Phong's pdf of l, D(h)(n·h)/(4 v·h), has an integrable singularity at l = −v,
        // where its half vectors, drawn without regard to v, still have weight at grazing
        // views; the midpoint quadrature cannot integrate it there.
        let grazing = if specular == SpecularModel::BlinnPhong {
            0.4
        } else {
            0.15
        };
        for cos in [1.0, 0.6, grazing] {
            let models = ShadingModels {
                diffuse: DiffuseModel::None,
                specular,
                distribution,
                geometry: Geometry::SmithCorrelated,
                subsurface: Subsurface::None,
            };
            let lobes = Lobes::new(models, &params(roughness), cos, false);
            assert_eq!(lobes.weights, [0.0, 1.0, 0.0]);
            let v = view(cos);
            let name = format!("{label} roughness {roughness} n·v {cos}");
            let integral = chi2(
                &name,
                |rng| lobes.sample(v, [rng.uniform(), rng.uniform(), rng.uniform()]),
                |l| lobes.pdf(v, l),
            );
            // Visible normals reflect into a density of total mass 1; Blinn-Phong's half
            // vectors that face away from v are dropped.
            assert!(integral <= 1.0 + 2e-3, "{name}: ∫ pdf = {integral}");
            if specular != SpecularModel::BlinnPhong {
                assert!((integral - 1.0).abs() < 2e-3, "{name}: ∫ pdf = {integral}");
            }
        }
    }
}

#[test]
fn ggx_visible_normals_match_their_pdf() {
    specular_sampling_matches_its_pdf(SpecularModel::CookTorrance, Distribution::Ggx, "ggx");
}

#[test]
fn beckmann_visible_normals_match_their_pdf() {
    specular_sampling_matches_its_pdf(SpecularModel::CookTorrance, Distribution::Beckmann, "beckmann");
}

#[test]
fn blinn_phong_half_vectors_match_their_pdf() {
    specular_sampling_matches_its_pdf(SpecularModel::BlinnPhong, Distribution::Ggx, "blinn-phong");
}

/// The mixture of cosine, specular and uniform-sphere sampling, as a subsurface clay uses.
#[test]
fn mixture_sampling_matches_its_pdf() {
    let models = ShadingModels {
        diffuse: DiffuseModel::Lambert,
        specular: SpecularModel::CookTorrance,
        distribution: Distribution::Ggx,
        geometry: Geometry::SmithCorrelated,
        subsurface: Subsurface::PreIntegrated,
    };
    for cos in [0.9, 0.3] {
        let lobes = Lobes::new(models, &params(0.5), cos, true);
        assert!(lobes.weights.iter().all(|&w| w > 0.05), "{:?}", lobes.weights);
        let v = view(cos);
        let integral = chi2(
            &format!("mixture n·v {cos}"),
            |rng| lobes.sample(v, [rng.uniform(), rng.uniform(), rng.uniform()]),
            |l| lobes.pdf(v, l),
        );
        assert!((integral - 1.0).abs() < 2e-3, "∫ pdf = {integral}");
    }
}

/// The inverse of erf, which Beckmann's visible slopes are built on.
#[test]
fn erf_inv_inverts_erf() {
    for i in -999..=999 {
        let y = f64::from(i) * 1e-3;
        let x = erf_inv(y);
        assert!((erf(x) - y).abs() < 1e-13, "erf(erf_inv({y})) = {}", erf(x));
    }
}

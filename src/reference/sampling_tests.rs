//! χ² tests of every lobe's sampling routine against its pdf (see `chi2.rs`).

use super::*;
use crate::brdf::shading::ShadingModels;
use crate::brdf::specular::{Distribution, Geometry};
use crate::brdf::subsurface::Subsurface;
use crate::reference::chi2::{chi2, direction};
use crate::rng::Rng;

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
        metallic: 0.0,
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

/// Irradiance from a uniformly emitting sphere of radiance I/(πr²) (the power of a point
/// light of intensity I) on a surface whose horizon it lies wholly above is I cos θ / d²,
/// exactly as from the point: the estimate from solid-angle samples must agree within
/// its own noise, facing the light and tilted, for a large and a tiny sphere (where
/// 1 − cos θmax would cancel).
#[test]
fn sphere_light_samples_give_the_point_lights_irradiance() {
    let center = DVec3::new(0.3, 2.0, -0.4);
    for (radius, tilt) in [(0.8, 0.0), (0.8, 0.6), (0.01, 0.0), (0.01, 1.0)] {
        let n = DVec3::new(tilt, 1.0, 0.0).normalize();
        let radiance = 1.0 / (PI * radius * radius);
        let mut rng = Rng::new(7);
        let count = 200_000;
        let (mut sum, mut sum2) = (0.0, 0.0);
        for _ in 0..count {
            let (l, distance, pdf) =
                sample_sphere_light(center, radius, DVec3::ZERO, [rng.uniform(), rng.uniform()]).expect("outside");
            // The sample lies on the sphere.
            assert!(((l * distance - center).length() - radius).abs() < 1e-9 * center.length());
            let x = radiance * l.dot(n).max(0.0) / pdf;
            sum += x;
            sum2 += x * x;
        }
        let mean = sum / count as f64;
        let sigma = ((sum2 / count as f64 - mean * mean) / count as f64).sqrt();
        let exact = n.dot(center.normalize()) / center.length_squared();
        assert!(
            (mean - exact).abs() <= 4.0 * sigma + 1e-12 * exact,
            "radius {radius}, tilt {tilt}: {mean} against {exact} (σ {sigma})"
        );
    }
    assert!(sample_sphere_light(center, 3.0, DVec3::ZERO, [0.5, 0.5]).is_none());
}

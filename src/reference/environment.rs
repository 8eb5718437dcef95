//! The scene's environment as the reference sees it: the radiance arriving from each
//! direction, evaluated exactly (the studio's f64 function, an equirectangular map read
//! bilinearly as `env_equirect.comp` reads it, before any cube map, mip or fp16 rounding),
//! and sampled in proportion to a bound of its luminance (`LuminanceDistribution`, at the
//! map's own resolution).

use std::f64::consts::PI;
use std::path::Path;

use anyhow::Result;
use glam::DVec3;

use crate::brdf::environment::{equirect_uv, map_rotation, rotate_y, studio_radiance};
use crate::brdf::luminance_distribution::LuminanceDistribution;
use crate::render::environment::equirect;
use crate::scene::Environment;

enum Source {
    Uniform(DVec3),
    Studio,
    Map {
        width: usize,
        height: usize,
        texels: Vec<DVec3>,
    },
}

pub struct EnvironmentLight {
    source: Source,
    intensity: f64,
    /// (cos, sin) taking world directions into the map's frame.
    to_map: [f64; 2],
    /// Importance sampling over the map's (u, v); none for a uniform environment, which is
    /// sampled uniformly over the sphere.
    distribution: Option<LuminanceDistribution>,
}

impl EnvironmentLight {
    /// None for `Environment::None`.
    pub fn new(environment: &Environment) -> Result<Option<Self>> {
        let (source, intensity, rotation) = match environment {
            Environment::None => return Ok(None),
            Environment::Uniform { radiance, .. } => (Source::Uniform(radiance.as_dvec3()), 1.0, 0.0),
            Environment::Studio {
                intensity,
                rotation_degrees,
                ..
            } => (Source::Studio, *intensity, *rotation_degrees),
            Environment::Map {
                path,
                intensity,
                rotation_degrees,
                ..
            } => (load_map(path)?, *intensity, *rotation_degrees),
        };
        Ok(Some(Self::from_source(
            source,
            f64::from(intensity),
            f64::from(rotation),
        )))
    }

    fn from_source(source: Source, intensity: f64, rotation_degrees: f64) -> Self {
        let distribution = match &source {
            Source::Uniform(_) => None,
            Source::Studio => Some(LuminanceDistribution::studio()),
            Source::Map { width, height, texels } => {
                let texels: Vec<_> = texels.iter().map(|t| t.to_array()).collect();
                Some(LuminanceDistribution::map(&texels, *width, *height, *width))
            }
        };
        Self {
            source,
            intensity,
            to_map: map_rotation(rotation_degrees),
            distribution,
        }
    }

    /// Radiance arriving from unit world direction d.
    pub fn radiance(&self, d: DVec3) -> DVec3 {
        let m = DVec3::from(rotate_y(d.to_array(), self.to_map));
        self.intensity
            * match &self.source {
                Source::Uniform(radiance) => *radiance,
                Source::Studio => DVec3::from(studio_radiance(m.to_array())),
                Source::Map { width, height, texels } => {
                    let [u, v] = equirect_uv(m.to_array());
                    bilinear(texels, *width, *height, u, v)
                }
            }
    }

    /// Whether sampling by luminance helps: a uniform environment is better integrated by
    /// the material's own sampling alone (cosine-weighted lobes against a uniform sphere),
    /// which also makes a white Lambert furnace exact at one sample.
    pub fn worth_sampling(&self) -> bool {
        self.distribution.is_some()
    }

    /// A direction towards the environment and its pdf per steradian.
    pub fn sample(&self, u: [f64; 2]) -> (DVec3, f64) {
        let (m, pdf) = match &self.distribution {
            None => {
                let z = 1.0 - 2.0 * u[0];
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = 2.0 * PI * u[1];
                (DVec3::new(r * phi.cos(), r * phi.sin(), z), 0.25 / PI)
            }
            Some(distribution) => {
                let (m, pdf) = distribution.sample_direction(u);
                (DVec3::from(m), pdf)
            }
        };
        let from_map = [self.to_map[0], -self.to_map[1]];
        (DVec3::from(rotate_y(m.to_array(), from_map)), pdf)
    }

    /// The pdf of `sample` choosing unit world direction d.
    pub fn pdf(&self, d: DVec3) -> f64 {
        let Some(distribution) = &self.distribution else {
            return 0.25 / PI;
        };
        distribution.pdf_direction(rotate_y(d.to_array(), self.to_map))
    }
}

fn load_map(path: &Path) -> Result<Source> {
    let map = equirect::load(path)?;
    Ok(Source::Map {
        width: map.width as usize,
        height: map.height as usize,
        texels: map
            .texels
            .iter()
            .map(|t| DVec3::new(f64::from(t[0]), f64::from(t[1]), f64::from(t[2])))
            .collect(),
    })
}

/// As `env_equirect.comp`: texel centres at (i + ½)/w, wrapping in u, clamped in v.
fn bilinear(texels: &[DVec3], width: usize, height: usize, u: f64, v: f64) -> DVec3 {
    let x = u * width as f64 - 0.5;
    let y = v * height as f64 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let column = |i: f64| (i.rem_euclid(width as f64) as usize).min(width - 1);
    let row = |j: f64| j.clamp(0.0, (height - 1) as f64) as usize;
    let at = |i: f64, j: f64| texels[row(j) * width + column(i)];
    let top = at(x0, y0).lerp(at(x0 + 1.0, y0), fx);
    let bottom = at(x0, y0 + 1.0).lerp(at(x0 + 1.0, y0 + 1.0), fx);
    top.lerp(bottom, fy)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::environment::equirect_direction;
    use crate::brdf::tonemap;
    use crate::reference::chi2::chi2;
    use crate::rng::Rng;

    fn luminance(c: DVec3) -> f64 {
        tonemap::luminance(c.to_array())
    }

    /// A dim map with a bright patch, rotated: sampling by luminance against its pdf.
    #[test]
    fn map_sampling_matches_its_pdf() {
        let (width, height) = (64, 32);
        let texels = (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                if (40..44).contains(&x) && (9..12).contains(&y) {
                    DVec3::new(40.0, 30.0, 20.0)
                } else {
                    DVec3::splat(0.2 + 0.1 * (x as f64 / width as f64))
                }
            })
            .collect();
        let light = EnvironmentLight::from_source(Source::Map { width, height, texels }, 1.5, 70.0);
        chi2(
            "map",
            |rng| Some(light.sample([rng.uniform(), rng.uniform()]).0),
            |d| light.pdf(d),
        );
    }

    /// A map of one bright texel on a dim one: over every direction, radiance over pdf stays
    /// within 18 ∫ L dω (the nine cells that read the texel, times sin θ's change across a
    /// row), including where bilinear filtering carries it into its neighbours' cells;
    /// weighting a cell by its own texel alone gives 4,700 ∫ L dω there.
    #[test]
    fn map_radiance_over_pdf_is_bounded_next_to_a_bright_texel() {
        let (width, height) = (32, 16);
        let texels = (0..width * height)
            .map(|i| DVec3::splat(if i == 6 * width + 11 { 1e4 } else { 1.0 }))
            .collect();
        let light = EnvironmentLight::from_source(Source::Map { width, height, texels }, 1.0, 0.0);
        // Midpoint quadrature on a grid 16 times finer than the map's in each direction.
        let (w, h) = (16 * width, 16 * height);
        let (mut integral, mut worst) = (0.0_f64, 0.0_f64);
        for y in 0..h {
            let v = (y as f64 + 0.5) / h as f64;
            let solid_angle = (v * PI).sin() * (PI / h as f64) * (2.0 * PI / w as f64);
            for x in 0..w {
                let d = DVec3::from(equirect_direction([(x as f64 + 0.5) / w as f64, v]));
                let l = luminance(light.radiance(d));
                integral += l * solid_angle;
                worst = worst.max(l / light.pdf(d));
            }
        }
        assert!(worst < 18.0 * integral, "L/pdf up to {worst}, ∫ L dω = {integral}");
    }

    #[test]
    fn studio_sampling_matches_its_pdf() {
        let light = EnvironmentLight::from_source(Source::Studio, 1.0, -20.0);
        chi2(
            "studio",
            |rng| Some(light.sample([rng.uniform(), rng.uniform()]).0),
            |d| light.pdf(d),
        );
    }

    /// ∫ L(ω)/pdf(ω) over samples of the studio equals ∫ L dω by quadrature: the sampler's
    /// pdf is the density of what it draws, and `pdf` agrees with `sample`.
    #[test]
    fn studio_samples_estimate_its_integral() {
        let light = EnvironmentLight::new(&Environment::Studio {
            intensity: 1.0,
            rotation_degrees: 30.0,
            reflection: Default::default(),
        })
        .unwrap()
        .unwrap();
        let mut rng = Rng::new(7);
        let n = 200_000;
        let mut estimate = 0.0;
        for _ in 0..n {
            let (d, pdf) = light.sample([rng.uniform(), rng.uniform()]);
            assert!((light.pdf(d) / pdf - 1.0).abs() < 1e-6, "pdf {pdf} vs {}", light.pdf(d));
            estimate += luminance(light.radiance(d)) / pdf;
        }
        estimate /= n as f64;
        // Midpoint quadrature on a 2048 × 1024 grid in (u, v).
        let (w, h) = (2048, 1024);
        let mut exact = 0.0;
        for y in 0..h {
            let v = (y as f64 + 0.5) / h as f64;
            let solid_angle = (v * PI).sin() * (PI / h as f64) * (2.0 * PI / w as f64);
            for x in 0..w {
                let d = DVec3::from(equirect_direction([(x as f64 + 0.5) / w as f64, v]));
                exact += luminance(DVec3::from(studio_radiance(d.to_array()))) * solid_angle;
            }
        }
        assert!(
            (estimate / exact - 1.0).abs() < 5e-3,
            "estimate {estimate}, quadrature {exact}"
        );
    }
}

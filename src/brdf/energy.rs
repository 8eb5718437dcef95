//! Multiple-scattering energy compensation of the specular lobe: twin of
//! `specular_energy_compensation` in `shaders/lib/brdf.glsl` and of the E(μ) lookup of
//! `shaders/lib/environment.glsl`.
//!
//! A single-scattering microfacet lobe reflects E(μ) < 1 of a white furnace at high
//! roughness: the light that bounces between facets more than once is lost. Kulla & Conty
//! 2017 add a lobe for it; Fdez-Agüera 2019 and Filament approximate that lobe's sum with
//! the single-scattering one scaled by 1 + F0 (1/E − 1), E read from the split-sum table
//! the environment already uses (E = A + B, the lobe's albedo at F0 = 1), so a white
//! conductor reflects exactly 1 of the table's E.

use std::sync::OnceLock;

use super::environment::{brdf_lut_estimate, lut_layer, lut_n_dot_v, lut_parameter, lut_x, LUT_LAYER_BLINN_PHONG};
use super::shading::ShadingModels;
use super::Vec3;
use crate::cache::{self, DiskCache};

/// Smallest single-scattering albedo E the compensation divides by: the table's least
/// specular E (grazing Torrance-Sparrow) is above it, and it bounds the factor by 1/E = 20.
pub const MIN_SPECULAR_ALBEDO: f64 = 0.05;

/// Fdez-Agüera 2019 (Kulla & Conty 2017 simplified, as Filament has it): the factor
/// 1 + F0 (1/E − 1) on the single-scattering lobe, E clamped to [MIN_SPECULAR_ALBEDO, 1]
/// (never darkening) and F0 to [0, 1].
pub fn specular_energy_compensation(e: f64, f0: Vec3) -> Vec3 {
    let e = e.clamp(MIN_SPECULAR_ALBEDO, 1.0);
    f0.map(|f| 1.0 + f.clamp(0.0, 1.0) * (1.0 / e - 1.0))
}

/// The single-scattering albedo E(n·v, roughness) = A + B of the specular layers of the
/// BRDF tables, texel for texel as env_brdf_lut.comp estimates them (`brdf_lut_estimate`
/// with the GPU's size and sample count, which tests/environment.rs holds to the GPU's
/// table), read as `brdf_table` reads them: linearly between texels.
pub struct SpecularAlbedoTable {
    width: u32,
    height: u32,
    /// Layer-major, then row (roughness), then column (lut_x).
    texels: Vec<f64>,
}

impl SpecularAlbedoTable {
    /// The table at the renderer's size, read from the disk cache or computed (about a
    /// second) once per process.
    pub fn get() -> &'static SpecularAlbedoTable {
        use crate::render::environment::{LUT_SAMPLES, LUT_SIZE};
        static TABLE: OnceLock<SpecularAlbedoTable> = OnceLock::new();
        TABLE.get_or_init(|| Self::cached(&DiskCache::from_env(), LUT_SIZE.width, LUT_SIZE.height, LUT_SAMPLES))
    }

    fn cached(cache: &DiskCache, width: u32, height: u32, samples: u32) -> SpecularAlbedoTable {
        let key = cache::key(&[
            include_str!("energy.rs").as_bytes(),
            include_str!("environment.rs").as_bytes(),
            include_str!("shading.rs").as_bytes(),
            include_str!("specular.rs").as_bytes(),
            include_str!("distribution.rs").as_bytes(),
            include_str!("geometry.rs").as_bytes(),
            include_str!("fresnel.rs").as_bytes(),
            &[width, height, samples].map(u32::to_le_bytes).concat(),
        ]);
        let count = (LUT_LAYER_BLINN_PHONG as usize + 1) * (width * height) as usize;
        let bytes = cache.get_or_compute(
            "specular-albedo",
            key,
            |b| b.len() == count * std::mem::size_of::<f64>(),
            || bytemuck::cast_slice(&Self::compute(width, height, samples)).to_vec(),
        );
        SpecularAlbedoTable {
            width,
            height,
            texels: bytemuck::pod_collect_to_vec(&bytes),
        }
    }

    /// Layers are independent: one thread each.
    fn compute(width: u32, height: u32, samples: u32) -> Vec<f64> {
        let layers: Vec<Vec<f64>> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..=LUT_LAYER_BLINN_PHONG)
                .map(|layer| {
                    scope.spawn(move || {
                        let mut out = Vec::with_capacity((width * height) as usize);
                        for y in 0..height {
                            for x in 0..width {
                                let n_dot_v = lut_n_dot_v(lut_parameter(x, width));
                                let [a, b, ..] = brdf_lut_estimate(layer, n_dot_v, lut_parameter(y, height), samples);
                                out.push(a + b);
                            }
                        }
                        out
                    })
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
                .collect()
        });
        layers.concat()
    }

    fn texel(&self, layer: u32, x: u32, y: u32) -> f64 {
        self.texels[((layer * self.height + y) * self.width + x) as usize]
    }

    /// E of the specular lobe of `models` (none: Blinn-Phong's layer, as `lut_layer`) at
    /// n·v and perceptual roughness, bilinear between texels i/(size − 1).
    pub fn lookup(&self, models: ShadingModels, n_dot_v: f64, roughness: f64) -> f64 {
        let layer = lut_layer(models);
        let position = |p: f64, size: u32| {
            let s = p.clamp(0.0, 1.0) * f64::from(size - 1);
            let i = (s.floor() as u32).min(size - 2);
            (i, s - f64::from(i))
        };
        let (x, fx) = position(lut_x(n_dot_v), self.width);
        let (y, fy) = position(roughness, self.height);
        let row = |y| self.texel(layer, x, y) * (1.0 - fx) + self.texel(layer, x + 1, y) * fx;
        row(y) * (1.0 - fy) + row(y + 1) * fy
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::environment::lut_layer_models;

    /// At a texel's parameters a lookup is the texel; halfway between four it is their mean.
    #[test]
    fn lookups_read_texels_and_interpolate_between_them() {
        let (width, height) = (5, 4);
        let table = SpecularAlbedoTable::cached(&DiskCache::at(None), width, height, 64);
        for layer in 0..=LUT_LAYER_BLINN_PHONG {
            let models = lut_layer_models(layer);
            // The last column's n·v is clamped to MIN_N_DOT_V, off its lut_x by 5e-5.
            for x in 0..width - 1 {
                for y in 0..height {
                    let at = table.lookup(models, lut_n_dot_v(lut_parameter(x, width)), lut_parameter(y, height));
                    assert!((at - table.texel(layer, x, y)).abs() < 1e-12, "layer {layer} ({x}, {y})");
                }
            }
            let mid = |i: u32, size: u32| (f64::from(i) + 0.5) / f64::from(size - 1);
            let between = table.lookup(models, lut_n_dot_v(mid(1, width)), mid(2, height));
            let mean = [(1, 2), (2, 2), (1, 3), (2, 3)]
                .map(|(x, y)| table.texel(layer, x, y))
                .iter()
                .sum::<f64>()
                / 4.0;
            assert!((between - mean).abs() < 1e-12, "layer {layer}: {between} vs {mean}");
        }
    }

    /// A white conductor's factor is 1/E, a non-reflecting F0 leaves the lobe alone, and E
    /// outside [MIN_SPECULAR_ALBEDO, 1] is clamped.
    #[test]
    fn the_factor_makes_up_a_white_lobes_loss() {
        let [white, black, _] = specular_energy_compensation(0.6, [1.0, 0.0, 0.5]);
        assert!((white - 1.0 / 0.6).abs() < 1e-15 && black == 1.0);
        assert_eq!(specular_energy_compensation(0.0, [1.0; 3])[0], 1.0 / MIN_SPECULAR_ALBEDO);
        assert_eq!(specular_energy_compensation(1.5, [1.0; 3])[0], 1.0);
    }
}

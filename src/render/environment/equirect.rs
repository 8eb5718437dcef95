//! Equirectangular environment maps from `.hdr` (Radiance) and `.exr` files: decoded with
//! the `image` crate, checked, and reduced to the resolution the cube map can hold.

use std::path::Path;

use anyhow::{bail, Context, Result};
use image::ImageReader;

use crate::error::InputError;
use crate::scene::limits::check_environment_map;
use crate::scene::Scene;

/// Maps are box-filtered down to this width before upload: a 512² cube face, the largest
/// argil builds, holds a quarter of it around the equator.
pub const MAX_UPLOAD_WIDTH: u32 = 2048;

/// Linear RGB radiance, rows from the top (+y), twice as wide as tall.
pub struct Equirect {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 4]>,
}

/// Loads and checks an equirectangular map: one that `check_environment_map` accepts, with
/// finite non-negative radiance. Errors name the file.
pub fn load(path: &Path) -> Result<Equirect> {
    read(path).map_err(|e| InputError(format!("environment map {}: {e:#}", path.display())).into())
}

/// A map that cannot be used, after the scene file that names it, as the scene's own errors
/// begin (the scene refused what the map's headers show as it loaded; what only decoding
/// shows is found here).
pub fn in_scene_file(error: anyhow::Error, scene: &Scene) -> anyhow::Error {
    match (error.downcast_ref::<InputError>(), &scene.source) {
        (Some(InputError(problem)), Some(file)) => {
            InputError(format!("{}: environment.path: {problem}", file.display())).into()
        }
        _ => error,
    }
}

fn read(path: &Path) -> Result<Equirect> {
    let (width, height) = check_environment_map(path).map_err(anyhow::Error::msg)?;
    let reader = ImageReader::open(path).context("cannot open")?.with_guessed_format().context("cannot read")?;
    let image = reader.decode().context("cannot decode")?.into_rgb32f();
    let mut texels = Vec::with_capacity(image.pixels().len());
    for (x, y, p) in image.enumerate_pixels() {
        let [r, g, b] = p.0;
        if !(r.is_finite() && g.is_finite() && b.is_finite()) {
            bail!("texel ({x}, {y}) is not finite: [{r}, {g}, {b}]");
        }
        if r < 0.0 || g < 0.0 || b < 0.0 {
            bail!("texel ({x}, {y}) has negative radiance: [{r}, {g}, {b}]");
        }
        texels.push([r, g, b, 1.0]);
    }
    let map = Equirect { width, height, texels };
    let factor = width.div_ceil(MAX_UPLOAD_WIDTH);
    Ok(if factor > 1 { downsample(&map, factor) } else { map })
}

/// The mean of each `factor`² block; the last column and row of blocks may be narrower.
fn downsample(map: &Equirect, factor: u32) -> Equirect {
    let (width, height) = (map.width.div_ceil(factor), map.height.div_ceil(factor));
    let mut texels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let (x0, y0) = (x * factor, y * factor);
            let (x1, y1) = ((x0 + factor).min(map.width), (y0 + factor).min(map.height));
            let mut sum = [0.0f64; 3];
            for sy in y0..y1 {
                for sx in x0..x1 {
                    let t = map.texels[(sy * map.width + sx) as usize];
                    for c in 0..3 {
                        sum[c] += f64::from(t[c]);
                    }
                }
            }
            let n = f64::from((x1 - x0) * (y1 - y0));
            texels.push([(sum[0] / n) as f32, (sum[1] / n) as f32, (sum[2] / n) as f32, 1.0]);
        }
    }
    Equirect { width, height, texels }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn downsampling_averages_blocks() {
        let map = Equirect {
            width: 6,
            height: 3,
            texels: (0..18).map(|i| [i as f32, 1.0, 0.0, 1.0]).collect(),
        };
        let small = downsample(&map, 2);
        assert_eq!((small.width, small.height), (3, 2));
        // Block (0, 0): texels 0, 1, 6, 7; the last row holds one row of texels (12..18).
        assert_eq!(small.texels[0], [3.5, 1.0, 0.0, 1.0]);
        assert_eq!(small.texels[3], [12.5, 1.0, 0.0, 1.0]);
    }
}

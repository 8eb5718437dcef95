//! The equirectangular map of the bench's `sphere-sky` scene, generated rather than
//! shipped: a clear sky over a dark ground with a small sun whose radiance is about 10³
//! times the sky's. That dynamic range is what a map asks of the renderer (the cube map's
//! mips and split-sum's prefilter must not smear the sun; `sampled` must find it) and of
//! the reference (its importance sampling of the map).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use glam::DVec3;

use crate::brdf::environment::equirect_direction;
use crate::atomic::Existing;
use crate::render::output::write_exr;

/// Texels of the map: 0.7° each, so the sun spans about four across.
const WIDTH: usize = 512;
const HEIGHT: usize = 256;
/// The sun is 1.5° in radius (the real one is 0.27°) so that the map resolves its disc.
const SUN_RADIUS_DEGREES: f64 = 1.5;
const SUN_ELEVATION_DEGREES: f64 = 35.0;
/// Measured from −z (the map's centre) towards +x, so the sun lights the sphere from the
/// front right as the bench camera on +z sees it.
const SUN_AZIMUTH_DEGREES: f64 = 140.0;
/// Linear RGB; with its solid angle the sun gives about twice the sky's irradiance on a
/// surface facing it.
const SUN_RADIANCE: [f64; 3] = [1500.0, 1400.0, 1250.0];
const ZENITH: [f64; 3] = [0.25, 0.45, 0.95];
const HORIZON: [f64; 3] = [1.1, 1.15, 1.2];
const GROUND: [f64; 3] = [0.12, 0.1, 0.08];

/// The file name carries the generator's version, so a change to the sky is a new
/// file and a new reference (whose key is the scene text naming it).
pub const FILE_NAME: &str = "sky-v1.exr";

/// The sky's path in `dir`, written there (atomically) if it is not there yet.
pub fn ensure(dir: &Path) -> Result<PathBuf> {
    let path = dir.join(FILE_NAME);
    if !path.exists() {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let rgba: Vec<f32> = texels()
            .flat_map(|c| [c.x as f32, c.y as f32, c.z as f32, 1.0])
            .collect();
        write_exr(
            &path,
            Existing::Replace,
            WIDTH as u32,
            HEIGHT as u32,
            &rgba,
            &[("argil.generator", FILE_NAME.into())],
        )?;
    }
    Ok(path)
}

/// Radiance of the texels, row by row from the top.
fn texels() -> impl Iterator<Item = DVec3> {
    (0..HEIGHT).flat_map(|y| {
        (0..WIDTH).map(move |x| {
            radiance(DVec3::from(equirect_direction([
                (x as f64 + 0.5) / WIDTH as f64,
                (y as f64 + 0.5) / HEIGHT as f64,
            ])))
        })
    })
}

fn sun_direction() -> DVec3 {
    let (elevation, azimuth) = (SUN_ELEVATION_DEGREES.to_radians(), SUN_AZIMUTH_DEGREES.to_radians());
    DVec3::new(
        elevation.cos() * azimuth.sin(),
        elevation.sin(),
        -elevation.cos() * azimuth.cos(),
    )
}

/// Radiance arriving from unit direction `d`: the sun's disc, else the sky graded from
/// the horizon to the zenith, else the ground.
fn radiance(d: DVec3) -> DVec3 {
    if d.dot(sun_direction()) >= SUN_RADIUS_DEGREES.to_radians().cos() {
        return DVec3::from(SUN_RADIANCE);
    }
    if d.y < 0.0 {
        return DVec3::from(GROUND);
    }
    DVec3::from(HORIZON).lerp(DVec3::from(ZENITH), d.y.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sun_is_resolved_and_outshines_the_sky() {
        let texels: Vec<DVec3> = texels().collect();
        let sun = texels.iter().filter(|c| c.x == SUN_RADIANCE[0]).count();
        assert!((10..100).contains(&sun), "{sun} sun texels");
        let brightest_sky = texels
            .iter()
            .filter(|c| c.x < SUN_RADIANCE[0])
            .map(|c| c.y)
            .fold(0.0, f64::max);
        assert!(SUN_RADIANCE[1] / brightest_sky > 1000.0);
    }

    #[test]
    fn the_sky_is_written_once_and_reads_back() {
        let dir = std::env::temp_dir().join(format!("argil-sky-{}", std::process::id()));
        let path = ensure(&dir).unwrap();
        let written = std::fs::metadata(&path).unwrap().modified().unwrap();
        assert_eq!(ensure(&dir).unwrap(), path);
        assert_eq!(std::fs::metadata(&path).unwrap().modified().unwrap(), written);
        let map = crate::render::environment::equirect::load(&path).unwrap();
        assert_eq!((map.width as usize, map.height as usize), (WIDTH, HEIGHT));
        std::fs::remove_dir_all(dir).unwrap();
    }
}

//! The references the bench measures error against, rendered once per scene, size and
//! settings and cached as EXRs named by a hash of all three.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use crate::cache::fnv1a;
use crate::compare::input::read_exr;
use crate::compare::metrics::Rgba32;
use crate::reference::{Filter, Sampling, Settings, Stop, SubsurfaceTransport, Transport};
use crate::render::output::write_linear;
use crate::scene::Scene;

/// A reference image and its own estimated relative RMS noise.
pub struct CachedReference {
    pub image: Rgba32,
    pub noise: f64,
    pub samples: u32,
    pub path: PathBuf,
}

/// The settings of a bench reference: box filter, MIS, each material's own subsurface
/// model, seed 1, stopped at `stop`.
pub fn settings(width: u32, height: u32, transport: Transport, stop: Stop) -> Settings {
    Settings {
        width,
        height,
        transport,
        filter: Filter::Box,
        sampling: Sampling::Mis,
        subsurface: SubsurfaceTransport::Model,
        stop,
        seed: 1,
        max_depth: Settings::DEFAULT_MAX_DEPTH,
    }
}

/// `dir/NAME-TRANSPORT-HASH.exr`, the hash over the scene text and the settings (which
/// hold the size); a change of either names another file.
pub fn path(dir: &Path, name: &str, text: &str, settings: &Settings) -> PathBuf {
    let key = format!("{text}\n{settings:?}");
    dir.join(format!(
        "{name}-{}-{:016x}.exr",
        settings.transport,
        fnv1a(key.as_bytes())
    ))
}

/// The cached reference of the scene `text`, rendered and written first if it is not cached.
pub fn get(dir: &Path, name: &str, text: &str, settings: &Settings) -> Result<CachedReference> {
    let path = path(dir, name, text, settings);
    if !path.is_file() {
        let scene = Scene::from_toml(text, name, Path::new(""))?;
        eprintln!(
            "argil: bench: rendering the {} reference of {name} at {}x{} into {}",
            settings.transport,
            settings.width,
            settings.height,
            path.display()
        );
        let image = crate::reference::render(&scene, settings, &())?;
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        write_linear(
            &path,
            image.width,
            image.height,
            &image.rgba,
            1.0,
            &image.exr_attributes(settings),
        )?;
    }
    let exr = read_exr(&path)?;
    let number = |key: &str| {
        exr.attributes
            .get(key)
            .and_then(|v| v.as_str())
            .and_then(|s| s.parse::<f64>().ok())
            .with_context(|| format!("{}: no {key} in its header", path.display()))
    };
    Ok(CachedReference {
        noise: number("argil.noise")?,
        samples: number("argil.spp")? as u32,
        image: exr.image,
        path,
    })
}

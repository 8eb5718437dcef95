//! What the bench renders: scenes, each as scene-file text, and the configurations of the
//! renderer it times on each, built by editing the scene file.

use anyhow::{Context, Result};
use ash::vk;

use crate::scene::file::{EnvironmentDef, SceneFile};
use crate::scene::{Horizon, ReflectionMode, Subsurface, DEFAULT_SCENE_TOML};

/// The configuration whose name marks the report's composition in the table and plot.
pub const REPORT: &str = "report";
/// The trivial-shader floor every time is divided by.
pub const FLOOR: &str = "floor";

/// One way of rendering a scene.
pub struct Configuration {
    pub name: String,
    /// The scene file of this configuration (the scene's own text with its edits).
    pub text: String,
    /// Drawn with `floor.frag` instead of the materials.
    pub floor: bool,
    /// Frame sizes it is timed at; the first is the headline.
    pub resolutions: Vec<vk::Extent2D>,
}

/// A scene with its configurations; its references are of `text`, argil's defaults.
pub struct BenchScene {
    pub name: &'static str,
    pub text: String,
    pub configurations: Vec<Configuration>,
}

pub const HEADLINE: vk::Extent2D = vk::Extent2D {
    width: 1280,
    height: 720,
};
const SMALL: vk::Extent2D = vk::Extent2D {
    width: 640,
    height: 360,
};
const LARGE: vk::Extent2D = vk::Extent2D {
    width: 1920,
    height: 1080,
};
const QUICK: vk::Extent2D = vk::Extent2D { width: 160, height: 90 };
/// Environment lookups per pixel of the `sampled` configurations.
const SAMPLED: [u32; 6] = [1, 4, 16, 64, 256, 1024];

/// Every scene and configuration of a full run, or the `--quick` subset.
pub fn scenes(quick: bool) -> Result<Vec<BenchScene>> {
    let default: SceneFile = toml::from_str(DEFAULT_SCENE_TOML).context("the embedded default scene")?;
    if quick {
        return Ok(vec![bench_scene(
            "default",
            &default,
            &[FLOOR, "split-sum", REPORT],
            |_| vec![QUICK],
        )?]);
    }
    let mut studio = default.clone();
    studio.environment = EnvironmentDef::Studio {
        intensity: None,
        rotation_degrees: None,
        reflection: None,
        samples: None,
        seed_strength: None,
    };
    let sampled: Vec<String> = SAMPLED.iter().map(|n| format!("sampled-{n}")).collect();
    let mut names = vec![FLOOR, "split-sum", "seed", REPORT];
    names.extend(sampled.iter().map(String::as_str));
    names.extend(SHADOW_CONFIGURATIONS);
    Ok(vec![
        bench_scene("default", &default, &names, |c| resolutions(c, true))?,
        bench_scene("studio", &studio, &names, |c| resolutions(c, false))?,
    ])
}

/// The sizes configuration `name` is timed at in a full run; the first is its headline.
fn resolutions(name: &str, scaling: bool) -> Vec<vk::Extent2D> {
    match name {
        // Seconds per frame at 1280×720 on lavapipe: 26 s for 1024 lookups.
        "sampled-256" | "sampled-1024" => vec![SMALL],
        // Cost against pixels: argil's defaults at a smaller and a larger size.
        "split-sum" if scaling => vec![HEADLINE, SMALL, LARGE],
        _ => vec![HEADLINE],
    }
}

fn bench_scene(
    name: &'static str,
    file: &SceneFile,
    names: &[&str],
    sizes: impl Fn(&str) -> Vec<vk::Extent2D>,
) -> Result<BenchScene> {
    let mut configurations: Vec<Configuration> = names
        .iter()
        .map(|&c| {
            Ok(Configuration {
                name: c.to_owned(),
                text: configured(file, c)?.to_toml()?,
                floor: c == FLOOR,
                resolutions: sizes(c),
            })
        })
        .collect::<Result<_>>()?;
    // The floor at every size another configuration is timed at, as each ratio needs it.
    let mut floor_sizes: Vec<vk::Extent2D> = Vec::new();
    for size in configurations.iter().flat_map(|c| c.resolutions.iter()) {
        if !floor_sizes.contains(size) {
            floor_sizes.push(*size);
        }
    }
    if let Some(floor) = configurations.iter_mut().find(|c| c.floor) {
        floor.resolutions = floor_sizes;
    }
    Ok(BenchScene {
        name,
        text: file.to_toml()?,
        configurations,
    })
}

/// `file` edited for configuration `name`: `split-sum` and `floor` are argil's defaults,
/// `seed` the report's reflection alone, `report` its reflection, horizon and subsurface
/// on every material, `sampled-N` N importance-sampled lookups.
fn configured(file: &SceneFile, name: &str) -> Result<SceneFile> {
    let mut file = file.clone();
    match name {
        FLOOR | "split-sum" => {}
        "seed" => set_reflection(&mut file.environment, ReflectionMode::Seed, None),
        REPORT => {
            set_reflection(&mut file.environment, ReflectionMode::Seed, None);
            for material in file.materials.values_mut() {
                material.horizon = Horizon::Seed;
                material.subsurface = Subsurface::Seed;
            }
        }
        _ if SHADOW_CONFIGURATIONS.contains(&name) => shadow_configured(&mut file, name),
        _ => {
            let samples = name
                .strip_prefix("sampled-")
                .and_then(|n| n.parse().ok())
                .with_context(|| format!("unknown bench configuration {name:?}"))?;
            set_reflection(&mut file.environment, ReflectionMode::Sampled, Some(samples));
        }
    }
    Ok(file)
}

/// What shadows cost and change: `no-shadows` turns every light's shadows off (the
/// renderer before them), `hard-shadows` makes every light a point (one lookup, no PCSS).
const SHADOW_CONFIGURATIONS: [&str; 2] = ["no-shadows", "hard-shadows"];

fn shadow_configured(file: &mut SceneFile, name: &str) {
    for light in &mut file.lights {
        let crate::scene::file::LightDef::Point { radius, shadows, .. } = light;
        match name {
            "no-shadows" => *shadows = Some(false),
            _ => *radius = None,
        }
    }
}

fn set_reflection(environment: &mut EnvironmentDef, mode: ReflectionMode, lookups: Option<u32>) {
    match environment {
        EnvironmentDef::None => {}
        EnvironmentDef::Uniform {
            reflection, samples, ..
        }
        | EnvironmentDef::Studio {
            reflection, samples, ..
        }
        | EnvironmentDef::Map {
            reflection, samples, ..
        } => {
            *reflection = Some(mode);
            *samples = lookups;
        }
    }
}

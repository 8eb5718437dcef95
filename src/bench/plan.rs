//! What the bench renders: scenes, each as scene-file text, and the configurations of the
//! renderer it times on each, built by editing the scene file.

use std::path::Path;

use anyhow::{Context, Result};
use ash::vk;

use crate::render::Renderer;
use crate::scene::file::{AntialiasingDef, EnvironmentDef, LightDef, MapDef, ObjectDef, SceneFile};
use crate::scene::{
    DiffuseModel, Distribution, Geometry, Horizon, MapSlot, ReflectionMode, SpecularModel, Subsurface,
    DEFAULT_SCENE_TOML,
};
use crate::viewer::responsive::REDUCED_SCALE;

/// The configuration whose name marks the report's composition in the table and plot.
pub const REPORT: &str = "report";
/// The close-up with every property map (roughness, metallic, occlusion, scatter).
const PROPERTY_MAPS: &str = "property-maps";
/// The trivial-shader floor every time is divided by.
pub const FLOOR: &str = "floor";
/// argil's defaults: the scene as written, with the split sum's reflection.
pub const DEFAULTS: &str = "split-sum";
/// argil's defaults through the generic pipeline: what specialising to the frame saves.
pub const GENERIC: &str = "generic";
/// argil's defaults with every object shaded in the forward pass: what shading the solids
/// once a pixel from the G-buffer saves (src/render/deferred.rs).
pub const FORWARD_SHADING: &str = "forward-shading";
/// argil's defaults with the ground's environment light found at each of its pixels: what
/// reading it from the ground's environment map saves (src/render/ground_maps.rs).
pub const GROUND_ENVIRONMENT_PER_PIXEL: &str = "ground-environment-per-pixel";
/// What a configuration moves before every timed frame, as a drag in the viewer moves it:
/// what the shadow maps, the ground's maps and the bounce at the vertices cost when they
/// follow it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Moving {
    /// The first light.
    Light,
    /// The first object that is not the ground.
    Object,
}

/// The configurations that move something (argil's defaults otherwise), and whether each
/// is drawn as the viewer draws while a slow device is in use: at 1/`REDUCED_SCALE` of the
/// headline's size, a draft (`Renderer::draft`).
const MOVING: [(&str, Moving, bool); 4] = [
    ("light-moving", Moving::Light, false),
    ("light-moving-draft", Moving::Light, true),
    ("object-moving", Moving::Object, false),
    ("object-moving-draft", Moving::Object, true),
];

/// One way of rendering a scene.
pub struct Configuration {
    pub name: String,
    /// The scene file of this configuration (the scene's own text with its edits).
    pub text: String,
    /// Drawn with `floor.frag` instead of the materials.
    pub floor: bool,
    /// Drawn with the generic pipelines (see `Renderer::generic`).
    pub generic: bool,
    /// Every object drawn in the forward pass (see `Renderer::deferred`).
    pub forward: bool,
    /// The ground's environment light found at its pixels (see `Renderer::ground_environment`).
    pub ground_environment_per_pixel: bool,
    /// Draws the scene's own meshes, so its floor frames are the scene's floor
    /// (`Floor::pooled`); a tessellation row's are of other meshes.
    pub own_meshes: bool,
    /// What it moves before each of its timed frames.
    pub moving: Option<Moving>,
    /// Drawn as drafts.
    pub draft: bool,
    /// Frame sizes it is timed at; the first is the headline.
    pub resolutions: Vec<vk::Extent2D>,
}

impl Configuration {
    /// Switches `renderer` to this configuration's frames, or to the `floor`, drawn as
    /// drafts where `draft`.
    pub fn switch(&self, renderer: &mut Renderer, floor: bool, draft: bool) {
        renderer.floor = floor;
        renderer.generic = self.generic;
        renderer.deferred = !self.forward;
        renderer.ground_environment = !self.ground_environment_per_pixel;
        renderer.draft = draft;
    }
}

/// A scene with its configurations; its references are of `text`: argil's defaults with
/// every builtin sphere tessellated at [`REFERENCE_SUBDIVISIONS`] and every builtin torus at
/// [`REFERENCE_TORUS_SUBDIVISIONS`], so that one reference serves every tessellation row.
pub struct BenchScene {
    pub name: &'static str,
    pub text: String,
    pub configurations: Vec<Configuration>,
}

impl BenchScene {
    /// The scene with only the configurations one of `patterns` names (all without
    /// patterns): a scene or configuration name, or `SCENE/CONFIGURATION`, where `*`
    /// stands for any run of characters (`occlusion*`, `*/sampled-*`).
    pub fn selected(mut self, patterns: &[String]) -> Self {
        if !patterns.is_empty() {
            let name = self.name;
            self.configurations.retain(|c| patterns.iter().any(|p| pattern_names(p, name, &c.name)));
        }
        self
    }

    /// Whether `pattern` names one of the scene's configurations, as [`Self::selected`]
    /// reads it.
    pub fn has(&self, pattern: &str) -> bool {
        self.configurations.iter().any(|c| pattern_names(pattern, self.name, &c.name))
    }
}

/// Whether `pattern` (see [`BenchScene::selected`]) names `configuration` of `scene`.
fn pattern_names(pattern: &str, scene: &str, configuration: &str) -> bool {
    match pattern.split_once('/') {
        Some((s, c)) => wildcard(s, scene) && wildcard(c, configuration),
        None => wildcard(pattern, scene) || wildcard(pattern, configuration),
    }
}

/// Whether `text` matches `pattern`, in which `*` matches any run of characters.
fn wildcard(pattern: &str, text: &str) -> bool {
    let mut parts = pattern.split('*');
    let first = parts.next().unwrap_or_default();
    let Some(mut rest) = text.strip_prefix(first) else {
        return false;
    };
    let mut parts: Vec<&str> = parts.collect();
    let Some(last) = parts.pop() else {
        return rest.is_empty();
    };
    for part in parts {
        match rest.find(part) {
            Some(at) => rest = &rest[at + part.len()..],
            None => return false,
        }
    }
    rest.ends_with(last)
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
/// The headline frame as the viewer draws it while in use on a slow device.
const VIEWER_REDUCED: vk::Extent2D = vk::Extent2D {
    width: HEADLINE.width / REDUCED_SCALE,
    height: HEADLINE.height / REDUCED_SCALE,
};
pub const QUICK: vk::Extent2D = vk::Extent2D { width: 160, height: 90 };
/// Environment lookups per pixel of the `sampled` configurations.
const SAMPLED: [u32; 6] = [1, 4, 16, 64, 256, 1024];
/// Cells along a cube edge of the builtin spheres of the `sphere-N` configurations
/// (argil's default, 32, is the scenes' own rows).
const SPHERE_SUBDIVISIONS: [u32; 4] = [8, 16, 64, 128];
/// Cells around the ring of the builtin tori of the `torus-N` configurations (argil's
/// default, 128, is the scene's own rows).
const TORUS_SUBDIVISIONS: [u32; 3] = [32, 64, 256];
/// The references' builtin spheres: cells π/512 across at most (1.5 M triangles), whose
/// interpolated normals are within ≈ (π/512)²/8 ≈ 5e-6 rad of the exact sphere's.
pub const REFERENCE_SUBDIVISIONS: u32 = 256;
/// The references' builtin tori: cells 2π/1024 around the ring and about as much around the
/// tube (0.8 M triangles), as close to the exact torus's normals as the spheres'.
pub const REFERENCE_TORUS_SUBDIVISIONS: u32 = 1024;

/// Every scene and configuration of a full run, or the `--quick` subset; `sky` is the
/// equirectangular map of the `sphere-sky` scene, which is left out without one.
pub fn scenes(quick: bool, sky: Option<&Path>) -> Result<Vec<BenchScene>> {
    let default: SceneFile = toml::from_str(DEFAULT_SCENE_TOML).context("the embedded default scene")?;
    if quick {
        return Ok(vec![bench_scene(
            "default",
            &default,
            &[FLOOR, DEFAULTS, REPORT],
            |_| vec![QUICK],
        )?]);
    }
    let names = configuration_names();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    // The default scene is a studio shot, so it is also "the default scene under the studio".
    let mut scenes = vec![bench_scene("default", &default, &names, |c| resolutions(c, true))?];
    let headline = |_: &str| vec![HEADLINE];
    let tessellations: Vec<String> = SPHERE_SUBDIVISIONS.iter().map(|n| format!("sphere-{n}")).collect();
    let sphere = parse(SPHERE_TOML, "bench/scenes/sphere.toml")?;
    for (name, diffuse, specular, distribution) in SPHERES {
        let mut file = sphere.clone();
        let m = file
            .materials
            .get_mut("m")
            .context("bench/scenes/sphere.toml has no material m")?;
        (m.diffuse, m.specular, m.distribution) = (diffuse, specular, distribution);
        m.diffuse_roughness = 0.5;
        let mut configurations = vec![FLOOR, DEFAULTS, "seed", REPORT, "sampled-64"];
        if specular == SpecularModel::CookTorrance {
            configurations.extend([SEPARABLE_G, ENERGY_COMPENSATION]);
        }
        configurations.extend(tessellations.iter().map(String::as_str));
        scenes.push(bench_scene(name, &file, &configurations, headline)?);
    }
    if let Some(sky) = sky {
        scenes.push(bench_scene(
            "sphere-sky",
            &under_sky(&sphere, sky),
            &SKY_CONFIGURATIONS,
            |c| resolutions(c, false),
        )?);
    }
    let close_up = parse(CLOSE_UP_TOML, "bench/scenes/close-up.toml")?;
    let maps = [
        FLOOR,
        DEFAULTS,
        GENERIC,
        "no-maps",
        "maps-off",
        "generic-maps-off",
        PROPERTY_MAPS,
        "seed",
        REPORT,
        "no-antialiasing",
        "msaa-4",
    ];
    scenes.push(bench_scene("close-up", &close_up, &maps, headline)?);
    let ground = parse(BALL_ON_GROUND_TOML, "bench/scenes/ball-on-ground.toml")?;
    let mut ground_names = vec![FLOOR, DEFAULTS, REPORT];
    ground_names.extend(OCCLUSION_CONFIGURATIONS);
    ground_names.extend(BOUNCE_CONFIGURATIONS);
    ground_names.extend(OBJECT_CONFIGURATIONS);
    scenes.push(bench_scene("ball-on-ground", &ground, &ground_names, headline)?);
    let penumbra = parse(PENUMBRA_TOML, "bench/scenes/penumbra.toml")?;
    let mut penumbra_names = vec![FLOOR, DEFAULTS];
    penumbra_names.extend(SHADOW_CONFIGURATIONS);
    scenes.push(bench_scene("penumbra", &penumbra, &penumbra_names, headline)?);
    let fill = [FLOOR, DEFAULTS, "no-ground-shadow-map"];
    scenes.push(bench_scene("penumbra-fill", &with_hard_fill(&penumbra), &fill, headline)?);
    let ball = parse(SUBSURFACE_BALL_TOML, "bench/scenes/subsurface-ball.toml")?;
    let subsurface = [FLOOR, DEFAULTS, "no-subsurface", REPORT];
    scenes.push(bench_scene("subsurface-ball", &ball, &subsurface, headline)?);
    scenes.push(bench_scene(
        "subsurface-ball-small",
        &scaled(&ball, 0.25),
        &subsurface,
        headline,
    )?);
    Ok(scenes)
}

/// The configurations of the default scene in a full run, in order; each is
/// the scene file as [`configured`] edits it (and the floor's and generic's flags).
pub fn configuration_names() -> Vec<String> {
    let base = [
        FLOOR,
        DEFAULTS,
        GENERIC,
        FORWARD_SHADING,
        GROUND_ENVIRONMENT_PER_PIXEL,
        "seed",
        REPORT,
        "no-subsurface",
        "generic-no-subsurface",
        "no-maps",
        "maps-off",
        "generic-maps-off",
        "no-environment",
        "generic-no-environment",
        "no-bounce",
        "generic-no-bounce",
        "no-objects",
        "generic-no-objects",
        "no-ground-map",
        "per-pixel",
    ];
    let mut names: Vec<String> = base.map(str::to_owned).into();
    names.extend(MOVING.iter().map(|(name, ..)| (*name).to_owned()));
    names.extend(SAMPLED.iter().map(|n| format!("sampled-{n}")));
    let others = SHADOW_CONFIGURATIONS
        .iter()
        .chain(&["generic-no-shadows"])
        .chain(&ANTIALIASING_CONFIGURATIONS)
        .chain(&OCCLUSION_CONFIGURATIONS);
    names.extend(others.map(|n| (*n).to_owned()));
    // The ball's and the ring's tessellations: on a software rasteriser each triangle
    // shades whole blocks of pixels, so finer meshes cost shading, not only vertices.
    names.extend(SPHERE_SUBDIVISIONS.iter().map(|n| format!("sphere-{n}")));
    names.extend(TORUS_SUBDIVISIONS.iter().map(|n| format!("torus-{n}")));
    names
}

const SPHERE_TOML: &str = include_str!("../../bench/scenes/sphere.toml");
const CLOSE_UP_TOML: &str = include_str!("../../bench/scenes/close-up.toml");
const BALL_ON_GROUND_TOML: &str = include_str!("../../bench/scenes/ball-on-ground.toml");
const PENUMBRA_TOML: &str = include_str!("../../bench/scenes/penumbra.toml");
const SUBSURFACE_BALL_TOML: &str = include_str!("../../bench/scenes/subsurface-ball.toml");

/// The sphere of each BRDF model, Oren-Nayar and EON at σ = 0.5, the lobes at roughness 0.3.
const SPHERES: [(&str, DiffuseModel, SpecularModel, Distribution); 7] = [
    (
        "sphere-lambert",
        DiffuseModel::Lambert,
        SpecularModel::None,
        Distribution::Ggx,
    ),
    (
        "sphere-oren-nayar",
        DiffuseModel::OrenNayar,
        SpecularModel::None,
        Distribution::Ggx,
    ),
    ("sphere-eon", DiffuseModel::Eon, SpecularModel::None, Distribution::Ggx),
    (
        "sphere-cook-torrance-ggx",
        DiffuseModel::Lambert,
        SpecularModel::CookTorrance,
        Distribution::Ggx,
    ),
    (
        "sphere-cook-torrance-beckmann",
        DiffuseModel::Lambert,
        SpecularModel::CookTorrance,
        Distribution::Beckmann,
    ),
    (
        "sphere-torrance-sparrow",
        DiffuseModel::Lambert,
        SpecularModel::TorranceSparrow,
        Distribution::Ggx,
    ),
    (
        "sphere-blinn-phong",
        DiffuseModel::Lambert,
        SpecularModel::BlinnPhong,
        Distribution::Ggx,
    ),
];

/// The sphere under an equirectangular map: reflection modes, `sampled` counts included,
/// on the map's dynamic range, and the silhouette anti-aliased under split sum and `seed`.
const SKY_CONFIGURATIONS: [&str; 10] = [
    FLOOR,
    DEFAULTS,
    "seed",
    REPORT,
    "msaa-4",
    "seed-msaa-4",
    "sampled-4",
    "sampled-16",
    "sampled-64",
    "sampled-256",
];

/// The BRDF sphere (Cook-Torrance GGX) lit by the map at `sky` alone.
fn under_sky(sphere: &SceneFile, sky: &Path) -> SceneFile {
    let mut file = sphere.clone();
    file.lights.clear();
    file.environment = EnvironmentDef::Map {
        path: sky.to_path_buf(),
        intensity: None,
        rotation_degrees: None,
        reflection: None,
        samples: None,
        seed_strength: None,
    };
    if let Some(m) = file.materials.get_mut("m") {
        m.specular = SpecularModel::CookTorrance;
    }
    file
}

/// Cook-Torrance with the separable Smith G, the approximation of the correlated one.
const SEPARABLE_G: &str = "smith-separable";
/// Every material's specular lobe energy-compensated: its cost is this row against
/// `split-sum`'s (one more table read a pixel).
const ENERGY_COMPENSATION: &str = "energy-compensation";

fn parse(text: &str, origin: &str) -> Result<SceneFile> {
    toml::from_str(text).with_context(|| format!("{origin}: not a scene"))
}

/// `file` with objects, camera and lights scaled by `s` about the origin, and the lights'
/// intensities by s² so that every point receives the light it did.
fn scaled(file: &SceneFile, s: f64) -> SceneFile {
    let mut file = file.clone();
    let scale = |p: &mut [f64; 3]| p.iter_mut().for_each(|x| *x *= s);
    scale(&mut file.camera.position);
    scale(&mut file.camera.target);
    for object in &mut file.objects {
        scale(&mut object.position);
        object.scale *= s;
    }
    for light in &mut file.lights {
        let LightDef::Point {
            position, intensity, ..
        } = light;
        scale(position);
        intensity.iter_mut().for_each(|i| *i *= s * s);
    }
    file
}

/// `file` with a hard fill light from the other side that casts shadows too, and a pebble
/// half-way from it to the ball: the ground reads the soft light's shadow from its map and
/// looks the hard one's up at its pixels, and the ball runs shadow code for the fill
/// light alone, which the pebble may stand before.
fn with_hard_fill(file: &SceneFile) -> SceneFile {
    let mut file = file.clone();
    let fill = [3.5, 3.0, -2.0];
    file.lights.push(LightDef::Point {
        position: fill,
        intensity: [12.0, 12.0, 12.0],
        radius: None,
        shadows: None,
    });
    let ball = file.objects[0].clone();
    file.objects.push(ObjectDef {
        position: [0, 1, 2].map(|k| 0.5 * (fill[k] + ball.position[k])),
        scale: 0.25,
        ..ball
    });
    file
}

/// The sizes configuration `name` is timed at in a full run; the first is its headline.
fn resolutions(name: &str, scaling: bool) -> Vec<vk::Extent2D> {
    match name {
        // Seconds per frame at 1280×720 on lavapipe: 26 s for 1024 lookups.
        "sampled-256" | "sampled-1024" => vec![SMALL],
        // Cost against pixels: argil's defaults, and with the solids shaded forward, at a
        // smaller and a larger size.
        DEFAULTS | FORWARD_SHADING if scaling => vec![HEADLINE, SMALL, LARGE],
        // What moves, also at the size the viewer draws while a slow device is in use, and
        // its drafts at that size alone.
        _ => match moving(name) {
            Some((_, false)) => vec![HEADLINE, VIEWER_REDUCED],
            Some((_, true)) => vec![VIEWER_REDUCED],
            None => vec![HEADLINE],
        },
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
                floor: is_floor(c),
                generic: is_generic(c),
                forward: c == FORWARD_SHADING,
                ground_environment_per_pixel: c == GROUND_ENVIRONMENT_PER_PIXEL,
                own_meshes: tessellated(c).is_none(),
                moving: moving(c).map(|(what, _)| what),
                draft: moving(c).is_some_and(|(_, draft)| draft),
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
    let mut reference = file.clone();
    set_subdivisions(&mut reference, SPHERE, REFERENCE_SUBDIVISIONS);
    set_subdivisions(&mut reference, TORUS, REFERENCE_TORUS_SUBDIVISIONS);
    Ok(BenchScene {
        name,
        text: reference.to_toml()?,
        configurations,
    })
}

/// Whether configuration `name` is drawn with `floor.frag` (see [`Configuration::floor`]).
pub fn is_floor(name: &str) -> bool {
    name == FLOOR
}

/// The builtin meshes whose `subdivisions` the `sphere-N` and `torus-N` configurations set.
const SPHERE: &str = "builtin:sphere";
const TORUS: &str = "builtin:torus";

/// The builtin mesh that configuration `name` retessellates (`sphere-N`, `torus-N`), and
/// the prefix of its rows.
fn tessellated(name: &str) -> Option<(&'static str, &'static str)> {
    [(SPHERE, "sphere-"), (TORUS, "torus-")]
        .into_iter()
        .find(|(_, prefix)| name.starts_with(prefix))
}

/// What configuration `name` moves between frames, and whether it draws drafts (see
/// [`MOVING`]).
pub fn moving(name: &str) -> Option<(Moving, bool)> {
    MOVING.iter().find(|(n, ..)| *n == name).map(|&(_, what, draft)| (what, draft))
}

/// Whether configuration `name` is drawn with the generic pipelines.
pub fn is_generic(name: &str) -> bool {
    name == GENERIC || name.starts_with("generic-")
}

/// `file` edited for configuration `name`: `split-sum`, `floor` and those that move
/// something ([`MOVING`]) are argil's defaults, `seed` the report's reflection alone,
/// `report` its reflection, horizon and subsurface on every material, `sampled-N` N
/// importance-sampled lookups, `no-FEATURE` the scene without subsurface scattering,
/// material maps or environment, `maps-off` every map at strength 0, `smith-separable` the
/// separable G, `energy-compensation` every specular lobe energy-compensated, `sphere-N`
/// builtin spheres of N cells along each cube edge, `torus-N` builtin tori of N cells
/// around the ring, the shadow and anti-aliasing configurations as their constants say;
/// `generic-NAME` is NAME drawn with the generic pipelines, `seed-NAME` an anti-aliasing
/// configuration NAME with `seed` reflection.
pub fn configured(file: &SceneFile, name: &str) -> Result<SceneFile> {
    let mut file = file.clone();
    if let Some(antialiasing) = name.strip_prefix("seed-").filter(|n| ANTIALIASING_CONFIGURATIONS.contains(n)) {
        set_reflection(&mut file.environment, ReflectionMode::Seed, None);
        file.antialiasing = Some(antialiasing_configured(antialiasing));
        return Ok(file);
    }
    let name = name.strip_prefix("generic-").unwrap_or(name);
    match name {
        FLOOR | GENERIC | FORWARD_SHADING | GROUND_ENVIRONMENT_PER_PIXEL | DEFAULTS => {}
        _ if moving(name).is_some() => {}
        "seed" => set_reflection(&mut file.environment, ReflectionMode::Seed, None),
        REPORT => {
            set_reflection(&mut file.environment, ReflectionMode::Seed, None);
            for material in file.materials.values_mut() {
                material.horizon = Horizon::Seed;
                material.subsurface = Subsurface::Seed;
            }
        }
        // A feature absent: what it costs is this row's time against argil's defaults.
        "no-subsurface" => file
            .materials
            .values_mut()
            .for_each(|m| m.subsurface = Subsurface::None),
        "no-maps" => file.materials.values_mut().for_each(|m| {
            // Without the preset, parsing the text back cannot restore the maps.
            m.preset = None;
            for slot in MapSlot::ALL {
                *m.map_mut(slot) = None;
            }
        }),
        "no-environment" => file.environment = EnvironmentDef::None,
        // The default scene's terms of the light between its surfaces, one at a time.
        "no-objects" => file.occlusion.get_or_insert_with(Default::default).objects = Some(false),
        "no-bounce" => file.shadows.get_or_insert_with(Default::default).bounce = Some(false),
        // The objects' occlusion of the ground at every pixel, not from the ground's map.
        "no-ground-map" => file.occlusion.get_or_insert_with(Default::default).ground_map = Some(false),
        // The objects' occlusion of each other at every pixel, not at their vertices.
        "per-pixel" => file.occlusion.get_or_insert_with(Default::default).per_vertex = Some(false),
        // A feature added: every property map, the builtin noise's channels as one packed
        // occlusion-roughness-metallic texture and as the scatter map.
        PROPERTY_MAPS => file.materials.values_mut().for_each(|m| {
            for slot in [
                MapSlot::Roughness,
                MapSlot::Metallic,
                MapSlot::Occlusion,
                MapSlot::Scatter,
            ] {
                *m.map_mut(slot) = Some(MapDef {
                    uv_scale: [2.0, 1.0],
                    ..MapDef::new("builtin:noise")
                });
            }
        }),
        // Present but doing nothing: the documented way to switch off a preset's map.
        "maps-off" => file.materials.values_mut().for_each(|m| {
            for slot in MapSlot::ALL {
                if let Some(map) = m.map_mut(slot) {
                    map.strength = 0.0;
                }
            }
        }),
        SEPARABLE_G => file
            .materials
            .values_mut()
            .for_each(|m| m.geometry = Geometry::SmithSeparable),
        ENERGY_COMPENSATION => file
            .materials
            .values_mut()
            .for_each(|m| m.energy_compensation = true),
        _ if SHADOW_CONFIGURATIONS.contains(&name) => shadow_configured(&mut file, name),
        _ if ANTIALIASING_CONFIGURATIONS.contains(&name) => file.antialiasing = Some(antialiasing_configured(name)),
        _ if OCCLUSION_CONFIGURATIONS.contains(&name) => occlusion_configured(&mut file, name),
        _ if BOUNCE_CONFIGURATIONS.contains(&name) => bounce_configured(&mut file, name),
        _ if OBJECT_CONFIGURATIONS.contains(&name) => objects_configured(&mut file, name),
        _ => {
            let number = |prefix: &str| {
                name.strip_prefix(prefix)
                    .and_then(|n| n.parse().ok())
                    .with_context(|| format!("unknown bench configuration {name:?}"))
            };
            if let Some((mesh, prefix)) = tessellated(name) {
                set_subdivisions(&mut file, mesh, number(prefix)?);
            } else {
                set_reflection(
                    &mut file.environment,
                    ReflectionMode::Sampled,
                    Some(number("sampled-")?),
                );
            }
        }
    }
    Ok(file)
}

/// What shadows cost and change: `no-shadows` turns every light's shadows off (the
/// renderer before them), `hard-shadows` makes every light a point (one lookup, no PCSS),
/// `shadow-taps-N` gives a soft shadow N taps to search and N to filter (argil's 16),
/// `no-ground-shadow-map` searches and filters the ground's shadows at its pixels rather
/// than reading them from its map, `shadows-per-vertex` finds the other objects' soft
/// shadows at their vertices.
const SHADOW_CONFIGURATIONS: [&str; 7] = [
    "no-shadows",
    "hard-shadows",
    "shadow-taps-4",
    "shadow-taps-8",
    "shadow-taps-32",
    "no-ground-shadow-map",
    "shadows-per-vertex",
];

fn shadow_configured(file: &mut SceneFile, name: &str) {
    if let Some(taps) = name.strip_prefix("shadow-taps-").and_then(|n| n.parse().ok()) {
        file.shadows.get_or_insert_with(Default::default).taps = Some(taps);
        return;
    }
    if name == "no-ground-shadow-map" {
        file.shadows.get_or_insert_with(Default::default).ground_map = Some(false);
        return;
    }
    if name == "shadows-per-vertex" {
        file.shadows.get_or_insert_with(Default::default).per_vertex = Some(true);
        return;
    }
    for light in &mut file.lights {
        let crate::scene::file::LightDef::Point { radius, shadows, .. } = light;
        match name {
            "no-shadows" => *shadows = Some(false),
            _ => *radius = None,
        }
    }
}

/// What anti-aliasing costs and changes against argil's defaults (one sample, specular
/// anti-aliasing): `no-antialiasing` is the renderer before it (no specular anti-aliasing
/// either), `msaa-N` N samples per pixel with specular anti-aliasing, `msaa-4-no-specular-aa`
/// multisampling alone. A row whose count the device does not support is skipped.
const ANTIALIASING_CONFIGURATIONS: [&str; 5] =
    ["no-antialiasing", "msaa-2", "msaa-4", "msaa-8", "msaa-4-no-specular-aa"];

fn antialiasing_configured(name: &str) -> AntialiasingDef {
    match name {
        "no-antialiasing" => AntialiasingDef {
            msaa: Some(1),
            specular: Some(false),
        },
        "msaa-4-no-specular-aa" => AntialiasingDef {
            msaa: Some(4),
            specular: Some(false),
        },
        _ => AntialiasingDef {
            msaa: name.strip_prefix("msaa-").and_then(|n| n.parse().ok()),
            specular: None,
        },
    }
}

/// What ambient occlusion costs and changes: `occlusion` its defaults (4 slices × 8 steps,
/// radius 0.5, the multi-bounce fit), `occlusion-plain` without the fit, `occlusion-SxN`
/// S slices × N steps, `occlusion-r1` a radius of 1. The scenes' own rows have none.
const OCCLUSION_CONFIGURATIONS: [&str; 5] = [
    "occlusion",
    "occlusion-plain",
    "occlusion-2x4",
    "occlusion-8x16",
    "occlusion-r1",
];

/// The scene's own `[occlusion]` (so `objects` stays as the scene has it) with GTAO on.
fn occlusion_configured(file: &mut SceneFile, name: &str) {
    let def = file.occlusion.get_or_insert_with(Default::default);
    def.enabled = Some(true);
    match name {
        "occlusion-plain" => def.multi_bounce = Some(false),
        "occlusion-2x4" => (def.slices, def.steps) = (Some(2), Some(4)),
        "occlusion-8x16" => (def.slices, def.steps) = (Some(8), Some(16)),
        "occlusion-r1" => def.radius = Some(1.0),
        _ => {}
    }
}

/// What the light bounced off the ground costs and changes, alone and with occlusion.
const BOUNCE_CONFIGURATIONS: [&str; 2] = ["bounce", "bounce-occlusion"];

fn bounce_configured(file: &mut SceneFile, name: &str) {
    file.shadows.get_or_insert_with(Default::default).bounce = Some(true);
    if name == "bounce-occlusion" {
        occlusion_configured(file, "occlusion");
    }
}

/// What occlusion by the objects as spheres (`[occlusion] objects`) costs and changes:
/// alone, with the ground's bounce, and with GTAO and the bounce as well.
const OBJECT_CONFIGURATIONS: [&str; 3] = ["objects", "objects-bounce", "objects-occlusion-bounce"];

fn objects_configured(file: &mut SceneFile, name: &str) {
    if name != "objects" {
        file.shadows.get_or_insert_with(Default::default).bounce = Some(true);
    }
    if name == "objects-occlusion-bounce" {
        occlusion_configured(file, "occlusion");
    }
    file.occlusion.get_or_insert_with(Default::default).objects = Some(true);
}

fn set_subdivisions(file: &mut SceneFile, mesh: &str, n: u32) {
    for object in &mut file.objects {
        if object.mesh == mesh {
            object.subdivisions = Some(n);
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

#[cfg(test)]
mod tests {
    use super::*;

    fn names(scene: BenchScene) -> Vec<String> {
        scene.configurations.into_iter().map(|c| c.name).collect()
    }

    /// Every tessellation row and its scene's reference draw the scene's one sphere, at
    /// the row's subdivisions and the reference's.
    #[test]
    fn tessellation_rows_vary_the_sphere_and_references_use_the_fine_one() {
        let lambert = scenes(false, None)
            .unwrap()
            .into_iter()
            .find(|s| s.name == "sphere-lambert")
            .unwrap();
        let spheres = |text: &str| {
            let file: SceneFile = toml::from_str(text).unwrap();
            file.objects.iter().map(|o| o.subdivisions).collect::<Vec<_>>()
        };
        assert_eq!(spheres(&lambert.text), [Some(REFERENCE_SUBDIVISIONS)]);
        for n in SPHERE_SUBDIVISIONS {
            let row = lambert.configurations.iter().find(|c| c.name == format!("sphere-{n}"));
            assert_eq!(spheres(&row.unwrap().text), [Some(n)]);
        }
        let own = lambert.configurations.iter().find(|c| c.name == DEFAULTS).unwrap();
        assert_eq!(spheres(&own.text), [None]);
    }

    /// The default scene's torus rows vary its ring alone, and its references draw the
    /// fine sphere and the fine torus.
    #[test]
    fn torus_rows_vary_the_ring_and_references_use_the_fine_one() {
        let default = scenes(false, None).unwrap().remove(0);
        let subdivisions = |text: &str| {
            let file: SceneFile = toml::from_str(text).unwrap();
            file.objects
                .iter()
                .filter(|o| o.mesh == SPHERE || o.mesh == TORUS)
                .map(|o| (o.mesh.clone(), o.subdivisions))
                .collect::<Vec<_>>()
        };
        let both = |sphere, torus| vec![(SPHERE.to_owned(), sphere), (TORUS.to_owned(), torus)];
        let fine = both(Some(REFERENCE_SUBDIVISIONS), Some(REFERENCE_TORUS_SUBDIVISIONS));
        assert_eq!(subdivisions(&default.text), fine);
        for n in TORUS_SUBDIVISIONS {
            let row = default.configurations.iter().find(|c| c.name == format!("torus-{n}")).unwrap();
            assert_eq!(subdivisions(&row.text), both(None, Some(n)));
            assert!(!row.own_meshes);
        }
    }

    #[test]
    fn patterns_select_scenes_configurations_or_both() {
        let default = || scenes(false, None).unwrap().remove(0);
        let all = names(default()).len();
        assert_eq!(names(default().selected(&[])).len(), all);
        assert_eq!(names(default().selected(&["default".into()])).len(), all);
        assert_eq!(names(default().selected(&["studio".into()])), Vec::<String>::new());
        assert_eq!(
            names(default().selected(&["seed".into(), "*/floor".into()])),
            ["floor", "seed"]
        );
        assert_eq!(
            names(default().selected(&["default/report".into(), "studio/seed".into()])),
            ["report"]
        );
        assert_eq!(
            names(default().selected(&["sampled-1*".into()])),
            ["sampled-1", "sampled-16", "sampled-1024"]
        );
        assert_eq!(names(default().selected(&["d*t/*-10*4".into()])), ["sampled-1024"]);
        assert!(default().has("d*t/*-10*4") && default().has("default") && default().has("*/floor"));
        assert!(!default().has("studio") && !default().has("default/studio") && !default().has("studio/seed"));
    }

    #[test]
    fn the_sky_scene_needs_its_map() {
        let named = |sky| scenes(false, sky).unwrap().into_iter().find(|s| s.name == "sphere-sky");
        assert!(named(None).is_none());
        let scene = named(Some(Path::new("bench/references/sky-v1.exr"))).unwrap();
        assert!(scene.text.contains("bench/references/sky-v1.exr"), "{}", scene.text);
        assert!(!scene.text.contains("[[lights]]"));
        // Split sum and seed, each under 4× MSAA: rows whose costs compare alike.
        let row = |name: &str| scene.configurations.iter().find(|c| c.name == name).unwrap();
        let parsed = |name: &str| toml::from_str::<SceneFile>(&row(name).text).unwrap();
        let (seed, msaa, both) = (parsed("seed"), parsed("msaa-4"), parsed("seed-msaa-4"));
        assert_eq!(both.antialiasing, msaa.antialiasing);
        assert!(both.antialiasing.is_some());
        assert_eq!(both.environment, seed.environment);
        assert_ne!(both.environment, msaa.environment);
    }

    /// Each taps row gives the penumbra scene's soft light its count of taps.
    #[test]
    fn shadow_taps_rows_set_a_soft_shadows_taps() {
        let penumbra = scenes(false, None).unwrap().into_iter().find(|s| s.name == "penumbra").unwrap();
        for n in [4, 8, 32] {
            let row = penumbra.configurations.iter().find(|c| c.name == format!("shadow-taps-{n}"));
            let scene = crate::scene::Scene::from_toml(&row.unwrap().text, "row", Path::new("")).unwrap();
            assert_eq!(scene.shadow_taps, n);
            assert!(scene.lights[0].radius > 0.0);
        }
    }

    /// The default scene's `shadows-per-vertex` row, and it alone, takes the soft shadows at
    /// the vertices.
    #[test]
    fn the_per_vertex_row_takes_soft_shadows_at_the_vertices() {
        let default = scenes(false, None).unwrap().into_iter().find(|s| s.name == "default").unwrap();
        for row in &default.configurations {
            let scene = crate::scene::Scene::from_toml(&row.text, "row", Path::new("")).unwrap();
            assert_eq!(scene.shadow_per_vertex, row.name == "shadows-per-vertex", "{}", row.name);
        }
    }

    /// The fill scene's ground reads its soft light's shadow from the map and looks its
    /// hard light's up at its pixels, which `no-ground-shadow-map` does for both; its ball
    /// may be shadowed by the fill light alone.
    #[test]
    fn the_fill_scene_has_soft_and_hard_shadows_on_the_ground() {
        let fill = scenes(false, None).unwrap().into_iter().find(|s| s.name == "penumbra-fill").unwrap();
        let scene = |name: &str| {
            let row = fill.configurations.iter().find(|c| c.name == name).unwrap();
            crate::scene::Scene::from_toml(&row.text, "row", Path::new("")).unwrap()
        };
        let own = scene(DEFAULTS);
        assert!(crate::render::ground_maps::shadow_ground(&own, true).is_some());
        assert!(crate::render::ground_maps::hard_shadows(&own));
        let extents: Vec<_> = own.meshes.iter().map(|m| m.extent()).collect();
        assert_eq!(own.shadowing_lights(0, &[0, 1], |m| extents[m]), 0b10, "the ball: the fill light alone");
        assert!(crate::render::ground_maps::shadow_ground(&scene("no-ground-shadow-map"), true).is_none());
    }

    #[test]
    fn a_star_matches_any_run_of_characters() {
        assert!(wildcard("*", ""));
        assert!(wildcard("occlusion*", "occlusion-2x4"));
        assert!(wildcard("*-maps-*", "generic-maps-off"));
        assert!(!wildcard("a*a", "a"));
        assert!(!wildcard("seed", "seeds"));
        assert!(!wildcard("*seed", "seeds"));
    }
}

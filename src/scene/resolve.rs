//! SceneFile ⇄ Scene: validation and mesh loading in one direction, the
//! saveable file in the other.

use std::collections::{HashMap, HashSet};
use std::fmt::Debug;
use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::antialiasing::{Antialiasing, MSAA_COUNTS};
use super::file::{
    AntialiasingDef, CameraDef, EnvironmentDef, Green, LightDef, MapDef, MaterialDef, ObjectDef, OcclusionDef,
    ShadowsDef,
};
use super::light::{
    Reflection, ReflectionMode, DEFAULT_SHADOW_RESOLUTION, DEFAULT_SHADOW_TAPS, SHADOW_RESOLUTION_RANGE,
    SHADOW_TAPS_RANGE,
};
use super::limits::{check_environment_map, MAX_LIGHTS, MAX_OBJECTS};
use super::material_keys::{limit, MAP_STRENGTH, MAX_UV_SCALE};
use super::{
    builtin_texture, decode_texture, gltf, load_texture, procedural, BuiltinMaps, Camera, Environment, MapRef,
    Material, MaterialMaps, Mesh, Object, Occlusion, PointLight, Scene, SceneError, SceneFile, TextureData,
    TextureRole, BUILTIN_MESHES, BUILTIN_PREFIX, BUILTIN_TEXTURES, OCCLUSION_SAMPLES_RANGE,
};

/// Name of the built-in neutral material, used by objects without a
/// `material` key unless the file defines `[materials.default]` itself.
const DEFAULT_MATERIAL: &str = "default";

/// The camera must be at least this far from its target for a view
/// direction to exist.
const MIN_CAMERA_DISTANCE: f32 = 1e-4;

/// `names` as one of them: "a", "a or b", "a, b or c".
fn alternatives(names: &[impl AsRef<str>]) -> String {
    match names {
        [] => String::new(),
        [one] => one.as_ref().to_owned(),
        [first @ .., last] => {
            let first: Vec<&str> = first.iter().map(AsRef::as_ref).collect();
            format!("{} or {}", first.join(", "), last.as_ref())
        }
    }
}

/// Validates values and narrows them to f32, with errors that name the
/// scene and the offending field. Ranges are checked on the narrowed value,
/// so a number too large for f32 is not finite and one too small for it is
/// zero; errors show the value as written.
struct Checker<'a> {
    origin: &'a str,
}

impl Checker<'_> {
    fn invalid(&self, field: &str, value: impl Debug, reason: impl Into<String>) -> SceneError {
        SceneError::Invalid {
            origin: self.origin.to_owned(),
            field: field.to_owned(),
            value: format!("{value:?}"),
            reason: reason.into(),
        }
    }

    fn integer_in(&self, field: &str, value: u32, range: RangeInclusive<u32>) -> Result<u32, SceneError> {
        if range.contains(&value) {
            Ok(value)
        } else {
            let reason = format!("must be an integer in [{}, {}]", range.start(), range.end());
            Err(self.invalid(field, value, reason))
        }
    }

    fn vector(&self, field: &str, v: [f64; 3]) -> Result<Vec3, SceneError> {
        let narrowed = narrow3(v);
        if narrowed.is_finite() {
            Ok(narrowed)
        } else {
            Err(self.invalid(field, v, "every component must be a finite number"))
        }
    }

    /// A 2-vector whose components are finite and pass `valid`.
    fn vector2(&self, field: &str, v: [f64; 2], valid: impl Fn(f32) -> bool, reason: &str) -> Result<Vec2, SceneError> {
        let narrowed = Vec2::from(v.map(|x| x as f32));
        if narrowed.is_finite() && narrowed.to_array().into_iter().all(valid) {
            Ok(narrowed)
        } else {
            Err(self.invalid(field, v, reason))
        }
    }

    fn color(&self, field: &str, v: [f64; 3]) -> Result<Vec3, SceneError> {
        let narrowed = narrow3(v);
        if narrowed.is_finite() && narrowed.min_element() >= 0.0 {
            Ok(narrowed)
        } else {
            Err(self.invalid(field, v, "every component must be a finite number >= 0"))
        }
    }

    fn non_negative(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        self.scalar(field, x, |x| x.is_finite() && x >= 0.0, "must be a finite number >= 0")
    }

    fn positive(&self, field: &str, x: f64) -> Result<f32, SceneError> {
        self.scalar(field, x, |x| x.is_finite() && x > 0.0, "must be a finite number > 0")
    }

    fn scalar(&self, field: &str, x: f64, valid: impl Fn(f32) -> bool, reason: &str) -> Result<f32, SceneError> {
        let narrowed = x as f32;
        if valid(narrowed) {
            Ok(narrowed)
        } else {
            Err(self.invalid(field, x, reason))
        }
    }
}

fn narrow3(v: [f64; 3]) -> Vec3 {
    Vec3::from(v.map(|x| x as f32))
}

/// The f64 whose shortest decimal form is the f32's, so that saved files
/// read `0.6` rather than `0.6000000238418579`; it narrows back to `x`.
pub(super) fn widen(x: f32) -> f64 {
    x.to_string().parse().unwrap_or(f64::from(x))
}

fn widen3(v: Vec3) -> [f64; 3] {
    v.to_array().map(widen)
}

fn widen2(v: Vec2) -> [f64; 2] {
    v.to_array().map(widen)
}

/// The textures that material maps name, each (texture string, role) once,
/// in order of first use. They load after everything cheap is checked.
#[derive(Default)]
struct TextureRequests {
    indices: HashMap<(String, TextureRole), usize>,
    /// (the first field naming it, texture string, role)
    pending: Vec<(String, String, TextureRole)>,
    /// Images embedded in glTF models, by the texture name their maps give.
    embedded: HashMap<String, Vec<u8>>,
}

impl TextureRequests {
    fn index(&mut self, field: String, texture: &str, role: TextureRole) -> usize {
        let pending = &mut self.pending;
        *self.indices.entry((texture.to_owned(), role)).or_insert_with(|| {
            pending.push((field, texture.to_owned(), role));
            pending.len() - 1
        })
    }
}

pub(super) fn resolve(
    file: &SceneFile,
    origin: &str,
    base_dir: &Path,
    builtin_maps: BuiltinMaps,
) -> Result<Scene, SceneError> {
    let check = Checker { origin };
    if file.lights.len() > MAX_LIGHTS {
        let reason = format!("{} point lights; at most {MAX_LIGHTS} are supported", file.lights.len());
        return Err(check.invalid("lights", file.lights.len(), reason));
    }
    if file.objects.len() > MAX_OBJECTS {
        let reason = format!("{} objects; at most {MAX_OBJECTS} are supported", file.objects.len());
        return Err(check.invalid("objects", file.objects.len(), reason));
    }
    let camera = camera(&check, &file.camera)?;
    let lights = file
        .lights
        .iter()
        .enumerate()
        .map(|(i, light)| match light {
            LightDef::Point {
                position,
                intensity,
                radius,
                shadows,
            } => Ok(PointLight {
                position: check.vector(&format!("lights[{i}].position"), *position)?,
                intensity: check.color(&format!("lights[{i}].intensity"), *intensity)?,
                radius: check.non_negative(&format!("lights[{i}].radius"), radius.unwrap_or(0.0))?,
                shadows: shadows.unwrap_or(true),
            }),
        })
        .collect::<Result<_, _>>()?;
    let shadow_resolution = shadow_resolution(&check, file.shadows.as_ref())?;
    let shadow_taps = shadow_taps(&check, file.shadows.as_ref())?;
    let bounce = file.shadows.as_ref().and_then(|d| d.bounce).unwrap_or(false);
    let shadow_ground_map = file.shadows.as_ref().and_then(|d| d.ground_map).unwrap_or(true);
    let shadow_per_vertex = file.shadows.as_ref().and_then(|d| d.per_vertex).unwrap_or(false);
    let antialiasing = antialiasing(&check, file.antialiasing.as_ref())?;
    let occlusion = occlusion(&check, file.occlusion.as_ref())?;
    let environment = environment(&check, &file.environment, base_dir)?;

    let mut requests = TextureRequests::default();
    let mut materials = file
        .materials
        .iter()
        .map(|(name, def)| material(&check, name, def, &mut requests))
        .collect::<Result<Vec<_>, _>>()?;

    if file.objects.is_empty() {
        return Err(SceneError::NoObjects {
            origin: origin.to_owned(),
        });
    }
    let mut meshes = Vec::new();
    let mut mesh_indices = HashMap::new();
    let mut objects = Vec::with_capacity(file.objects.len());
    let mut warnings = Vec::new();
    let mut inputs: Vec<PathBuf> = match &environment {
        Environment::Map { path, .. } => vec![path.clone()],
        _ => Vec::new(),
    };
    for (i, object) in file.objects.iter().enumerate() {
        let position = check.vector(&format!("objects[{i}].position"), object.position)?;
        let scale = check.positive(&format!("objects[{i}].scale"), object.scale)?;
        let material_name = object.material.as_deref().unwrap_or(DEFAULT_MATERIAL);
        let named = materials.iter().position(|m| m.name == material_name);
        if named.is_none() && material_name != DEFAULT_MATERIAL {
            let defined: Vec<&str> = file.materials.keys().map(String::as_str).collect();
            let defined = if defined.is_empty() {
                "none".to_owned()
            } else {
                defined.join(", ")
            };
            return Err(check.invalid(
                &format!("objects[{i}].material"),
                material_name,
                format!("no [materials.{material_name}] table is defined (defined: {defined})"),
            ));
        }
        // The default count is the builtin itself, so both spellings share one mesh.
        let subdivisions = subdivisions(&check, i, object)?;
        // Meshes load last, so cheap mistakes are reported without waiting
        // for a large OBJ.
        let key = (object.mesh.as_str(), subdivisions);
        let parts = match mesh_indices.get(&key) {
            Some(parts) => Vec::clone(parts),
            None => {
                let field = format!("objects[{i}].mesh");
                let loaded = match subdivisions.and_then(|n| Mesh::subdivided(&object.mesh, n)) {
                    Some(mesh) => Loaded::one(mesh),
                    None => load_mesh(&check, &field, &object.mesh, base_dir, &mut warnings)?,
                };
                requests.embedded.extend(loaded.images);
                inputs.extend(loaded.files);
                let first_material = materials.len();
                for (name, def) in &loaded.materials {
                    materials.push(material(&check, name, def, &mut requests)?);
                }
                let mut parts = Vec::with_capacity(loaded.parts.len());
                for (mesh, model_material) in loaded.parts {
                    parts.push((meshes.len(), model_material.map(|m| first_material + m)));
                    meshes.push(mesh);
                }
                mesh_indices.insert(key, parts.clone());
                parts
            }
        };
        for (part, (mesh, model_material)) in parts.into_iter().enumerate() {
            // A model's parts keep their own materials unless the object names one.
            let (material, material_from_model) = match (object.material.is_none(), model_material) {
                (true, Some(m)) => (m, true),
                _ => match named {
                    Some(m) => (m, false),
                    None => (default_material(&check, &mut materials, &mut requests)?, false),
                },
            };
            objects.push(Object {
                mesh,
                position,
                scale,
                material,
                part,
                material_from_model,
            });
        }
    }
    if objects.len() > MAX_OBJECTS {
        let reason = format!(
            "the models' primitives make {} objects; at most {MAX_OBJECTS} are supported",
            objects.len()
        );
        return Err(check.invalid("objects", file.objects.len(), reason));
    }

    let source = TextureSource {
        base_dir,
        embedded: &requests.embedded,
        builtin_maps,
    };
    // Decoded in parallel (PNG and JPEG decoders use one core each), the first error in
    // the scene's order reported.
    let loaded: Vec<_> = requests
        .pending
        .par_iter()
        .map(|(field, texture, role)| load_map_texture(&check, field, texture, *role, &source))
        .collect();
    let mut textures = Vec::with_capacity(loaded.len());
    for (texture, file) in loaded {
        inputs.extend(file);
        textures.push(texture?);
    }
    let mut seen = HashSet::new();
    inputs.retain(|file| seen.insert(file.clone()));

    Ok(Scene {
        camera,
        lights,
        shadow_resolution,
        shadow_taps,
        bounce,
        shadow_ground_map,
        shadow_per_vertex,
        antialiasing,
        occlusion,
        environment,
        meshes,
        objects,
        materials,
        textures,
        source: None,
        inputs,
        warnings,
    })
}

/// `[shadows]` with the keys that differ from their defaults, or none.
fn shadows_def(scene: &Scene) -> Option<ShadowsDef> {
    let def = ShadowsDef {
        resolution: (scene.shadow_resolution != DEFAULT_SHADOW_RESOLUTION).then_some(scene.shadow_resolution),
        taps: (scene.shadow_taps != DEFAULT_SHADOW_TAPS).then_some(scene.shadow_taps),
        bounce: scene.bounce.then_some(true),
        ground_map: (!scene.shadow_ground_map).then_some(false),
        per_vertex: scene.shadow_per_vertex.then_some(true),
    };
    (def != ShadowsDef::default()).then_some(def)
}

/// Object `i`'s `subdivisions`: `None` without the key or at the mesh's default, else the
/// count, checked to be in the range of a `builtin:sphere` or a `builtin:torus`.
fn subdivisions(check: &Checker, i: usize, object: &ObjectDef) -> Result<Option<u32>, SceneError> {
    let Some(n) = object.subdivisions else {
        return Ok(None);
    };
    let field = format!("objects[{i}].subdivisions");
    let Some((default, range)) = Mesh::subdivisions_key(&object.mesh) else {
        let meshes: Vec<String> = Mesh::subdivided_meshes().iter().map(|n| format!("a {n}")).collect();
        let reason = format!(
            "only {} has subdivisions; this object's mesh is {:?}",
            alternatives(&meshes),
            object.mesh
        );
        return Err(check.invalid(&field, n, reason));
    };
    let n = check.integer_in(&field, n, range)?;
    Ok((n != default).then_some(n))
}

fn shadow_resolution(check: &Checker, def: Option<&ShadowsDef>) -> Result<u32, SceneError> {
    let resolution = def.and_then(|d| d.resolution).unwrap_or(DEFAULT_SHADOW_RESOLUTION);
    check.integer_in("shadows.resolution", resolution, SHADOW_RESOLUTION_RANGE)
}

fn shadow_taps(check: &Checker, def: Option<&ShadowsDef>) -> Result<u32, SceneError> {
    let taps = def.and_then(|d| d.taps).unwrap_or(DEFAULT_SHADOW_TAPS);
    check.integer_in("shadows.taps", taps, SHADOW_TAPS_RANGE)
}

fn antialiasing(check: &Checker, def: Option<&AntialiasingDef>) -> Result<Antialiasing, SceneError> {
    let defaults = Antialiasing::DEFAULT;
    let msaa = def.and_then(|d| d.msaa).unwrap_or(defaults.msaa);
    if !MSAA_COUNTS.contains(&msaa) {
        return Err(check.invalid(
            "antialiasing.msaa",
            msaa,
            format!("must be one of {MSAA_COUNTS:?} (samples per pixel)"),
        ));
    }
    Ok(Antialiasing {
        msaa,
        specular: def.and_then(|d| d.specular).unwrap_or(defaults.specular),
    })
}

fn occlusion(check: &Checker, def: Option<&OcclusionDef>) -> Result<Occlusion, SceneError> {
    let defaults = Occlusion::default();
    let Some(def) = def else { return Ok(defaults) };
    let samples = |field: &str, value: Option<u32>, default: u32| {
        check.integer_in(field, value.unwrap_or(default), OCCLUSION_SAMPLES_RANGE)
    };
    Ok(Occlusion {
        enabled: def.enabled.unwrap_or(defaults.enabled),
        radius: check.positive("occlusion.radius", def.radius.unwrap_or(f64::from(defaults.radius)))?,
        slices: samples("occlusion.slices", def.slices, defaults.slices)?,
        steps: samples("occlusion.steps", def.steps, defaults.steps)?,
        multi_bounce: def.multi_bounce.unwrap_or(defaults.multi_bounce),
        objects: def.objects.unwrap_or(defaults.objects),
        ground_map: def.ground_map.unwrap_or(defaults.ground_map),
        per_vertex: def.per_vertex.unwrap_or(defaults.per_vertex),
    })
}

/// `[occlusion]` as saved: only the keys that differ from the defaults, and no section
/// when none does.
fn occlusion_def(occlusion: &Occlusion) -> Option<OcclusionDef> {
    let defaults = Occlusion::default();
    let def = OcclusionDef {
        enabled: (occlusion.enabled != defaults.enabled).then_some(occlusion.enabled),
        radius: (occlusion.radius != defaults.radius).then(|| widen(occlusion.radius)),
        slices: (occlusion.slices != defaults.slices).then_some(occlusion.slices),
        steps: (occlusion.steps != defaults.steps).then_some(occlusion.steps),
        multi_bounce: (occlusion.multi_bounce != defaults.multi_bounce).then_some(occlusion.multi_bounce),
        objects: (occlusion.objects != defaults.objects).then_some(occlusion.objects),
        ground_map: (occlusion.ground_map != defaults.ground_map).then_some(occlusion.ground_map),
        per_vertex: (occlusion.per_vertex != defaults.per_vertex).then_some(occlusion.per_vertex),
    };
    (def != OcclusionDef::default()).then_some(def)
}

fn camera(check: &Checker, def: &CameraDef) -> Result<Camera, SceneError> {
    let position = check.vector("camera.position", def.position)?;
    let target = check.vector("camera.target", def.target)?;
    let fov_y_degrees = check.scalar(
        "camera.fov_y_degrees",
        def.fov_y_degrees,
        |fov| fov > 0.0 && fov < 180.0,
        "must be a finite number of degrees in (0, 180)",
    )?;
    let distance = position.distance(target);
    if !(distance.is_finite() && distance >= MIN_CAMERA_DISTANCE) {
        return Err(check.invalid(
            "camera.position",
            def.position,
            format!("must differ from camera.target {:?}", def.target),
        ));
    }
    Ok(Camera {
        position,
        target,
        fov_y_degrees,
        near: Camera::NEAR,
        far: Camera::FAR,
    })
}

fn environment(check: &Checker, def: &EnvironmentDef, base_dir: &Path) -> Result<Environment, SceneError> {
    Ok(match def {
        EnvironmentDef::None => Environment::None,
        EnvironmentDef::Uniform {
            radiance,
            reflection,
            samples,
            seed_strength,
        } => Environment::Uniform {
            radiance: check.color("environment.radiance", *radiance)?,
            reflection: check.reflection(*reflection, *samples, *seed_strength)?,
        },
        EnvironmentDef::Studio {
            intensity,
            rotation_degrees,
            reflection,
            samples,
            seed_strength,
        } => Environment::Studio {
            intensity: check.intensity(*intensity)?,
            rotation_degrees: check.rotation(*rotation_degrees)?,
            reflection: check.reflection(*reflection, *samples, *seed_strength)?,
        },
        EnvironmentDef::Map {
            path,
            intensity,
            rotation_degrees,
            reflection,
            samples,
            seed_strength,
        } => {
            let is_image = path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| e.eq_ignore_ascii_case("hdr") || e.eq_ignore_ascii_case("exr"));
            if !is_image {
                return Err(check.invalid(
                    "environment.path",
                    path,
                    "must be an equirectangular .hdr or .exr image",
                ));
            }
            let resolved = base_dir.join(path);
            if !resolved.is_file() {
                return Err(check.invalid(
                    "environment.path",
                    path,
                    format!("no such file: {}", resolved.display()),
                ));
            }
            if let Err(problem) = check_environment_map(&resolved) {
                return Err(check.invalid("environment.path", path, format!("{}: {problem}", resolved.display())));
            }
            Environment::Map {
                path: resolved,
                intensity: check.intensity(*intensity)?,
                rotation_degrees: check.rotation(*rotation_degrees)?,
                reflection: check.reflection(*reflection, *samples, *seed_strength)?,
            }
        }
    })
}

impl Checker<'_> {
    fn intensity(&self, intensity: Option<f64>) -> Result<f32, SceneError> {
        intensity.map_or(Ok(1.0), |x| self.non_negative("environment.intensity", x))
    }

    fn rotation(&self, degrees: Option<f64>) -> Result<f32, SceneError> {
        degrees.map_or(Ok(0.0), |x| {
            self.scalar(
                "environment.rotation_degrees",
                x,
                f32::is_finite,
                "must be a finite number of degrees",
            )
        })
    }

    fn reflection(
        &self,
        mode: Option<ReflectionMode>,
        samples: Option<u32>,
        seed_strength: Option<f64>,
    ) -> Result<Reflection, SceneError> {
        let samples = samples.unwrap_or(Reflection::DEFAULT_SAMPLES);
        if !(1..=Reflection::MAX_SAMPLES).contains(&samples) {
            return Err(self.invalid(
                "environment.samples",
                samples,
                format!("must be an integer in 1..={}", Reflection::MAX_SAMPLES),
            ));
        }
        Ok(Reflection {
            mode: mode.unwrap_or_default(),
            samples,
            seed_strength: seed_strength.map_or(Ok(Reflection::DEFAULT_SEED_STRENGTH), |x| {
                self.non_negative("environment.seed_strength", x)
            })?,
        })
    }
}

/// The keys of a reflection that differ from their defaults, for saving.
fn reflection_def(r: &Reflection) -> (Option<ReflectionMode>, Option<u32>, Option<f64>) {
    let defaults = Reflection::default();
    (
        (r.mode != defaults.mode).then_some(r.mode),
        (r.samples != defaults.samples).then_some(r.samples),
        (r.seed_strength != defaults.seed_strength).then(|| widen(r.seed_strength)),
    )
}

/// `x` for saving, unless it is the default.
fn non_default(x: f32, default: f32) -> Option<f64> {
    (x != default).then(|| widen(x))
}

fn material(
    check: &Checker,
    name: &str,
    def: &MaterialDef,
    textures: &mut TextureRequests,
) -> Result<Material, SceneError> {
    let field = |key: &str| format!("materials.{name}.{key}");
    Material::resolve(
        name,
        def,
        |key, value, reason| check.invalid(&field(key), value, reason),
        || {
            let mut maps = MaterialMaps::default();
            for (slot, map) in maps.iter_mut() {
                let info = slot.info();
                *map = def
                    .map(slot)
                    .as_ref()
                    .map(|def| check_map(check, &field(info.key), def, info.role, textures))
                    .transpose()?;
            }
            Ok(maps)
        },
    )
}

/// Checks one map table (`field` is e.g. `materials.clay.normal_map`) and
/// requests its texture.
fn check_map(
    check: &Checker,
    field: &str,
    def: &MapDef,
    role: TextureRole,
    textures: &mut TextureRequests,
) -> Result<MapRef, SceneError> {
    let key = |key: &str| format!("{field}.{key}");
    let builtins = alternatives(&BUILTIN_TEXTURES);
    if def.texture.is_empty() {
        return Err(check.invalid(
            &key("texture"),
            &def.texture,
            format!("must be an image path (relative to the scene file) or one of {builtins}"),
        ));
    }
    if def.texture.starts_with(BUILTIN_PREFIX) && !BUILTIN_TEXTURES.contains(&def.texture.as_str()) {
        return Err(check.invalid(
            &key("texture"),
            &def.texture,
            format!("unknown builtin texture; expected {builtins}"),
        ));
    }
    let strength = check.scalar(
        &key("strength"),
        def.strength,
        |s| MAP_STRENGTH.contains(s),
        &MAP_STRENGTH.reason(),
    )?;
    let uv_scale = check.vector2(
        &key("uv_scale"),
        def.uv_scale,
        |s| s != 0.0 && s.abs() <= MAX_UV_SCALE,
        &format!(
            "every component must be a finite, non-zero number in [-{0}, {0}]",
            limit(MAX_UV_SCALE)
        ),
    )?;
    let uv_offset = check.vector2(
        &key("uv_offset"),
        def.uv_offset,
        |_| true,
        "every component must be a finite number",
    )?;
    let uv_rotation_degrees = check.scalar(
        &key("uv_rotation_degrees"),
        def.uv_rotation_degrees,
        f32::is_finite,
        "must be a finite number",
    )?;
    let green_down = def.green == Green::Down;
    if green_down && role != TextureRole::Normal {
        return Err(check.invalid(
            &key("green"),
            "down",
            "only normal_map and detail_map have a green direction",
        ));
    }
    Ok(MapRef {
        texture: textures.index(key("texture"), &def.texture, role),
        strength,
        uv_scale,
        uv_offset,
        uv_rotation_degrees,
        green_down,
    })
}

/// Where the textures of maps come from.
struct TextureSource<'a> {
    /// What relative paths are relative to.
    base_dir: &'a Path,
    /// Images embedded in glTF models, by the texture name their maps give.
    embedded: &'a HashMap<String, Vec<u8>>,
    builtin_maps: BuiltinMaps,
}

/// The texture of a map, built in, embedded in a model, or read from a file, which is
/// returned beside it.
fn load_map_texture(
    check: &Checker,
    field: &str,
    texture: &str,
    role: TextureRole,
    source: &TextureSource,
) -> (Result<TextureData, SceneError>, Option<PathBuf>) {
    if texture.starts_with(BUILTIN_PREFIX) {
        let builtin = match source.builtin_maps {
            BuiltinMaps::Now => builtin_texture(texture),
            BuiltinMaps::StandIns => procedural::stand_in(texture),
        };
        // Names were checked with the map; this only avoids an unwrap.
        return (builtin.ok_or_else(|| check.invalid(field, texture, "unknown builtin texture")), None);
    }
    let (loaded, file) = match source.embedded.get(texture) {
        Some(bytes) => (decode_texture(bytes, texture, role), None),
        None => {
            let file = source.base_dir.join(texture);
            (load_texture(&file, role), Some(file))
        }
    };
    let loaded = loaded.map_err(|error| SceneError::MaterialTexture {
        origin: check.origin.to_owned(),
        field: field.to_owned(),
        value: texture.to_owned(),
        error: Box::new(error),
    });
    (loaded, file)
}

/// The index of the built-in `default` material (or the file's `[materials.default]`),
/// added on first use.
fn default_material(
    check: &Checker,
    materials: &mut Vec<Material>,
    requests: &mut TextureRequests,
) -> Result<usize, SceneError> {
    if let Some(index) = materials.iter().position(|m| m.name == DEFAULT_MATERIAL) {
        return Ok(index);
    }
    materials.push(material(check, DEFAULT_MATERIAL, &MaterialDef::default(), requests)?);
    Ok(materials.len() - 1)
}

/// What an object's `mesh` loads: its parts, each with its index in `materials` if it has
/// a material of its own, and those materials (a glTF model's).
struct Loaded {
    parts: Vec<(Mesh, Option<usize>)>,
    materials: Vec<(String, MaterialDef)>,
    /// The model's embedded images the materials name, by texture name.
    images: Vec<(String, Vec<u8>)>,
    /// The files read: the mesh's own and a glTF model's buffer files.
    files: Vec<PathBuf>,
}

impl Loaded {
    fn one(mesh: Mesh) -> Loaded {
        Loaded {
            parts: vec![(mesh, None)],
            materials: Vec::new(),
            images: Vec::new(),
            files: Vec::new(),
        }
    }
}

/// The meshes of an object's `mesh`: one for a builtin or an OBJ file, one per primitive
/// for a glTF model (whose warnings join `warnings`).
fn load_mesh(
    check: &Checker,
    field: &str,
    name: &str,
    base_dir: &Path,
    warnings: &mut Vec<String>,
) -> Result<Loaded, SceneError> {
    if name.starts_with(BUILTIN_PREFIX) {
        let mesh = Mesh::builtin(name).ok_or_else(|| {
            let expected = alternatives(&BUILTIN_MESHES);
            check.invalid(field, name, format!("unknown builtin mesh; expected {expected}"))
        })?;
        return Ok(Loaded::one(mesh));
    }
    let path = base_dir.join(name);
    let loaded = if gltf::is_model(Path::new(name)) {
        gltf::Model::load(&path).map(|model| {
            warnings.extend(model.warnings);
            Loaded {
                parts: model.parts.into_iter().map(|p| (p.mesh, p.material)).collect(),
                materials: model.materials,
                images: model.images,
                files: std::iter::once(path.clone()).chain(model.buffer_files).collect(),
            }
        })
    } else {
        Mesh::load_obj(&path).map(|mesh| Loaded {
            files: vec![path.clone()],
            ..Loaded::one(mesh)
        })
    };
    loaded.map_err(|error| SceneError::ObjectMesh {
        origin: check.origin.to_owned(),
        field: field.to_owned(),
        value: name.to_owned(),
        error: Box::new(error),
    })
}

pub(super) fn to_file(scene: &Scene, file: Option<&Path>) -> SceneFile {
    let folder = file.and_then(Path::parent);
    // A relative path outside the file's folder is relative to the working directory,
    // which the saved file does not know: it is written absolute.
    let relative = |path: &Path| -> PathBuf {
        match folder.map(|folder| path.strip_prefix(folder)) {
            Some(Ok(inside)) => inside.to_path_buf(),
            Some(Err(_)) if path.is_relative() => std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf()),
            _ => path.to_path_buf(),
        }
    };
    // A mesh's or texture's name as the file writes it.
    let written = |name: &str| -> String {
        if name.starts_with(BUILTIN_PREFIX) {
            name.to_owned()
        } else {
            relative(Path::new(name)).to_string_lossy().into_owned()
        }
    };
    let map = |map: &Option<MapRef>| {
        map.map(|m| MapDef {
            texture: written(&scene.textures[m.texture].name),
            strength: widen(m.strength),
            uv_scale: widen2(m.uv_scale),
            uv_offset: widen2(m.uv_offset),
            uv_rotation_degrees: widen(m.uv_rotation_degrees),
            green: if m.green_down { Green::Down } else { Green::Up },
        })
    };
    let camera = &scene.camera;
    SceneFile {
        camera: CameraDef {
            position: widen3(camera.position),
            target: widen3(camera.target),
            fov_y_degrees: widen(camera.fov_y_degrees),
        },
        lights: scene
            .lights
            .iter()
            .map(|light| LightDef::Point {
                position: widen3(light.position),
                intensity: widen3(light.intensity),
                radius: (light.radius > 0.0).then(|| widen(light.radius)),
                shadows: (!light.shadows).then_some(false),
            })
            .collect(),
        shadows: shadows_def(scene),
        antialiasing: antialiasing_def(scene.antialiasing),
        occlusion: occlusion_def(&scene.occlusion),
        environment: environment_def(&scene.environment, relative),
        objects: scene
            .objects
            .iter()
            .filter(|object| object.part == 0)
            .map(|object| ObjectDef {
                mesh: written(&scene.meshes[object.mesh].name),
                position: widen3(object.position),
                scale: widen(object.scale),
                material: (!object.material_from_model).then(|| scene.materials[object.material].name.clone()),
                subdivisions: {
                    let mesh = &scene.meshes[object.mesh];
                    let default = Mesh::subdivisions_key(&mesh.name).map(|(n, _)| n);
                    mesh.subdivisions.filter(|&n| Some(n) != default)
                },
            })
            .collect(),
        // A model's own materials come from the model when the file loads again.
        materials: scene
            .materials
            .iter()
            .enumerate()
            .filter(|&(i, _)| {
                let users = || scene.objects.iter().filter(|o| o.material == i);
                !(users().any(|o| o.material_from_model) && users().all(|o| o.material_from_model))
            })
            .map(|(_, m)| {
                let def = m.to_def(map);
                (m.name.clone(), def)
            })
            .collect(),
    }
}

/// `[antialiasing]` with only the keys that differ from the defaults; none when all do not.
fn antialiasing_def(a: Antialiasing) -> Option<AntialiasingDef> {
    let defaults = Antialiasing::DEFAULT;
    (a != defaults).then(|| AntialiasingDef {
        msaa: (a.msaa != defaults.msaa).then_some(a.msaa),
        specular: (a.specular != defaults.specular).then_some(a.specular),
    })
}

fn environment_def(environment: &Environment, relative: impl Fn(&Path) -> PathBuf) -> EnvironmentDef {
    match environment {
        Environment::None => EnvironmentDef::None,
        Environment::Uniform { radiance, reflection } => {
            let (reflection, samples, seed_strength) = reflection_def(reflection);
            EnvironmentDef::Uniform {
                radiance: widen3(*radiance),
                reflection,
                samples,
                seed_strength,
            }
        }
        Environment::Studio {
            intensity,
            rotation_degrees,
            reflection,
        } => {
            let (reflection, samples, seed_strength) = reflection_def(reflection);
            EnvironmentDef::Studio {
                intensity: non_default(*intensity, 1.0),
                rotation_degrees: non_default(*rotation_degrees, 0.0),
                reflection,
                samples,
                seed_strength,
            }
        }
        Environment::Map {
            path,
            intensity,
            rotation_degrees,
            reflection,
        } => {
            let (reflection, samples, seed_strength) = reflection_def(reflection);
            EnvironmentDef::Map {
                path: relative(path),
                intensity: non_default(*intensity, 1.0),
                rotation_degrees: non_default(*rotation_degrees, 0.0),
                reflection,
                samples,
                seed_strength,
            }
        }
    }
}

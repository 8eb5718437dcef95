//! The references the bench measures error against, rendered once per scene, size and
//! settings and cached as EXRs named by a hash of all three.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};

use crate::atomic::Existing;
use crate::cache::fnv1a;
use crate::compare::input::read_exr;
use crate::compare::metrics::Rgba32;
use crate::reference::{Filter, Sampling, Settings, Stop, SubsurfaceTransport, Transport};
use crate::render::output::write_linear;
use crate::scene::file::{EnvironmentDef, LightDef, MaterialDef, SceneFile};
use crate::scene::{builtin_texture, Mesh, Scene, BUILTIN_PREFIX};

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
        max_time: None,
    }
}

/// `dir/NAME-TRANSPORT-HASH.exr`, the hash over the scene as the reference sees it
/// ([`key_text`]) and the settings (which hold the size); a change of either names another
/// file.
pub fn path(dir: &Path, name: &str, text: &str, settings: &Settings) -> Result<PathBuf> {
    let key = format!("{}\n{}", key_text(text)?, settings_key(settings));
    Ok(dir.join(format!(
        "{name}-{}-{:016x}.exr",
        settings.transport,
        fnv1a(key.as_bytes())
    )))
}

/// `settings` as a reference's name hashes them, in the form of their derived `Debug` when
/// the committed references were named, which they keep. Every field is named: one added
/// to `Settings` must be added here (renaming the references) or left out as `_` if it
/// leaves the image as it was.
fn settings_key(settings: &Settings) -> String {
    let Settings {
        width,
        height,
        transport,
        filter,
        sampling,
        subsurface,
        stop,
        seed,
        max_depth,
        max_time,
    } = settings;
    format!(
        "Settings {{ width: {width}, height: {height}, transport: {transport:?}, filter: {filter:?}, sampling: \
         {sampling:?}, subsurface: {subsurface:?}, stop: {stop:?}, seed: {seed}, max_depth: {max_depth}, max_time: \
         {max_time:?} }}"
    )
}

/// The scene file `text` with only what `argil reference` reads of it, so that a reference
/// is keyed by its image. Left out:
/// - what only the rasterizer reads, the approximations the reference measures: `[shadows]`
///   (map resolution, bounce), `[antialiasing]`, `[occlusion]`, a light's `shadows` switch
///   (the reference always shadows), and the environment's `reflection`, `samples` and
///   `seed_strength`;
/// - material keys at their defaults, so that a new key, whose default keeps the material
///   as it was, renames no reference. The price: a change of a default must rename the
///   references of the scenes that rely on it.
///
/// The files it names (the environment's map, meshes, map textures; relative to the
/// working directory, as the bench loads them) and the builtin meshes and maps are keyed by
/// their content ([`content_key`]), not their names: a reference follows an edited file or
/// builtin, and keeps its name wherever the files sit.
pub fn key_text(text: &str) -> Result<String> {
    let mut file: SceneFile = toml::from_str(text).context("a bench reference's scene")?;
    if let EnvironmentDef::Map { path, .. } = &mut file.environment {
        *path = content_key(&path.to_string_lossy())?.into();
    }
    for object in &mut file.objects {
        object.mesh = content_key(&object.mesh)?;
    }
    file.shadows = None;
    file.antialiasing = None;
    file.occlusion = None;
    for light in &mut file.lights {
        let LightDef::Point { shadows, .. } = light;
        *shadows = None;
    }
    if let Some((reflection, samples, seed_strength)) = file.environment.reflection_keys_mut() {
        (*reflection, *samples, *seed_strength) = (None, None, None);
    }
    let defaults = toml::Table::try_from(MaterialDef::default()).context("the default material")?;
    let mut value = toml::Table::try_from(&file).context("a bench reference's scene")?;
    if let Some(toml::Value::Table(materials)) = value.get_mut("materials") {
        for (_, material) in materials.iter_mut() {
            if let toml::Value::Table(keys) = material {
                keys.retain(|key, v| defaults.get(key) != Some(v));
                for (_, map) in keys.iter_mut() {
                    if let Some(toml::Value::String(texture)) = map.get_mut("texture") {
                        *texture = content_key(texture.as_str())?;
                    }
                }
            }
        }
    }
    Ok(toml::to_string(&value)?)
}

/// A builtin mesh as `mesh-HASH`, the hash over its vertices and triangles at its default
/// tessellation (a `subdivisions` key stays in the text, and the same code makes every
/// tessellation); an image file or a builtin map (a preset's too: the text holds its merged
/// maps) as `image-HASH`, the hash over its size and texels, so that one encoded again (the
/// bench's generated sky, written by another EXR writer) keeps its references; any other
/// file as `file-HASH`, the hash over its bytes. A change to how a builtin is made thus
/// names new references, as an edited file does.
fn content_key(name: &str) -> Result<String> {
    if let Some(mesh) = Mesh::builtin(name) {
        let triangles: &[u8] = bytemuck::cast_slice(&mesh.indices);
        let vertices: &[u8] = bytemuck::cast_slice(&mesh.vertices);
        return Ok(format!("mesh-{:016x}", fnv1a(&[vertices, triangles].concat())));
    }
    if let Some(map) = builtin_texture(name) {
        let size = [map.width, map.height].map(u32::to_le_bytes).concat();
        return Ok(format!("image-{:016x}", fnv1a(&[size.as_slice(), &map.pixels].concat())));
    }
    if name.starts_with(BUILTIN_PREFIX) {
        bail!("{name}: no builtin mesh or map has this name");
    }
    let cannot = || format!("cannot read {name}, which a bench scene names");
    let extension = Path::new(name).extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if matches!(extension.as_deref(), Some("png" | "jpg" | "jpeg" | "hdr" | "exr")) {
        let image = image::ImageReader::open(name)
            .with_context(cannot)?
            .with_guessed_format()
            .with_context(cannot)?
            .decode()
            .with_context(cannot)?
            .into_rgba32f();
        let size = [image.width(), image.height()].map(u32::to_le_bytes).concat();
        let texels: &[u8] = bytemuck::cast_slice(image.as_raw());
        return Ok(format!("image-{:016x}", fnv1a(&[size.as_slice(), texels].concat())));
    }
    let bytes = std::fs::read(name).with_context(cannot)?;
    Ok(format!("file-{:016x}", fnv1a(&bytes)))
}

/// The cached reference of the scene `text`, rendered and written first if it is not cached.
pub fn get(dir: &Path, name: &str, text: &str, settings: &Settings) -> Result<CachedReference> {
    let path = path(dir, name, text, settings)?;
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
            Existing::Replace,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::ReflectionMode;
    use crate::scene::DEFAULT_SCENE_TOML;

    /// The default scene with every key [`key_text`] leaves out set away from its value.
    fn rasterizer_edited(text: &str) -> String {
        let mut file: SceneFile = toml::from_str(text).unwrap();
        file.shadows = Some(toml::from_str("resolution = 64\nbounce = true").unwrap());
        file.antialiasing = Some(toml::from_str("msaa = 4\nspecular = false").unwrap());
        file.occlusion = Some(toml::from_str("enabled = false\nradius = 2.0").unwrap());
        for light in &mut file.lights {
            let LightDef::Point { shadows, .. } = light;
            *shadows = Some(false);
        }
        let (reflection, samples, seed_strength) = file.environment.reflection_keys_mut().unwrap();
        (*reflection, *samples, *seed_strength) = (Some(ReflectionMode::Seed), Some(8), Some(0.5));
        file.to_toml().unwrap()
    }

    #[test]
    fn what_the_key_leaves_out_does_not_change_the_reference() {
        let edited = rasterizer_edited(DEFAULT_SCENE_TOML);
        assert_ne!(edited, DEFAULT_SCENE_TOML);
        assert_eq!(key_text(&edited).unwrap(), key_text(DEFAULT_SCENE_TOML).unwrap());
        let settings = settings(24, 14, Transport::Full, Stop::Samples(2));
        let render = |text: &str| {
            let scene = Scene::from_toml(text, "default", Path::new("")).unwrap();
            crate::reference::render(&scene, &settings, &()).unwrap().rgba
        };
        assert!(render(DEFAULT_SCENE_TOML) == render(&edited), "the reference read a key its cache key leaves out");
    }

    /// The sky's key is its bytes': the same file anywhere names the same reference, and an
    /// edited file another one.
    #[test]
    fn a_file_is_keyed_by_its_content() {
        let dir = crate::scratch::Scratch::new("reference-key").unwrap();
        let sky = crate::bench::sky::ensure(&dir).unwrap();
        let copy = dir.join("elsewhere.exr");
        std::fs::copy(&sky, &copy).unwrap();
        let scene = |map: &Path| {
            let mut file: SceneFile = toml::from_str(DEFAULT_SCENE_TOML).unwrap();
            file.environment = toml::from_str(&format!("kind = \"map\"\npath = {:?}", map.to_str().unwrap())).unwrap();
            key_text(&file.to_toml().unwrap()).unwrap()
        };
        assert_eq!(scene(&sky), scene(&copy));
        assert!(!scene(&sky).contains("elsewhere"));
        let textured = |map: &Path| {
            let path = format!("{:?}", map.to_str().unwrap());
            key_text(&format!("{DEFAULT_SCENE_TOML}\n[materials.ground.base_color_map]\ntexture = {path}\n")).unwrap()
        };
        assert_eq!(textured(&sky), textured(&copy));
        assert!(!textured(&sky).contains("elsewhere"));
        // The same texels encoded otherwise (uncompressed, by the `image` crate) keep the key;
        // one texel changed does not.
        let mut texels = image::open(&sky).unwrap().into_rgba32f();
        texels.save(&copy).unwrap();
        assert_ne!(std::fs::read(&sky).unwrap(), std::fs::read(&copy).unwrap());
        assert_eq!(scene(&sky), scene(&copy));
        texels.get_pixel_mut(7, 5).0[1] += 0.5;
        texels.save(&copy).unwrap();
        assert_ne!(scene(&sky), scene(&copy));
        assert!(key_text(&DEFAULT_SCENE_TOML.replace("builtin:torus", "missing.obj")).is_err());
    }

    /// Builtin meshes and maps are keyed by what they are, as files are: a change to how one
    /// is made names other references.
    #[test]
    fn builtins_are_keyed_by_their_content() {
        let mapped = format!("{DEFAULT_SCENE_TOML}\n[materials.ground.normal_map]\ntexture = \"builtin:clay-lumps\"\n");
        let key = key_text(&mapped).unwrap();
        assert!(mapped.contains("builtin:torus") && mapped.contains("builtin:clay-lumps"));
        assert!(!key.contains(BUILTIN_PREFIX), "{key}");
        let sphere = content_key("builtin:sphere").unwrap();
        assert!(sphere.starts_with("mesh-") && sphere != content_key("builtin:torus").unwrap());
        assert!(key.contains(&content_key("builtin:clay-lumps").unwrap()));
        assert!(content_key("builtin:clay-lumps").unwrap().starts_with("image-"));
        let unknown = content_key("builtin:teapot").unwrap_err().to_string();
        assert!(unknown.contains("builtin:teapot"), "{unknown}");
    }

    /// A key added to the materials comes with a default that keeps them as they were;
    /// the scenes' references must keep their names.
    #[test]
    fn a_material_key_at_its_default_is_not_in_the_key() {
        let mut file: SceneFile = toml::from_str(DEFAULT_SCENE_TOML).unwrap();
        let key = |file: &SceneFile| key_text(&file.to_toml().unwrap()).unwrap();
        let defaults = MaterialDef::default();
        assert!(file.materials.values().all(|m| m.metallic == defaults.metallic));
        assert!(file.to_toml().unwrap().contains("metallic"));
        let written = key(&file);
        assert!(!written.contains("metallic"), "{written}");
        fn first(file: &mut SceneFile) -> &mut MaterialDef {
            file.materials.values_mut().next().unwrap()
        }
        first(&mut file).metallic = 0.5;
        assert!(key(&file).contains("metallic = 0.5"));
        first(&mut file).metallic = defaults.metallic;
        assert_eq!(key(&file), written);
        first(&mut file).roughness += 0.125;
        assert_ne!(key(&file), written);
        let mut file: SceneFile = toml::from_str(DEFAULT_SCENE_TOML).unwrap();
        file.camera.fov_y_degrees += 1.0;
        assert_ne!(key(&file), written);
    }
}


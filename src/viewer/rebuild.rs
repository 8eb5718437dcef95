//! Edits that change what the scene loads (a preset's maps, a texture, an environment map,
//! a mesh): made on the scene as a file and resolved again, with the same checks as a
//! scene file the viewer opens, so that a bad file is an error naming it and the scene on
//! screen stays.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use super::Viewable;
use crate::scene::file::{EnvironmentDef, MapDef, MaterialDef, ObjectDef, SceneFile};
use crate::scene::{MapSlot, Preset, Scene};

/// A file-level edit the panel asks for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Rebuild {
    /// Give `material` this preset's values (`None`: the built-in defaults).
    Preset { material: String, preset: Option<Preset> },
    /// Use an image as a map (`normal_map`, …) of `material`.
    Texture {
        material: String,
        map: &'static str,
        path: String,
    },
    /// Light the scene with an equirectangular image.
    EnvironmentMap { path: String },
    /// Add an OBJ mesh at the origin with `material`.
    Mesh { material: String, path: String },
    /// Read every file the scene names again (one changed on disk).
    ReadAgain,
}

/// A path typed in the panel, relative to the working directory, as the file will hold it.
fn typed(path: &str) -> Result<String> {
    let path = Path::new(path.trim());
    let absolute: PathBuf = std::path::absolute(path).with_context(|| format!("{}: not a path", path.display()))?;
    Ok(absolute.to_string_lossy().into_owned())
}

/// `scene` with `edit` made, resolved and checked as the viewer checks a file it opens.
pub fn rebuild(scene: &Scene, edit: &Rebuild) -> Result<Viewable> {
    let mut file: SceneFile = scene.to_file();
    match edit {
        Rebuild::Preset { material: name, preset } => {
            let mut def = preset.map_or_else(MaterialDef::default, Preset::material);
            def.preset = *preset;
            file.materials.insert(name.clone(), def);
        }
        Rebuild::Texture {
            material: name,
            map,
            path,
        } => {
            let def = file
                .materials
                .get_mut(name)
                .with_context(|| format!("no material {name}"))?;
            let slot = def.map_mut(MapSlot::from_key(map).with_context(|| format!("no map {map}"))?);
            let texture = typed(path)?;
            *slot = Some(match slot.take() {
                Some(old) => MapDef { texture, ..old },
                None => MapDef::new(texture),
            });
        }
        Rebuild::EnvironmentMap { path } => {
            let (reflection, samples, seed_strength) = file
                .environment
                .reflection_keys_mut()
                .map(|(reflection, samples, seed_strength)| (*reflection, *samples, *seed_strength))
                .unwrap_or_default();
            file.environment = EnvironmentDef::Map {
                path: typed(path)?.into(),
                intensity: None,
                rotation_degrees: None,
                reflection,
                samples,
                seed_strength,
            };
        }
        Rebuild::Mesh { material, path } => file.objects.push(ObjectDef {
            mesh: typed(path)?,
            position: [0.0; 3],
            scale: 1.0,
            material: Some(material.clone()),
            subdivisions: None,
        }),
        Rebuild::ReadAgain => {}
    }
    let base_dir = scene.folder();
    let origin = scene
        .source
        .as_deref()
        .map_or_else(|| "the default scene".to_owned(), |p| p.display().to_string());
    let mut rebuilt = Scene::from_file(&file, &origin, base_dir)?;
    rebuilt.source = scene.source.clone();
    rebuilt.camera = scene.camera;
    Viewable::check(rebuilt)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_preset_brings_its_maps_and_a_bad_file_is_an_error_naming_it() {
        let scene = Scene::default_scene();
        let ring = scene.materials.iter().position(|m| m.name == "terracotta").unwrap();
        assert!(scene.materials[ring].maps[MapSlot::Detail].is_none());
        let edit = Rebuild::Preset {
            material: "terracotta".into(),
            preset: Some(Preset::Plasticine),
        };
        let rebuilt = rebuild(&scene, &edit).unwrap().scene;
        let m = &rebuilt.materials[ring];
        assert_eq!((m.preset, m.roughness), (Some(Preset::Plasticine), 0.6));
        assert!(
            m.maps[MapSlot::Detail].is_some(),
            "the plasticine's fingerprints come with it"
        );
        assert_eq!(rebuilt.camera, scene.camera);

        let dir = std::env::temp_dir().join(format!("argil-rebuild-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let bad = dir.join("not-an-image.png");
        std::fs::write(&bad, "text").unwrap();
        let edit = Rebuild::Texture {
            material: "terracotta".into(),
            map: "normal_map",
            path: bad.display().to_string(),
        };
        let error = format!("{:#}", rebuild(&scene, &edit).err().expect("an error"));
        assert!(error.contains("not-an-image.png"), "{error}");

        let obj = dir.join("tri.obj");
        std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
        let edit = Rebuild::Mesh {
            material: "ground".into(),
            path: obj.display().to_string(),
        };
        let rebuilt = rebuild(&scene, &edit).unwrap().scene;
        assert_eq!(rebuilt.objects.len(), scene.objects.len() + 1);
        let error = format!(
            "{:#}",
            rebuild(
                &scene,
                &Rebuild::EnvironmentMap {
                    path: bad.display().to_string()
                }
            )
            .err().expect("an error")
        );
        assert!(error.contains("not-an-image.png"), "{error}");
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A texture and a map rewritten on disk are read again, with the scene's edits kept;
    /// one that no longer loads is an error naming it.
    #[test]
    fn reading_again_takes_in_rewritten_files_and_keeps_the_edits() {
        let dir = crate::scene::tests::TempDir::new();
        let texture = dir.0.join("colour.png");
        let colour = |rgb| image::RgbImage::from_pixel(2, 2, image::Rgb(rgb)).save(&texture).unwrap();
        colour([255, 0, 0]);
        let map = dir.0.join("sky.hdr");
        let sky = |radiance| {
            image::Rgb32FImage::from_pixel(16, 8, image::Rgb([radiance; 3]))
                .save(&map)
                .unwrap()
        };
        sky(1.0);
        let path = dir.write(
            "scene.toml",
            "[environment]\nkind = \"map\"\npath = \"sky.hdr\"\n\n[[objects]]\nmesh = \"builtin:sphere\"\n\
             material = \"clay\"\n\n[materials.clay.base_color_map]\ntexture = \"colour.png\"\n",
        );
        let (Viewable { mut scene, map: decoded, .. }, _) = super::super::load_document(&path).unwrap();
        assert_eq!(decoded.unwrap().texels[0][0], 1.0);
        assert_eq!(scene.inputs, [map.clone(), texture.clone()], "the files to watch");
        scene.materials[0].roughness = 0.33;

        colour([0, 255, 0]);
        sky(0.5);
        let again = rebuild(&scene, &Rebuild::ReadAgain).unwrap();
        assert_eq!(again.scene.materials[0].roughness, 0.33, "the edit is kept");
        assert_eq!(&again.scene.textures[0].pixels[..4], &[0, 255, 0, 255]);
        assert_eq!(again.map.unwrap().texels[0][0], 0.5);

        std::fs::write(&texture, "text").unwrap();
        let error = format!("{:#}", rebuild(&scene, &Rebuild::ReadAgain).err().expect("an error"));
        assert!(error.contains("colour.png"), "{error}");
    }
}

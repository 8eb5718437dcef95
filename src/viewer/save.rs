//! Saving without losing what the user wrote. The scene is written into the text it was
//! read from (comments, order and `preset` lines kept, see `Scene::edit_document`), whole
//! or not at all (`crate::atomic`). Save refuses to write over its own file when that file
//! no longer holds what the viewer read (a hand edit, broken or not), and over any other
//! file unless asked to.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use crate::atomic::Existing;
use crate::scene::{Scene, DEFAULT_SCENE_TOML};

/// The scene file the viewer shows, as it was read.
#[derive(Clone, Debug, PartialEq)]
pub struct Document {
    /// The file, or `None` for the embedded default scene.
    pub path: Option<PathBuf>,
    /// The text the shown scene was read from, or last written by Save.
    pub text: String,
}

impl Document {
    /// The embedded default scene, which has no file.
    pub fn default_scene() -> Document {
        Document {
            path: None,
            text: DEFAULT_SCENE_TOML.to_owned(),
        }
    }

    /// Reads a scene file's text.
    pub fn read(path: &Path) -> Result<Document> {
        Ok(Document {
            // The file the user named: not readable is bad input (exit code 2), as Scene::load has it.
            text: std::fs::read_to_string(path).map_err(|error| crate::scene::SceneError::Io {
                path: path.to_path_buf(),
                error,
            })?,
            path: Some(path.to_path_buf()),
        })
    }
}

/// Why Save wrote nothing.
#[derive(Debug, thiserror::Error)]
pub enum Refused {
    #[error(
        "not saved: {} does not load as it is on disk ({reason}), and saving would overwrite \
         what was written in it; fix the file, or use Save As",
        path.display()
    )]
    Broken { path: PathBuf, reason: String },
    #[error(
        "not saved: {} changed on disk since the viewer read it; read it again (losing the \
         changes not saved), or use Save As",
        path.display()
    )]
    Changed { path: PathBuf },
    /// Another file is in the way: the viewer asks before overwriting it.
    #[error("{} already exists", path.display())]
    Exists { path: PathBuf },
}

/// What Save wrote.
#[derive(Debug)]
pub struct Saved {
    /// Where, absolute, for the notice.
    pub path: PathBuf,
    /// The document now on disk.
    pub document: Document,
}

/// Writes `scene`, shown from `document`, to `to`. `overwrite` allows replacing a file
/// other than the document's own (the user confirmed it).
pub fn save(scene: &Scene, document: &Document, to: &Path, overwrite: bool) -> Result<Saved> {
    let absolute = std::path::absolute(to).with_context(|| format!("{}: no such folder", to.display()))?;
    let own = document
        .path
        .as_deref()
        .and_then(|p| std::path::absolute(p).ok())
        .is_some_and(|p| p == absolute);
    let on_disk = match std::fs::read_to_string(to) {
        Ok(text) => Some(text),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(e).with_context(|| format!("{}: cannot read", to.display())),
    };
    match &on_disk {
        Some(text) if own && *text != document.text => {
            return Err(match super::load_scene(to) {
                Err(e) => Refused::Broken {
                    path: absolute,
                    reason: format!("{e:#}"),
                },
                Ok(_) => Refused::Changed { path: absolute },
            }
            .into());
        }
        Some(_) if !own && !overwrite => return Err(Refused::Exists { path: absolute }.into()),
        _ => {}
    }
    let text = scene.edit_document(&document.text, to)?;
    crate::atomic::write_bytes(to, Existing::Replace, text.as_bytes())?;
    Ok(Saved {
        path: absolute,
        document: Document {
            path: Some(to.to_path_buf()),
            text,
        },
    })
}

/// Writes `scene`, shown from `document`, into a file of its own when the viewer must stop
/// with changes not saved: `NAME.recovered.toml` beside the document's file (the default
/// scene's `argil-scene.toml` in the working folder), or `NAME.recovered-2.toml` and so on
/// where that exists, so that no file is written over; in the temporary folder where the
/// document's folder refuses it. Returns where, absolute.
pub fn recover(scene: &Scene, document: &Document) -> Result<PathBuf> {
    let own = document.path.clone().unwrap_or_else(|| PathBuf::from(super::DEFAULT_SAVE_PATH));
    let stem = own.file_stem().map_or_else(|| "argil-scene".into(), |s| s.to_string_lossy());
    let beside = own.parent().map_or_else(PathBuf::new, Path::to_path_buf);
    let mut failure = None;
    for folder in [beside, std::env::temp_dir()] {
        let Some(to) = (1..=1000)
            .map(|k| match k {
                1 => folder.join(format!("{stem}.recovered.toml")),
                k => folder.join(format!("{stem}.recovered-{k}.toml")),
            })
            .find(|p| p.symlink_metadata().is_err())
        else {
            continue;
        };
        let text = scene.edit_document(&document.text, &to)?;
        match crate::atomic::write_bytes(&to, Existing::Refuse, text.as_bytes()) {
            Ok(()) => return Ok(std::path::absolute(&to).unwrap_or(to)),
            Err(e) => failure = Some(e),
        }
    }
    Err(failure.unwrap_or_else(|| anyhow::anyhow!("every name for a recovered {stem} is taken")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Environment, MapSlot, PointLight, Reflection};
    use glam::{Vec2, Vec3};

    use crate::scene::tests::TempDir as Folder;

    fn load(path: &Path) -> (Scene, Document) {
        let (viewable, document) = super::super::load_document(path).unwrap();
        (viewable.scene, document)
    }

    fn material<'a>(scene: &'a mut Scene, name: &str) -> &'a mut crate::scene::Material {
        scene.materials.iter_mut().find(|m| m.name == name).unwrap()
    }

    /// The lines of `after` that are not in `before`, and the other way round.
    fn changed_lines(before: &str, after: &str) -> (Vec<String>, Vec<String>) {
        let added = after
            .lines()
            .filter(|l| !before.lines().any(|b| b == *l))
            .map(str::to_owned)
            .collect();
        let removed = before
            .lines()
            .filter(|l| !after.lines().any(|a| a == *l))
            .map(str::to_owned)
            .collect();
        (added, removed)
    }

    #[test]
    fn an_edit_rewrites_only_its_own_key_and_keeps_comments_and_presets() {
        let folder = Folder::new();
        let path = folder.write("scene.toml", DEFAULT_SCENE_TOML);
        let (mut scene, document) = load(&path);
        material(&mut scene, "plasticine").roughness = 0.33;
        material(&mut scene, "ground").base_color = Vec3::new(0.5, 0.5, 0.5);
        let saved = save(&scene, &document, &path, false).unwrap();
        assert_eq!(saved.path, std::path::absolute(&path).unwrap());
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, saved.document.text);
        let (added, removed) = changed_lines(DEFAULT_SCENE_TOML, &text);
        assert_eq!(added, ["roughness = 0.33", "base_color = [0.5, 0.5, 0.5]"], "{text}");
        assert_eq!(removed, ["base_color = [0.72, 0.68, 0.6]"], "{text}");
        // The new key goes into its own table, after the keys written there.
        let plasticine =
            &text[text.find("[materials.plasticine]").unwrap()..text.find("[materials.terracotta]").unwrap()];
        assert!(
            plasticine.ends_with("scatter_color = [0.35, 0.55, 1.0]\nroughness = 0.33\n\n"),
            "{plasticine}"
        );
        let (reloaded, _) = load(&path);
        assert_eq!(reloaded.materials, scene.materials);
        assert_eq!(reloaded.camera, scene.camera);
    }

    /// A map's turn is one key of its table, written where the map's other keys are.
    #[test]
    fn a_maps_rotation_is_written_as_its_own_key() {
        let folder = Folder::new();
        let path = folder.write("scene.toml", DEFAULT_SCENE_TOML);
        let (mut scene, document) = load(&path);
        let ring = material(&mut scene, "terracotta");
        ring.maps[MapSlot::Normal].as_mut().unwrap().uv_rotation_degrees = 15.0;
        save(&scene, &document, &path, false).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let (added, removed) = changed_lines(DEFAULT_SCENE_TOML, &text);
        assert_eq!((added, removed), (vec!["uv_rotation_degrees = 15.0".to_owned()], vec![]), "{text}");
        let (mut saved, _) = load(&path);
        let turned = material(&mut saved, "terracotta").maps[MapSlot::Normal].unwrap().uv_rotation_degrees;
        assert_eq!(turned, 15.0);
    }

    /// The changes not saved go to a file of their own beside the scene's, the next name
    /// free each time, never over a file; the scene file keeps its text.
    #[test]
    fn recovered_changes_go_beside_the_scene_without_overwriting_a_file() {
        let folder = Folder::new();
        let path = folder.write("clay.toml", DEFAULT_SCENE_TOML);
        let (mut scene, document) = load(&path);
        material(&mut scene, "plasticine").roughness = 0.33;
        let first = recover(&scene, &document).unwrap();
        assert_eq!(first, std::path::absolute(folder.0.join("clay.recovered.toml")).unwrap());
        let (recovered, _) = load(&first);
        assert_eq!(recovered.materials, scene.materials);
        material(&mut scene, "plasticine").roughness = 0.44;
        let second = recover(&scene, &document).unwrap();
        assert_eq!(second, std::path::absolute(folder.0.join("clay.recovered-2.toml")).unwrap());
        let roughness = |path: &Path| material(&mut load(path).0, "plasticine").roughness;
        assert_eq!(roughness(&first), 0.33, "the first is kept");
        assert_eq!(roughness(&second), 0.44);
        assert_eq!(std::fs::read_to_string(&path).unwrap(), DEFAULT_SCENE_TOML);
    }

    /// Where the scene's folder refuses the recovered file (here the folder is gone, as a
    /// removed drive's would be), it goes to the temporary folder.
    #[test]
    fn recovered_changes_go_to_the_temporary_folder_where_the_scenes_folder_refuses_them() {
        let folder = Folder::new();
        let stem = format!("argil-gone-{}", std::process::id());
        let path = folder.write(&format!("{stem}.toml"), DEFAULT_SCENE_TOML);
        let (mut scene, document) = load(&path);
        material(&mut scene, "plasticine").roughness = 0.33;
        std::fs::remove_dir_all(&folder.0).unwrap();
        let recovered = recover(&scene, &document).unwrap();
        let roughness = material(&mut load(&recovered).0, "plasticine").roughness;
        std::fs::remove_file(&recovered).unwrap();
        let temp = std::path::absolute(std::env::temp_dir()).unwrap();
        assert_eq!(recovered.parent(), Some(temp.as_path()));
        let name = recovered.file_name().unwrap().to_string_lossy().into_owned();
        assert!(name.starts_with(&format!("{stem}.recovered")), "{name}");
        assert_eq!(roughness, 0.33);
        assert!(!folder.0.exists(), "nothing made where the scene was");
    }

    #[test]
    fn values_back_at_the_preset_are_left_to_the_preset() {
        let folder = Folder::new();
        let path = folder.write("scene.toml", DEFAULT_SCENE_TOML);
        let (mut scene, document) = load(&path);
        let preset = crate::scene::Preset::Plasticine.material();
        let ball = material(&mut scene, "plasticine");
        ball.base_color = Vec3::from_array(preset.base_color.map(|c| c as f32));
        let ring = material(&mut scene, "terracotta");
        ring.maps[MapSlot::Normal].as_mut().unwrap().uv_scale = Vec2::new(8.0, 4.0);
        // Not in the file, and equal to the preset: not written either.
        ring.roughness = 0.9;
        save(&scene, &document, &path, false).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let (added, removed) = changed_lines(DEFAULT_SCENE_TOML, &text);
        assert!(added.is_empty(), "{added:?}");
        assert_eq!(removed, ["base_color = [0.12, 0.24, 0.55]", "uv_scale = [11.5, 4.0]"]);
        assert!(text.contains("preset = \"plasticine\"") && text.contains("preset = \"terracotta\""));
        let (reloaded, _) = load(&path);
        assert_eq!(reloaded.materials, scene.materials);
    }

    #[test]
    fn lights_environment_and_camera_are_written_in_place() {
        let folder = Folder::new();
        let path = folder.write("scene.toml", DEFAULT_SCENE_TOML);
        let (mut scene, document) = load(&path);
        scene
            .lights
            .push(PointLight::new(Vec3::new(1.0, 2.0, 3.0), Vec3::splat(5.0)));
        scene.lights[0].radius = 0.25;
        scene.lights[0].shadows = false;
        scene.shadow_resolution = 512;
        scene.shadow_taps = 8;
        scene.shadow_ground_map = false;
        scene.shadow_per_vertex = true;
        scene.antialiasing.msaa = 8;
        scene.antialiasing.specular = false;
        scene.environment = Environment::Studio {
            intensity: 1.5,
            rotation_degrees: 0.0,
            reflection: Reflection::default(),
        };
        scene.camera.fov_y_degrees = 40.0;
        save(&scene, &document, &path, false).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let (reloaded, document) = load(&path);
        assert_eq!(
            (&reloaded.lights, &reloaded.environment, reloaded.camera),
            (&scene.lights, &scene.environment, scene.camera)
        );
        assert!(!text.contains("radiance"), "the uniform environment's key goes: {text}");
        assert!(
            text.starts_with("# The scene shown when no scene file is given"),
            "{text}"
        );

        scene.lights.truncate(1);
        save(&scene, &document, &path, false).unwrap();
        let (reloaded, _) = load(&path);
        assert_eq!(reloaded.lights, scene.lights);
        assert_eq!((reloaded.shadow_resolution, reloaded.shadow_taps), (512, 8));
        assert!(!reloaded.shadow_ground_map && reloaded.shadow_per_vertex);
        assert_eq!((reloaded.antialiasing.msaa, reloaded.antialiasing.specular), (8, false));
    }

    #[test]
    fn a_file_that_no_longer_loads_is_not_saved_over() {
        let folder = Folder::new();
        let path = folder.write("scene.toml", DEFAULT_SCENE_TOML);
        let (mut scene, document) = load(&path);
        scene.materials[0].roughness = 0.1;
        let hand_edit =
            DEFAULT_SCENE_TOML.replace("roughness = 0.8", "roughness = 0.8 # half way through typing\nwrap = ");
        std::fs::write(&path, &hand_edit).unwrap();
        let error = save(&scene, &document, &path, false).unwrap_err();
        assert!(
            matches!(error.downcast_ref::<Refused>(), Some(Refused::Broken { .. })),
            "{error:#}"
        );
        let message = format!("{error:#}");
        assert!(
            message.contains("scene.toml") && message.contains("Save As"),
            "{message}"
        );
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            hand_edit,
            "the hand edit is intact"
        );

        // A hand edit that loads is not overwritten either: the viewer reloads it first.
        let good_edit = DEFAULT_SCENE_TOML.replace("roughness = 0.8", "roughness = 0.7");
        std::fs::write(&path, &good_edit).unwrap();
        let error = save(&scene, &document, &path, false).unwrap_err();
        assert!(matches!(error.downcast_ref::<Refused>(), Some(Refused::Changed { .. })));
        assert_eq!(std::fs::read_to_string(&path).unwrap(), good_edit);
    }

    #[test]
    fn save_as_asks_before_replacing_a_file_and_keeps_paths_working() {
        let folder = Folder::new();
        std::fs::create_dir(folder.0.join("textures")).unwrap();
        image::RgbaImage::from_pixel(4, 4, image::Rgba([200, 100, 50, 255]))
            .save(folder.0.join("textures/skin.png"))
            .unwrap();
        let text = "# my pot\n[[objects]]\nmesh = \"builtin:sphere\"\nmaterial = \"pot\"\n\n\
                    [materials.pot]\npreset = \"terracotta\" # the look I want\n\
                    [materials.pot.base_color_map]\ntexture = \"textures/skin.png\"\n";
        let path = folder.write("pot.toml", text);
        let (mut scene, document) = load(&path);
        scene.materials[0].f0 = 0.05;

        let other = folder.write("other.toml", "# somebody else's file\n");
        let error = save(&scene, &document, &other, false).unwrap_err();
        assert!(matches!(error.downcast_ref::<Refused>(), Some(Refused::Exists { .. })));
        assert_eq!(std::fs::read_to_string(&other).unwrap(), "# somebody else's file\n");
        save(&scene, &document, &other, true).unwrap();
        assert_eq!(load(&other).0.materials, scene.materials);

        std::fs::create_dir(folder.0.join("copies")).unwrap();
        let copy = folder.0.join("copies/pot.toml");
        let saved = save(&scene, &document, &copy, false).unwrap();
        assert!(saved.document.text.starts_with("# my pot\n"), "{}", saved.document.text);
        assert!(saved
            .document
            .text
            .contains("preset = \"terracotta\" # the look I want\n"));
        let (reloaded, _) = load(&copy);
        assert_eq!(reloaded.materials, scene.materials);
        assert_eq!(reloaded.textures, scene.textures);
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            text,
            "the original is untouched"
        );
    }

    #[test]
    fn the_default_scene_saves_with_its_comments_and_a_failed_write_leaves_nothing() {
        let folder = Folder::new();
        let mut scene = Scene::default_scene();
        scene.materials[0].wrap = 0.45;
        let to = folder.0.join("argil-scene.toml");
        save(&scene, &Document::default_scene(), &to, false).unwrap();
        let text = std::fs::read_to_string(&to).unwrap();
        let (added, removed) = changed_lines(DEFAULT_SCENE_TOML, &text);
        assert_eq!((added, removed.len()), (vec!["wrap = 0.45".to_owned()], 0), "{text}");

        let nowhere = folder.0.join("no-such-folder/scene.toml");
        assert!(save(&scene, &Document::default_scene(), &nowhere, false).is_err());
        assert!(!nowhere.exists());
        assert_eq!(
            std::fs::read_dir(&folder.0).unwrap().count(),
            1,
            "no temporary file left"
        );
    }
}

//! Scene-file and OBJ tests; mesh, tangent and camera tests live beside
//! their code.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{Vec3, Vec4};

use super::file::{EnvironmentDef, LightDef, MaterialDef, ObjectDef};
use super::*;

/// A fresh folder under the system temp dir, removed on drop.
pub(crate) struct TempDir(pub(crate) PathBuf);

impl TempDir {
    pub(crate) fn new() -> TempDir {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let path = std::env::temp_dir().join(format!(
            "argil-scene-test-{}-{}",
            std::process::id(),
            COUNTER.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&path).unwrap();
        TempDir(path)
    }

    pub(crate) fn write(&self, name: &str, contents: &str) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, contents).unwrap();
        path
    }

    /// A 16×8 equirectangular environment map, its format by `name`'s extension.
    pub(crate) fn write_map(&self, name: &str) -> PathBuf {
        let path = self.0.join(name);
        image::Rgb32FImage::from_pixel(16, 8, image::Rgb([1.0, 1.0, 1.0])).save(&path).unwrap();
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn parse(text: &str) -> Result<Scene, SceneError> {
    Scene::from_toml(text, "scene.toml", Path::new("."))
}

fn error(text: &str) -> String {
    parse(text).unwrap_err().to_string()
}

const CUBE: &str = "[[objects]]\nmesh = \"builtin:cube\"\n";

// ---------------------------------------------------------------- scene files

#[test]
fn minimal_scene_gets_the_documented_defaults() {
    let scene = parse(CUBE).unwrap();
    assert_eq!(
        scene.camera,
        Camera {
            position: Vec3::new(0.0, 0.0, 5.0),
            target: Vec3::ZERO,
            fov_y_degrees: 30.0,
            near: Camera::NEAR,
            far: Camera::FAR
        }
    );
    assert!(scene.lights.is_empty());
    assert_eq!(scene.environment, Environment::None);
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.meshes[0].name, "builtin:cube");
    assert_eq!(
        scene.objects,
        [Object {
            mesh: 0,
            position: Vec3::ZERO,
            scale: 1.0,
            material: 0,
            part: 0,
            material_from_model: false
        }]
    );
    // The built-in neutral material: the documented models and numbers, and every other
    // key at the default its declaration gives.
    let [m] = &scene.materials[..] else {
        panic!("one material, not {}", scene.materials.len())
    };
    assert_eq!((m.name.as_str(), m.preset), ("default", None));
    assert_eq!(
        (m.base_color, m.diffuse, m.specular, m.distribution, m.geometry),
        (
            Vec3::splat(0.8),
            DiffuseModel::Lambert,
            SpecularModel::CookTorrance,
            Distribution::Ggx,
            Geometry::SmithCorrelated
        )
    );
    assert_eq!((m.roughness, m.f0, m.metallic, m.subsurface), (0.5, 0.04, 0.0, Subsurface::Seed));
    let declared = Material::resolve(
        "default",
        &MaterialDef::default(),
        |key: &str, _: &dyn std::fmt::Debug, reason: String| -> SceneError { panic!("{key}: {reason}") },
        || Ok(MaterialMaps::default()),
    )
    .unwrap();
    assert_eq!(*m, declared);
    assert!(scene.textures.is_empty());
    assert_eq!(scene.source, None);
}

#[test]
fn full_scene_is_read_field_by_field() {
    let scene = parse(
        r#"
[camera]
position = [1, 2, 3]        # integers are accepted as floats
target = [0.0, 0.5, 0.0]
fov_y_degrees = 45.0

[[lights]]
kind = "point"
position = [2.0, 2.0, 3.0]
intensity = [10.0, 9.0, 8.0]

[environment]
kind = "uniform"
radiance = [0.1, 0.2, 0.3]

[[objects]]
mesh = "builtin:sphere"
position = [0.0, 1.0, 0.0]
scale = 2.5
material = "clay"

[[objects]]
mesh = "builtin:sphere"
material = "default"

[[objects]]
mesh = "builtin:torus"

[materials.clay]
base_color = [0.8, 0.45, 0.3]
diffuse = "oren-nayar"
specular = "torrance-sparrow"
distribution = "beckmann"
geometry = "smith-separable"
roughness = 0.25
f0 = 0.5
diffuse_roughness = 0.3
specular_color = [0.5, 0.6, 0.7]
wrap = 0.4
wrap_width = 0.2
wrap_color = [0.9, 0.3, 0.2]
wrap_intensity = 2.0

[materials.unused]
diffuse = "eon"
specular = "blinn-phong"
"#,
    )
    .unwrap();
    assert_eq!(scene.camera.position, Vec3::new(1.0, 2.0, 3.0));
    assert_eq!(scene.camera.fov_y_degrees, 45.0);
    assert_eq!(
        scene.lights,
        [PointLight::new(Vec3::new(2.0, 2.0, 3.0), Vec3::new(10.0, 9.0, 8.0))]
    );
    assert_eq!(
        scene.environment,
        Environment::Uniform {
            radiance: Vec3::new(0.1, 0.2, 0.3),
            reflection: Reflection::default()
        }
    );
    // The sphere is loaded once for both objects.
    let names: Vec<&str> = scene.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["builtin:sphere", "builtin:torus"]);
    let meshes: Vec<usize> = scene.objects.iter().map(|o| o.mesh).collect();
    assert_eq!(meshes, [0, 0, 1]);
    // Defined materials in name order, then the built-in default once.
    let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["clay", "unused", "default"]);
    let materials: Vec<usize> = scene.objects.iter().map(|o| o.material).collect();
    assert_eq!(materials, [0, 2, 2]);
    assert_eq!(scene.objects[0].scale, 2.5);
    let clay = &scene.materials[0];
    assert_eq!(clay.diffuse, DiffuseModel::OrenNayar);
    assert_eq!(clay.specular, SpecularModel::TorranceSparrow);
    assert_eq!(clay.distribution, Distribution::Beckmann);
    assert_eq!(clay.geometry, Geometry::SmithSeparable);
    assert_eq!(
        (clay.roughness, clay.f0, clay.diffuse_roughness, clay.wrap),
        (0.25, 0.5, 0.3, 0.4)
    );
    assert_eq!((clay.wrap_width, clay.wrap_intensity), (0.2, 2.0));
    assert_eq!(clay.specular_color, Vec3::new(0.5, 0.6, 0.7));
    assert_eq!(clay.wrap_color, Vec3::new(0.9, 0.3, 0.2));
    assert_eq!(scene.materials[1].diffuse, DiffuseModel::Eon);
    assert_eq!(scene.materials[1].specular, SpecularModel::BlinnPhong);
}

#[test]
fn a_defined_default_material_overrides_the_builtin_one() {
    let scene = parse(&format!("{CUBE}[materials.default]\nroughness = 0.9\n")).unwrap();
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.materials[0].roughness, 0.9);
}

#[test]
fn shader_constants_are_stable() {
    let diffuse = [
        DiffuseModel::Lambert,
        DiffuseModel::OrenNayar,
        DiffuseModel::Eon,
        DiffuseModel::None,
    ];
    assert_eq!(diffuse.map(|d| d as u32), [0, 1, 2, 3]);
    let specular = [
        SpecularModel::CookTorrance,
        SpecularModel::TorranceSparrow,
        SpecularModel::BlinnPhong,
        SpecularModel::None,
    ];
    assert_eq!(specular.map(|s| s as u32), [0, 1, 2, 3]);
    assert_eq!([Distribution::Ggx as u32, Distribution::Beckmann as u32], [0, 1]);
    assert_eq!(
        [Geometry::SmithCorrelated as u32, Geometry::SmithSeparable as u32],
        [0, 1]
    );
    let blends = [
        DetailBlend::Rnm,
        DetailBlend::Udn,
        DetailBlend::Whiteout,
        DetailBlend::Seed,
    ];
    assert_eq!(blends.map(|b| b as u32), [0, 1, 2, 3]);
}

#[test]
fn unknown_keys_are_named_with_their_line() {
    let message = error(&format!("{CUBE}\n[materials.clay]\nroughnes = 0.5\n"));
    assert!(message.starts_with("scene.toml: "), "{message}");
    assert!(message.contains("line 5"), "{message}");
    assert!(message.contains("unknown field `roughnes`"), "{message}");

    for (text, key, line) in [
        (format!("[camera]\nfov = 30.0\n{CUBE}"), "fov", 2),
        (format!("{CUBE}scael = 2.0\n"), "scael", 3),
        (format!("{CUBE}[[lights]]\nkind = \"point\"\nposition = [0.0, 0.0, 0.0]\nintensity = [1.0, 1.0, 1.0]\ncolor = [1.0, 1.0, 1.0]\n"), "color", 3),
        (format!("{CUBE}[environment]\nkind = \"uniform\"\nradiance = [1.0, 1.0, 1.0]\npath = \"x.hdr\"\n"), "path", 3),
        (format!("{CUBE}[extras]\nfoo = 1\n"), "extras", 3),
    ] {
        let message = error(&text);
        assert!(message.starts_with("scene.toml: "), "{message}");
        assert!(message.contains(&format!("`{key}`")), "{message}");
        assert!(message.contains(&format!("line {line}")), "{message}");
    }
}

#[test]
fn unknown_kinds_are_named() {
    for (text, kind) in [
        (format!("{CUBE}[materials.m]\ndiffuse = \"phong\"\n"), "phong"),
        (format!("{CUBE}[materials.m]\nspecular = \"ward\"\n"), "ward"),
        (format!("{CUBE}[materials.m]\ndistribution = \"gtr\"\n"), "gtr"),
        (format!("{CUBE}[materials.m]\ngeometry = \"kelemen\"\n"), "kelemen"),
        (format!("{CUBE}[environment]\nkind = \"sky\"\n"), "sky"),
        (format!("{CUBE}[[lights]]\nkind = \"spot\"\n"), "spot"),
    ] {
        let message = error(&text);
        assert!(message.starts_with("scene.toml: "), "{message}");
        assert!(message.contains(&format!("`{kind}`")), "{message}");
    }
}

#[test]
fn broken_toml_reports_its_line_and_column() {
    let message = error("[camera]\nposition = [0.0, 0.0, 5.0]\nfov_y_degrees = = 3\n");
    assert!(message.starts_with("scene.toml: "), "{message}");
    assert!(message.contains("line 3, column 17"), "{message}");
    let message = error(&format!("{CUBE}[camera]\nposition = \"up\"\n"));
    assert!(
        message.contains("line 4") && message.contains("invalid type"),
        "{message}"
    );
}

#[test]
fn missing_required_keys_are_named() {
    assert!(error("[[objects]]\nscale = 2.0\n").contains("missing field `mesh`"));
    let message = error(&format!(
        "{CUBE}[[lights]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\n"
    ));
    assert!(message.contains("missing field `intensity`"), "{message}");
    assert!(error(&format!("{CUBE}[environment]\nradiance = [1.0, 1.0, 1.0]\n")).contains("missing field `kind`"));
}

#[test]
fn out_of_range_values_name_the_field() {
    assert_eq!(
        error(&format!("{CUBE}[materials.clay]\nroughness = nan\n")),
        "scene.toml: materials.clay.roughness = NaN: must be a finite number in [0, 1]"
    );
    let cases = [
        ("[materials.m]\nf0 = 1.5", "materials.m.f0 = 1.5: must be a finite number in [0, 1]"),
        ("[materials.m]\nroughness = -0.1", "materials.m.roughness = -0.1: must be a finite number in [0, 1]"),
        ("[materials.m]\ndiffuse_roughness = inf", "materials.m.diffuse_roughness = inf: must be a finite number in [0, 1]"),
        ("[materials.m]\nwrap = 2", "materials.m.wrap = 2.0: must be a finite number in [0, 1]"),
        ("[materials.m]\nwrap_width = 0.0", "materials.m.wrap_width = 0.0: must be a finite number > 0"),
        ("[materials.m]\nwrap_intensity = -1.0", "materials.m.wrap_intensity = -1.0: must be a finite number >= 0"),
        ("[materials.m]\nbase_color = [0.5, -0.1, 0.5]", "materials.m.base_color = [0.5, -0.1, 0.5]: every component must be a finite number >= 0"),
        ("[materials.m]\nspecular_color = [nan, 1.0, 1.0]", "materials.m.specular_color = [NaN, 1.0, 1.0]: every component must be a finite number >= 0"),
        ("[materials.m]\nwrap_color = [1.0, 1.0, inf]", "materials.m.wrap_color = [1.0, 1.0, inf]: every component must be a finite number >= 0"),
        // Too large or too small for f32.
        ("[materials.m]\nroughness = 1e39", "materials.m.roughness = 1e39: must be a finite number in [0, 1]"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nscale = 1e-50", "objects[1].scale = 1e-50: must be a finite number > 0"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nposition = [0.0, 1e39, 0.0]", "objects[1].position = [0.0, 1e39, 0.0]: every component must be a finite number"),
        ("[camera]\nfov_y_degrees = 180.0", "camera.fov_y_degrees = 180.0: must be a finite number of degrees in (0, 180)"),
        ("[camera]\nfov_y_degrees = 0.0", "camera.fov_y_degrees = 0.0: must be a finite number of degrees in (0, 180)"),
        ("[camera]\nfov_y_degrees = nan", "camera.fov_y_degrees = NaN: must be a finite number of degrees in (0, 180)"),
        ("[camera]\nposition = [1.0, 2.0, 3.0]\ntarget = [1.0, 2.0, 3.0]", "camera.position = [1.0, 2.0, 3.0]: must differ from camera.target [1.0, 2.0, 3.0]"),
        ("[camera]\nposition = [3e38, 0.0, 0.0]\ntarget = [-3e38, 0.0, 0.0]", "camera.position = [3e38, 0.0, 0.0]: must differ from camera.target [-3e38, 0.0, 0.0]"),
        ("[camera]\ntarget = [0.0, -inf, 0.0]", "camera.target = [0.0, -inf, 0.0]: every component must be a finite number"),
        ("[[lights]]\nkind = \"point\"\nposition = [0.0, 0.0, 0.0]\nintensity = [1.0, -1.0, 1.0]", "lights[0].intensity = [1.0, -1.0, 1.0]: every component must be a finite number >= 0"),
        ("[[lights]]\nkind = \"point\"\nposition = [0.0, nan, 0.0]\nintensity = [1.0, 1.0, 1.0]", "lights[0].position = [0.0, NaN, 0.0]: every component must be a finite number"),
        ("[[lights]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\nintensity = [1.0, 1.0, 1.0]\nradius = -0.5", "lights[0].radius = -0.5: must be a finite number >= 0"),
        ("[[lights]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\nintensity = [1.0, 1.0, 1.0]\nradius = inf", "lights[0].radius = inf: must be a finite number >= 0"),
        ("[shadows]\nresolution = 8", "shadows.resolution = 8: must be an integer in [16, 4096]"),
        ("[shadows]\nresolution = 8192", "shadows.resolution = 8192: must be an integer in [16, 4096]"),
        ("[shadows]\ntaps = 0", "shadows.taps = 0: must be an integer in [1, 64]"),
        ("[shadows]\ntaps = 65", "shadows.taps = 65: must be an integer in [1, 64]"),
        ("[occlusion]\nslices = 0", "occlusion.slices = 0: must be an integer in [1, 32]"),
        ("[occlusion]\nradius = 0.0", "occlusion.radius = 0.0: must be a finite number > 0"),
        ("[environment]\nkind = \"uniform\"\nradiance = [-1.0, 0.0, 0.0]", "environment.radiance = [-1.0, 0.0, 0.0]: every component must be a finite number >= 0"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nscale = 0.0", "objects[1].scale = 0.0: must be a finite number > 0"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nscale = -2.0", "objects[1].scale = -2.0: must be a finite number > 0"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nscale = inf", "objects[1].scale = inf: must be a finite number > 0"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nposition = [0.0, 0.0, nan]", "objects[1].position = [0.0, 0.0, NaN]: every component must be a finite number"),
        ("[[objects]]\nmesh = \"builtin:cone\"", "objects[1].mesh = \"builtin:cone\": unknown builtin mesh; expected builtin:sphere, builtin:torus, builtin:plane or builtin:cube"),
        ("[[objects]]\nmesh = \"builtin:sphere\"\nsubdivisions = 0", "objects[1].subdivisions = 0: must be an integer in [1, 512]"),
        ("[[objects]]\nmesh = \"builtin:sphere\"\nsubdivisions = 513", "objects[1].subdivisions = 513: must be an integer in [1, 512]"),
        ("[[objects]]\nmesh = \"builtin:torus\"\nsubdivisions = 2", "objects[1].subdivisions = 2: must be an integer in [3, 2048]"),
        ("[[objects]]\nmesh = \"builtin:cube\"\nsubdivisions = 8", "objects[1].subdivisions = 8: only a builtin:sphere or a builtin:torus has subdivisions; this object's mesh is \"builtin:cube\""),
    ];
    for (extra, expected) in cases {
        assert_eq!(error(&format!("{CUBE}{extra}\n")), format!("scene.toml: {expected}"));
    }
}

/// Spheres and tori of different `subdivisions` are different meshes, each object keeps
/// its own, and the count is saved only where it is not the mesh's default.
#[test]
fn subdivisions_are_per_object_and_saved() {
    let text = "[[objects]]\nmesh = \"builtin:sphere\"\nsubdivisions = 4\n\
                [[objects]]\nmesh = \"builtin:sphere\"\n\
                [[objects]]\nmesh = \"builtin:sphere\"\nsubdivisions = 4\n\
                [[objects]]\nmesh = \"builtin:sphere\"\nsubdivisions = 32\n\
                [[objects]]\nmesh = \"builtin:torus\"\nsubdivisions = 64\n\
                [[objects]]\nmesh = \"builtin:torus\"\nsubdivisions = 128\n";
    let scene = parse(text).unwrap();
    let meshes: Vec<usize> = scene.objects.iter().map(|o| o.mesh).collect();
    assert_eq!(meshes, [0, 1, 0, 1, 2, 3]);
    assert_eq!(scene.meshes[0].indices.len(), 6 * 6 * 4 * 4);
    assert_eq!(scene.meshes[1], Mesh::builtin("builtin:sphere").unwrap());
    // 64 cells around the ring, 24 around the tube, two triangles each.
    assert_eq!(scene.meshes[2].indices.len(), 3 * 2 * 64 * 24);
    assert_eq!(scene.meshes[3], Mesh::builtin("builtin:torus").unwrap());
    assert_eq!(scene.meshes[3].indices.len(), 3 * 2 * 128 * 48);
    let saved: Vec<Option<u32>> = scene.to_file().objects.iter().map(|o| o.subdivisions).collect();
    assert_eq!(saved, [Some(4), None, Some(4), None, Some(64), None]);
}

#[test]
fn undefined_material_is_named() {
    assert_eq!(
        error("[[objects]]\nmesh = \"builtin:cube\"\nmaterial = \"stone\"\n[materials.clay]\n[materials.wood]\n"),
        "scene.toml: objects[0].material = \"stone\": no [materials.stone] table is defined (defined: clay, wood)"
    );
    assert_eq!(
        error("[[objects]]\nmesh = \"builtin:cube\"\nmaterial = \"stone\"\n"),
        "scene.toml: objects[0].material = \"stone\": no [materials.stone] table is defined (defined: none)"
    );
}

#[test]
fn a_scene_needs_objects() {
    let expected = "scene.toml: the scene has no objects; add at least one [[objects]] table";
    assert_eq!(error(""), expected);
    assert_eq!(error("[camera]\nfov_y_degrees = 40.0\n"), expected);
}

#[test]
fn default_scene_is_a_valid_clay_scene() {
    let scene = Scene::default_scene();
    assert_eq!(scene.objects.len(), 3);
    let names: Vec<&str> = scene.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["builtin:sphere", "builtin:torus", "builtin:plane"]);
    // Plasticine with fingerprints on the sphere, terracotta (no
    // fingerprints) on the torus, a plain ground; all maps are builtins.
    let material = |i: usize| &scene.materials[scene.objects[i].material];
    let (plasticine, terracotta, ground) = (material(0), material(1), material(2));
    let file: SceneFile = toml::from_str(DEFAULT_SCENE_TOML).unwrap();
    assert_eq!(file.materials[&plasticine.name].preset, Some(Preset::Plasticine));
    assert_eq!(file.materials[&terracotta.name].preset, Some(Preset::Terracotta));
    assert_eq!(ground.maps, MaterialMaps::default());
    assert_eq!(terracotta.maps[MapSlot::Detail], None);
    let detail = plasticine.maps[MapSlot::Detail].unwrap();
    assert_eq!(scene.textures[detail.texture].name, "builtin:fingerprints");
    assert!(scene.textures.iter().all(|t| t.name.starts_with("builtin:")));
    for material in &scene.materials {
        assert!((0.02..=0.04).contains(&material.f0), "{material:?}");
    }
    assert_eq!(scene.lights.len(), 1);
    let light = scene.lights[0];
    assert!(light.intensity.min_element() >= 30.0 && light.intensity.max_element() <= 60.0);
    // A studio shot: the studio's light, a soft key light, its light bounced off the
    // ground, and the studio's light the objects hide from each other.
    assert!(
        matches!(scene.environment, Environment::Studio { .. }),
        "{:?}",
        scene.environment
    );
    assert!(light.radius > 0.0 && light.shadows);
    assert!(scene.bounce && scene.occlusion.objects && !scene.occlusion.enabled);
    // Up, left and in front of the objects.
    assert!(light.position.y > 0.0 && light.position.x < 0.0 && light.position.z > 0.0);
    let camera = scene.camera;
    assert!(camera.position.y > camera.target.y, "the camera looks down");
    // The camera is above the ground plane at y = -1 and outside the
    // sphere's and the torus's bounding spheres.
    let ground = scene.objects[2];
    assert_eq!(ground.position.y, -1.0);
    assert!(camera.position.y > ground.position.y + 1.0);
    for (object, radius) in scene.objects.iter().zip([1.0, 1.35]) {
        let distance = camera.position.distance(object.position);
        assert!(distance > radius * object.scale + 1.0, "{object:?}");
    }
    // The sphere and torus rest on the ground and each object's centre is
    // in front of the camera and on screen.
    assert_eq!(scene.objects[0].position.y, 0.0);
    assert!((scene.objects[1].position.y - (-1.0 + 0.35)).abs() < 1e-6);
    let view_projection = camera.projection(16.0 / 9.0) * camera.view();
    for object in &scene.objects[..2] {
        let clip = view_projection * object.position.extend(1.0);
        assert!(clip.w > 0.0);
        assert!(clip.x.abs() < clip.w * 0.8 && clip.y.abs() < clip.w * 0.8);
    }
    // The plasticine is the nearer object, close enough that its
    // fingerprint ridges are at least 3 pixels apart at 1080p: the sphere's
    // u runs 2π around it and the map holds 75 ridges (0.4 mm in 3 cm).
    let [sphere, torus] = [0, 1].map(|i| camera.position.distance(scene.objects[i].position));
    assert!(sphere < torus);
    let ridge = std::f32::consts::TAU / detail.uv_scale.x / 75.0;
    let pixels_per_unit = 1080.0 / (2.0 * (sphere - 1.0) * (camera.fov_y_degrees.to_radians() / 2.0).tan());
    assert!(ridge * pixels_per_unit >= 3.0, "{}", ridge * pixels_per_unit);
}

#[test]
fn scene_file_round_trips_through_toml() {
    for text in [
        DEFAULT_SCENE_TOML.to_owned(),
        format!("{CUBE}[environment]\nkind = \"map\"\npath = \"sky/studio.exr\"\n[[objects]]\nmesh = \"models/pot.obj\"\nmaterial = \"clay\"\n[materials.clay]\nwrap = 0.5\n"),
        CUBE.to_owned(),
    ] {
        let file: SceneFile = toml::from_str(&text).unwrap();
        for saved in [toml::to_string_pretty(&file).unwrap(), file.to_toml().unwrap()] {
            let reread: SceneFile = toml::from_str(&saved).unwrap();
            assert_eq!(reread, file, "{saved}");
        }
    }
    let file: SceneFile = toml::from_str(DEFAULT_SCENE_TOML).unwrap();
    assert_eq!(file.objects.len(), 3);
    assert_eq!(
        file.objects[2],
        ObjectDef {
            mesh: "builtin:plane".into(),
            position: [0.0, -1.0, 0.0],
            scale: 8.0,
            material: Some("ground".into()),
            subdivisions: None,
        }
    );
    assert_eq!(file.materials["ground"].roughness, 0.8);
    assert_eq!(file.materials["ground"].base_color, [0.72, 0.68, 0.6]);
    assert_eq!(file.materials["ground"].wrap_width, MaterialDef::default().wrap_width);
    assert!(matches!(file.lights[0], LightDef::Point { intensity, .. } if intensity == [48.0, 45.0, 40.0]));
    assert!(matches!(file.environment, EnvironmentDef::Studio { .. }));
}

/// A light's radius and shadows, the maps' resolution, a soft shadow's taps, the ground's
/// shadow map and the shadows at the vertices are read, default to a point that casts
/// shadows at 1024 with 16 taps, the ground's map and the pixels, and are saved only when
/// not the default.
#[test]
fn shadow_keys_are_read_defaulted_and_saved() {
    let text = format!(
        "{CUBE}[shadows]\nresolution = 512\ntaps = 8\nground_map = false\nper_vertex = true\n[[lights]]\nkind = \"point\"\nposition = [0.0, 2.0, 0.0]\nintensity = [1.0, 1.0, 1.0]\nradius = 0.25\nshadows = false\n[[lights]]\nkind = \"point\"\nposition = [1.0, 2.0, 0.0]\nintensity = [1.0, 1.0, 1.0]\n"
    );
    let scene = Scene::from_toml(&text, "scene.toml", Path::new("")).unwrap();
    assert_eq!((scene.shadow_resolution, scene.shadow_taps), (512, 8));
    assert_eq!((scene.lights[0].radius, scene.lights[0].shadows), (0.25, false));
    assert_eq!((scene.lights[1].radius, scene.lights[1].shadows), (0.0, true));
    let saved = scene.to_file().to_toml().unwrap();
    let reread = Scene::from_toml(&saved, "saved.toml", Path::new("")).unwrap();
    assert_eq!((reread.lights, reread.shadow_resolution, reread.shadow_taps), (scene.lights.clone(), 512, 8));
    assert!(!scene.shadow_ground_map && !reread.shadow_ground_map);
    assert!(scene.shadow_per_vertex && reread.shadow_per_vertex);
    let defaults = Scene::from_toml(CUBE, "scene.toml", Path::new("")).unwrap();
    assert!(defaults.shadow_ground_map && !defaults.shadow_per_vertex);
    assert_eq!(defaults.shadow_resolution, crate::scene::DEFAULT_SHADOW_RESOLUTION);
    assert_eq!(defaults.shadow_taps, crate::scene::DEFAULT_SHADOW_TAPS);
    let saved = defaults.to_file().to_toml().unwrap();
    let keys: Vec<&str> = saved.lines().filter_map(|l| l.split(" =").next()).collect();
    assert!(
        !saved.contains("[shadows]") && !keys.contains(&"radius") && !keys.contains(&"shadows"),
        "{saved}"
    );
    assert_eq!(Scene::default_scene().lights[0].radius, 0.5);
}

/// `[antialiasing]` is read, defaults to one sample with specular anti-aliasing, is saved
/// only where it differs from that, and a sample count outside 1, 2, 4, 8 names the field.
#[test]
fn antialiasing_keys_are_read_defaulted_validated_and_saved() {
    let text = format!("{CUBE}[antialiasing]\nmsaa = 4\n");
    let scene = Scene::from_toml(&text, "scene.toml", Path::new("")).unwrap();
    assert_eq!((scene.antialiasing.msaa, scene.antialiasing.specular), (4, true));
    let saved = scene.to_file().to_toml().unwrap();
    assert!(
        saved.contains("[antialiasing]\nmsaa = 4\n") && !saved.contains("specular = true"),
        "{saved}"
    );
    assert_eq!(
        Scene::from_toml(&saved, "saved.toml", Path::new(""))
            .unwrap()
            .antialiasing,
        scene.antialiasing
    );
    let defaults = Scene::from_toml(CUBE, "scene.toml", Path::new("")).unwrap();
    assert_eq!(defaults.antialiasing, crate::scene::Antialiasing::DEFAULT);
    assert!(!defaults.to_file().to_toml().unwrap().contains("[antialiasing]"));
    for bad in ["msaa = 3", "msaa = 16", "msaa = 0"] {
        let error = Scene::from_toml(&format!("{CUBE}[antialiasing]\n{bad}\n"), "bad.toml", Path::new(""))
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("bad.toml") && error.contains("antialiasing.msaa"),
            "{error}"
        );
    }
    let error = Scene::from_toml(
        &format!("{CUBE}[antialiasing]\nfxaa = true\n"),
        "bad.toml",
        Path::new(""),
    )
    .unwrap_err()
    .to_string();
    assert!(error.contains("fxaa"), "{error}");
}

/// `[occlusion]` is read, defaults to off (radius 0.5, 4 × 8, multi-bounce, no object
/// occlusion), and only the
/// keys that differ from the defaults are saved.
#[test]
fn occlusion_keys_are_read_defaulted_and_saved() {
    let text = format!(
        "{CUBE}[occlusion]\nenabled = true\nsteps = 12\nmulti_bounce = false\nobjects = true\nground_map = false\n\
         per_vertex = false\n"
    );
    let scene = Scene::from_toml(&text, "scene.toml", Path::new("")).unwrap();
    let expected = crate::scene::Occlusion {
        enabled: true,
        steps: 12,
        multi_bounce: false,
        objects: true,
        ground_map: false,
        per_vertex: false,
        ..Default::default()
    };
    assert_eq!(scene.occlusion, expected);
    let def = scene.to_file().occlusion.expect("an [occlusion] section");
    assert_eq!((def.radius, def.slices), (None, None));
    let saved = scene.to_file().to_toml().unwrap();
    let reread = Scene::from_toml(&saved, "saved.toml", Path::new("")).unwrap();
    assert_eq!(reread.occlusion, expected);
    let defaults = Scene::from_toml(CUBE, "scene.toml", Path::new("")).unwrap();
    let o = &defaults.occlusion;
    assert!(!o.enabled && !o.objects && o.ground_map && o.per_vertex);
    assert!(!defaults.to_file().to_toml().unwrap().contains("[occlusion]"));
}

#[test]
fn saved_scene_reloads_identically_with_relative_paths() {
    let dir = TempDir::new();
    dir.write("pot.obj", TRIANGLE_OBJ);
    dir.write_map("sky.hdr");
    let path = dir.write(
        "scene.toml",
        &format!("{CUBE}[environment]\nkind = \"map\"\npath = \"sky.hdr\"\n[[objects]]\nmesh = \"pot.obj\"\n[[objects]]\nmesh = \"pot.obj\"\nscale = 2.0\n"),
    );
    let scene = Scene::load(&path).unwrap();
    assert_eq!(scene.source.as_deref(), Some(path.as_path()));
    assert_eq!(
        scene.environment,
        Environment::Map {
            path: dir.0.join("sky.hdr"),
            intensity: 1.0,
            rotation_degrees: 0.0,
            reflection: Reflection::default()
        }
    );
    assert_eq!(scene.meshes.len(), 2);

    let file = scene.to_file();
    assert_eq!(file.objects[1].mesh, "pot.obj");
    assert_eq!(file.objects[1].material.as_deref(), Some("default"));
    assert_eq!(
        file.environment,
        EnvironmentDef::Map {
            path: "sky.hdr".into(),
            intensity: None,
            rotation_degrees: None,
            reflection: None,
            samples: None,
            seed_strength: None
        }
    );
    let saved = dir.write("saved.toml", &toml::to_string_pretty(&file).unwrap());
    let mut reloaded = Scene::load(&saved).unwrap();
    reloaded.source = scene.source.clone();
    assert_eq!(reloaded, scene);
}

#[test]
fn edited_scene_saves_its_edits() {
    let mut scene = Scene::default_scene();
    scene.camera.fov_y_degrees = 50.0;
    scene.materials[0].roughness = 0.3;
    scene.objects[1].scale = 1.5;
    let text = scene.to_file().to_toml().unwrap();
    // Saved numbers are the shortest decimals of the f32 values.
    assert!(text.contains("position = [0.0, 1.4, 6.2]\n"), "{text}");
    assert!(text.contains("scale = 1.5\n"), "{text}");
    let reloaded = parse(&text).unwrap();
    assert_eq!(reloaded, scene);
}

#[test]
fn environment_map_is_resolved_and_checked() {
    let dir = TempDir::new();
    let scene = |env: &str| Scene::from_toml(&format!("{CUBE}[environment]\n{env}\n"), "s.toml", &dir.0);
    dir.write_map("studio.EXR");
    assert_eq!(
        scene("kind = \"map\"\npath = \"studio.EXR\"").unwrap().environment,
        Environment::Map {
            path: dir.0.join("studio.EXR"),
            intensity: 1.0,
            rotation_degrees: 0.0,
            reflection: Reflection::default()
        }
    );
    assert_eq!(
        scene("kind = \"map\"\npath = \"missing.hdr\"").unwrap_err().to_string(),
        format!(
            "s.toml: environment.path = \"missing.hdr\": no such file: {}",
            dir.0.join("missing.hdr").display()
        )
    );
    assert_eq!(
        scene("kind = \"map\"\npath = \"sky.png\"").unwrap_err().to_string(),
        "s.toml: environment.path = \"sky.png\": must be an equirectangular .hdr or .exr image"
    );
    // Its headers are read as the scene loads.
    let square = dir.0.join("square.hdr");
    image::Rgb32FImage::new(8, 8).save(&square).unwrap();
    assert_eq!(
        scene("kind = \"map\"\npath = \"square.hdr\"").unwrap_err().to_string(),
        format!(
            "s.toml: environment.path = \"square.hdr\": {}: is 8x8; an equirectangular map is twice as wide as tall",
            square.display()
        )
    );
    assert_eq!(scene("kind = \"none\"").unwrap().environment, Environment::None);
}

#[test]
fn missing_scene_file_names_it() {
    let dir = TempDir::new();
    let path = dir.0.join("nope.toml");
    let message = Scene::load(&path).unwrap_err().to_string();
    assert!(
        message.starts_with(&format!("{}: cannot read: ", path.display())),
        "{message}"
    );
    let broken = dir.write("broken.toml", "[[objects]\n");
    let message = Scene::load(&broken).unwrap_err().to_string();
    assert!(
        message.starts_with(&format!("{}: TOML parse error at line 1", broken.display())),
        "{message}"
    );
}

#[test]
fn object_model_matrix_scales_then_translates() {
    let object = Object {
        mesh: 0,
        position: Vec3::new(1.0, 2.0, 3.0),
        scale: 2.0,
        material: 0,
        part: 0,
        material_from_model: false,
    };
    let p = object.model_matrix() * Vec4::new(1.0, 0.0, -1.0, 1.0);
    assert_eq!(p, Vec4::new(3.0, 2.0, 1.0, 1.0));
}

// ------------------------------------------------------ material maps, presets

/// A small RGBA8 PNG, written with `image`.
fn write_png(path: &Path) {
    image::RgbaImage::from_pixel(4, 2, image::Rgba([200, 100, 50, 255]))
        .save(path)
        .unwrap();
}

#[test]
fn material_maps_are_read_and_textures_shared() {
    let dir = TempDir::new();
    std::fs::create_dir(dir.0.join("textures")).unwrap();
    write_png(&dir.0.join("textures/skin.png"));
    let scene = Scene::from_toml(
        &format!(
            r#"{CUBE}
[materials.a]
detail_blend = "whiteout"
[materials.a.base_color_map]
texture = "textures/skin.png"
strength = 0.5
uv_scale = [2, -3.5]
uv_offset = [0.25, 1e3]
uv_rotation_degrees = -400
[materials.a.normal_map]
texture = "builtin:clay-lumps"
green = "down"
[materials.a.detail_map]
texture = "builtin:fingerprints"
[materials.a.noise_map]
texture = "textures/skin.png"

[materials.b]
[materials.b.normal_map]
texture = "builtin:clay-lumps"
strength = 8
[materials.b.detail_map]
texture = "builtin:clay-lumps"
"#
        ),
        "s.toml",
        &dir.0,
    )
    .unwrap();
    // One texture per (texture, role), in order of first use: the PNG as
    // colour and as noise; clay-lumps once for both normal and detail maps.
    let names: Vec<(&str, TexelFormat)> = scene.textures.iter().map(|t| (t.name.as_str(), t.format)).collect();
    let skin = dir.0.join("textures/skin.png").display().to_string();
    assert_eq!(
        names,
        [
            (skin.as_str(), TexelFormat::Rgba8Srgb),
            ("builtin:clay-lumps", TexelFormat::Rgba8Unorm),
            ("builtin:fingerprints", TexelFormat::Rgba8Unorm),
            (skin.as_str(), TexelFormat::Rgba8Unorm),
        ]
    );
    let a = &scene.materials[0].maps;
    assert_eq!(
        a[MapSlot::BaseColor],
        Some(MapRef {
            texture: 0,
            strength: 0.5,
            uv_scale: glam::Vec2::new(2.0, -3.5),
            uv_offset: glam::Vec2::new(0.25, 1000.0),
            uv_rotation_degrees: -400.0,
            green_down: false
        })
    );
    let defaults = |texture| MapRef {
        texture,
        strength: 1.0,
        uv_scale: glam::Vec2::ONE,
        uv_offset: glam::Vec2::ZERO,
        uv_rotation_degrees: 0.0,
        green_down: false,
    };
    assert_eq!(
        a[MapSlot::Normal],
        Some(MapRef {
            green_down: true,
            ..defaults(1)
        })
    );
    assert_eq!(a[MapSlot::Detail], Some(defaults(2)));
    assert_eq!(a[MapSlot::Noise], Some(defaults(3)));
    assert_eq!(scene.materials[0].detail_blend, DetailBlend::Whiteout);
    let b = &scene.materials[1].maps;
    assert_eq!(b[MapSlot::Normal].map(|m| (m.texture, m.strength)), Some((1, 8.0)));
    assert_eq!(b[MapSlot::Detail].map(|m| m.texture), Some(1));
    assert_eq!((b[MapSlot::BaseColor], b[MapSlot::Noise]), (None, None));
    assert_eq!(scene.materials[1].detail_blend, DetailBlend::Rnm);
}

#[test]
fn detail_blend_names() {
    for (name, blend) in [
        ("rnm", DetailBlend::Rnm),
        ("udn", DetailBlend::Udn),
        ("whiteout", DetailBlend::Whiteout),
        ("seed", DetailBlend::Seed),
    ] {
        let scene = parse(&format!(
            "{CUBE}material = \"m\"\n[materials.m]\ndetail_blend = \"{name}\"\n"
        ))
        .unwrap();
        assert_eq!(scene.materials[0].detail_blend, blend);
    }
    let message = error(&format!("{CUBE}[materials.m]\ndetail_blend = \"mix\"\n"));
    assert!(
        message.contains("line 4") && message.contains("`mix`") && message.contains("`rnm`"),
        "{message}"
    );
}

#[test]
fn energy_compensation_is_a_flag_off_by_default_and_saved() {
    let read = |keys: &str| parse(&format!("{CUBE}material = \"m\"\n[materials.m]\n{keys}\n")).unwrap();
    assert!(!read("").materials[0].energy_compensation);
    let on = read("energy_compensation = true");
    assert!(on.materials[0].energy_compensation);
    assert!(on.to_file().materials["m"].energy_compensation);
    let message = error(&format!("{CUBE}[materials.m]\nenergy_compensation = \"yes\"\n"));
    assert!(message.contains("line 4") && message.contains("boolean"), "{message}");
}

#[test]
fn map_errors_name_the_field() {
    let normal = |keys: &str| {
        error(&format!(
            "{CUBE}[materials.m.normal_map]\ntexture = \"builtin:clay-lumps\"\n{keys}\n"
        ))
    };
    let cases = [
        ("strength = 8.5", "materials.m.normal_map.strength = 8.5: must be a finite number in [0, 8]"),
        ("strength = -0.1", "materials.m.normal_map.strength = -0.1: must be a finite number in [0, 8]"),
        ("strength = nan", "materials.m.normal_map.strength = NaN: must be a finite number in [0, 8]"),
        ("uv_scale = [0.0, 1.0]", "materials.m.normal_map.uv_scale = [0.0, 1.0]: every component must be a finite, non-zero number in [-10000, 10000]"),
        ("uv_scale = [1.0, -2e4]", "materials.m.normal_map.uv_scale = [1.0, -20000.0]: every component must be a finite, non-zero number in [-10000, 10000]"),
        ("uv_scale = [1.0, inf]", "materials.m.normal_map.uv_scale = [1.0, inf]: every component must be a finite, non-zero number in [-10000, 10000]"),
        ("uv_scale = [1e-50, 1.0]", "materials.m.normal_map.uv_scale = [1e-50, 1.0]: every component must be a finite, non-zero number in [-10000, 10000]"),
        ("uv_offset = [nan, 0.0]", "materials.m.normal_map.uv_offset = [NaN, 0.0]: every component must be a finite number"),
        ("uv_offset = [0.0, 1e39]", "materials.m.normal_map.uv_offset = [0.0, 1e39]: every component must be a finite number"),
        ("uv_rotation_degrees = inf", "materials.m.normal_map.uv_rotation_degrees = inf: must be a finite number"),
        ("uv_rotation_degrees = 1e39", "materials.m.normal_map.uv_rotation_degrees = 1e39: must be a finite number"),
    ];
    for (keys, expected) in cases {
        assert_eq!(normal(keys), format!("scene.toml: {expected}"));
    }
    let builtins = "builtin:clay-lumps, builtin:fingerprints or builtin:noise";
    assert_eq!(
        error(&format!("{CUBE}[materials.m.detail_map]\ntexture = \"builtin:marble\"\n")),
        format!("scene.toml: materials.m.detail_map.texture = \"builtin:marble\": unknown builtin texture; expected {builtins}")
    );
    assert_eq!(
        error(&format!("{CUBE}[materials.m.noise_map]\ntexture = \"\"\n")),
        format!("scene.toml: materials.m.noise_map.texture = \"\": must be an image path (relative to the scene file) or one of {builtins}")
    );
    assert_eq!(
        error(&format!("{CUBE}[materials.m.base_color_map]\ntexture = \"builtin:noise\"\ngreen = \"down\"\n")),
        "scene.toml: materials.m.base_color_map.green = \"down\": only normal_map and detail_map have a green direction"
    );
    // Errors from toml: the line, the table and the key.
    let message = normal("strenght = 1.0");
    assert!(
        message.contains("line 5") && message.contains("unknown field `strenght`"),
        "{message}"
    );
    let message = normal("green = \"left\"");
    assert!(message.contains("line 5") && message.contains("`left`"), "{message}");
    let message = error(&format!("{CUBE}[materials.m.normal_map]\nstrength = 0.5\n"));
    assert!(
        message.contains("line 3")
            && message.contains("missing field `texture` in `normal_map` (no preset supplies this map)"),
        "{message}"
    );
    let message = error(&format!("{CUBE}[materials.m]\nsheen_map = \"x.png\"\n"));
    assert!(message.contains("unknown field `sheen_map`"), "{message}");
}

#[test]
fn unloadable_map_textures_name_the_map_and_the_file() {
    let dir = TempDir::new();
    let scene = |texture: &str, map: &str| {
        Scene::from_toml(
            &format!("{CUBE}[materials.m.{map}]\ntexture = \"{texture}\"\n"),
            "s.toml",
            &dir.0,
        )
        .unwrap_err()
        .to_string()
    };
    let missing = dir.0.join("missing.png");
    let message = scene("missing.png", "base_color_map");
    let expected = format!(
        "s.toml: materials.m.base_color_map.texture = \"missing.png\": {}: cannot read: ",
        missing.display()
    );
    assert!(message.starts_with(&expected), "{message}");

    std::fs::write(dir.0.join("broken.png"), b"\x89PNG\r\n\x1a\nnot really").unwrap();
    // The files are decoded in parallel; the error is the first map's in the scene's order.
    let two = format!(
        "{CUBE}[materials.m]\n{}{}",
        "base_color_map = { texture = \"missing.png\" }\n", "normal_map = { texture = \"broken.png\" }\n"
    );
    let message = Scene::from_toml(&two, "s.toml", &dir.0).unwrap_err().to_string();
    assert!(message.starts_with(&expected), "{message}");
    let message = scene("broken.png", "normal_map");
    let expected = format!(
        "s.toml: materials.m.normal_map.texture = \"broken.png\": {}: ",
        dir.0.join("broken.png").display()
    );
    assert!(message.starts_with(&expected), "{message}");

    let sky = dir.0.join("sky.hdr");
    image::Rgb32FImage::from_pixel(2, 2, image::Rgb([1.0, 2.0, 3.0]))
        .save(&sky)
        .unwrap();
    assert_eq!(
        scene("sky.hdr", "detail_map"),
        format!("s.toml: materials.m.detail_map.texture = \"sky.hdr\": {}: a Radiance HDR image cannot be a normal map (normal maps are 8- or 16-bit PNG or JPEG)", sky.display())
    );
    // Float images are fine as colour.
    Scene::from_toml(
        &format!("{CUBE}[materials.m.base_color_map]\ntexture = \"sky.hdr\"\n"),
        "s.toml",
        &dir.0,
    )
    .unwrap();
}

fn preset_material(preset: &str, keys: &str) -> Material {
    let scene = parse(&format!(
        "{CUBE}material = \"m\"\n[materials.m]\npreset = \"{preset}\"\n{keys}\n"
    ))
    .unwrap();
    scene.materials[0].clone()
}

#[test]
fn presets_supply_every_field() {
    for preset in Preset::ALL {
        let def = preset.material();
        let text = format!(
            "{CUBE}material = \"m\"\n[materials.m]\npreset = {}\n",
            toml::Value::try_from(preset).unwrap()
        );
        let scene = parse(&text).unwrap();
        let material = &scene.materials[0];
        // The table is exactly the preset's values.
        let file: SceneFile = toml::from_str(&text).unwrap();
        assert_eq!(file.materials["m"], def, "{preset:?}");
        assert_eq!(material.roughness, def.roughness as f32, "{preset:?}");
        assert_eq!(material.diffuse, def.diffuse, "{preset:?}");
        assert!(material.maps[MapSlot::Normal].is_some(), "{preset:?}");
        assert!(material.maps[MapSlot::Noise].is_some(), "{preset:?}");
        for map in [
            material.maps[MapSlot::Normal],
            material.maps[MapSlot::Detail],
            material.maps[MapSlot::Noise],
        ]
        .into_iter()
        .flatten()
        {
            assert!(scene.textures[map.texture].name.starts_with("builtin:"));
        }
    }
}

/// Each preset has the character docs/scene-format.md gives it.
#[test]
fn presets_look_like_their_clay() {
    let [plasticine, terracotta, wet, polymer, armature] = Preset::ALL.map(Preset::material);
    assert_eq!(
        (armature.metallic, plasticine.metallic, polymer.metallic),
        (1.0, 0.0, 0.0)
    );
    assert_eq!(armature.subsurface, Subsurface::None);
    let luminance = |c: [f64; 3]| 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    let texture = |map: &Option<file::MapDef>| map.as_ref().map(|m| m.texture.clone());

    assert_eq!(plasticine.diffuse, DiffuseModel::Eon);
    assert_eq!(texture(&plasticine.detail_map).as_deref(), Some("builtin:fingerprints"));
    assert_eq!(texture(&plasticine.normal_map).as_deref(), Some("builtin:clay-lumps"));
    assert!(plasticine.roughness >= 0.5 && plasticine.wrap > 0.0 && plasticine.wrap_intensity > 0.0);

    assert!(matches!(
        terracotta.diffuse,
        DiffuseModel::OrenNayar | DiffuseModel::Eon
    ));
    assert!(terracotta.roughness >= 0.8 && terracotta.diffuse_roughness >= 0.7);
    assert!(terracotta.detail_map.is_none());
    assert!(terracotta.f0 < 0.04 && terracotta.wrap_intensity == 0.0);

    assert!((0.25..=0.35).contains(&wet.roughness));
    assert!(luminance(wet.base_color) < 0.5 * luminance(plasticine.base_color));
    assert!(luminance(wet.base_color) < 0.5 * luminance(terracotta.base_color));
    assert!(wet.wrap > plasticine.wrap && wet.wrap_intensity > plasticine.wrap_intensity);

    assert!(polymer.roughness < plasticine.roughness && polymer.roughness > wet.roughness);
    let strength = |map: &Option<file::MapDef>| map.as_ref().map_or(0.0, |m| m.strength);
    assert!(strength(&polymer.detail_map) < strength(&plasticine.detail_map));
    assert!(strength(&polymer.normal_map) < strength(&plasticine.normal_map));
}

#[test]
fn keys_written_in_a_table_override_its_preset() {
    let preset = Preset::Plasticine.material();
    let material = preset_material(
        "plasticine",
        "roughness = 0.2\nbase_color = [0.1, 0.2, 0.3]\ndetail_blend = \"udn\"\n\
         [materials.m.detail_map]\nstrength = 0.25\n\
         [materials.m.normal_map]\ntexture = \"builtin:noise\"\n\
         [materials.m.base_color_map]\ntexture = \"builtin:noise\"\n",
    );
    assert_eq!(material.roughness, 0.2);
    assert_eq!(material.base_color, Vec3::new(0.1, 0.2, 0.3));
    assert_eq!(material.detail_blend, DetailBlend::Udn);
    // Untouched keys keep the preset's values, also inside map tables.
    assert_eq!(material.f0, preset.f0 as f32);
    assert_eq!(material.diffuse, preset.diffuse);
    let preset_detail = preset.detail_map.unwrap();
    let detail = material.maps[MapSlot::Detail].unwrap();
    assert_eq!(detail.strength, 0.25);
    assert_eq!(detail.uv_scale.to_array().map(f64::from), preset_detail.uv_scale);
    let normal = material.maps[MapSlot::Normal].unwrap();
    assert_eq!(normal.strength, preset.normal_map.unwrap().strength as f32);
    assert_eq!(material.maps[MapSlot::BaseColor].unwrap().strength, 1.0);

    // Without a preset the same keys start from the defaults.
    let scene = parse(&format!("{CUBE}material = \"m\"\n[materials.m]\nroughness = 0.2\n")).unwrap();
    assert_eq!(scene.materials[0].maps, MaterialMaps::default());
    assert_eq!(scene.materials[0].diffuse, DiffuseModel::Lambert);

    let message = error(&format!("{CUBE}[materials.m]\npreset = \"plastecine\"\n"));
    assert!(
        message.contains("line 4") && message.contains("`plastecine`") && message.contains("`wet-clay`"),
        "{message}"
    );
}

#[test]
fn maps_and_presets_round_trip_through_to_file() {
    let dir = TempDir::new();
    std::fs::create_dir(dir.0.join("textures")).unwrap();
    write_png(&dir.0.join("textures/skin.png"));
    let path = dir.write(
        "scene.toml",
        &format!(
            "{CUBE}material = \"clay\"\n[[objects]]\nmesh = \"builtin:sphere\"\nmaterial = \"pot\"\n\
             [materials.clay]\npreset = \"wet-clay\"\nroughness = 0.35\n\
             [materials.clay.detail_map]\ntexture = \"builtin:fingerprints\"\ngreen = \"down\"\nuv_offset = [0.5, 0.25]\n\
             [materials.pot]\npreset = \"terracotta\"\n\
             [materials.pot.base_color_map]\ntexture = \"textures/skin.png\"\nstrength = 0.75\n"
        ),
    );
    let scene = Scene::load(&path).unwrap();
    let file = scene.to_file();
    let clay = &file.materials["clay"];
    // Saved resolved, every key written beside the preset, so retuning
    // presets later does not change saved scenes.
    assert_eq!(clay.preset, Some(Preset::WetClay));
    assert_eq!(clay.roughness, 0.35);
    assert_eq!(clay.f0, Preset::WetClay.material().f0);
    let detail = clay.detail_map.as_ref().unwrap();
    assert_eq!(
        (detail.texture.as_str(), detail.green, detail.uv_offset),
        ("builtin:fingerprints", file::Green::Down, [0.5, 0.25])
    );
    let base = file.materials["pot"].base_color_map.as_ref().unwrap();
    assert_eq!((base.texture.as_str(), base.strength), ("textures/skin.png", 0.75));

    let text = file.to_toml().unwrap();
    assert!(
        text.contains("preset = \"wet-clay\"") && text.contains("f0 = ") && text.contains("wrap_color = "),
        "{text}"
    );
    assert!(
        text.contains("[materials.pot.base_color_map]\ntexture = \"textures/skin.png\"\n"),
        "{text}"
    );
    let saved = dir.write("saved.toml", &text);
    let mut reloaded = Scene::load(&saved).unwrap();
    reloaded.source = scene.source.clone();
    assert_eq!(reloaded, scene);

    // A file read with presets writes the preset back and reads the same.
    let file: SceneFile = toml::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(file.materials["pot"].preset, Some(Preset::Terracotta));
    let reread: SceneFile = toml::from_str(&file.to_toml().unwrap()).unwrap();
    assert_eq!(reread, file);
}

// ------------------------------------------------------------------------ OBJ

const TRIANGLE_OBJ: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

fn load(contents: &str) -> Result<Mesh, SceneError> {
    let dir = TempDir::new();
    Mesh::load_obj(&dir.write("model.obj", contents))
}

fn obj_error(contents: &str) -> String {
    let dir = TempDir::new();
    let path = dir.write("model.obj", contents);
    let message = Mesh::load_obj(&path).unwrap_err().to_string();
    let prefix = format!("{}: ", path.display());
    message
        .strip_prefix(&prefix)
        .unwrap_or_else(|| panic!("{message}"))
        .to_owned()
}

/// The guarantees every loaded vertex must meet.
fn assert_valid(mesh: &Mesh) {
    for v in &mesh.vertices {
        let n = Vec3::from(v.normal);
        let t = Vec4::from(v.tangent);
        assert!(n.is_finite() && t.is_finite());
        assert!((n.length() - 1.0).abs() < 1e-5 && (t.truncate().length() - 1.0).abs() < 1e-5);
        assert!(n.dot(t.truncate()).abs() < 1e-5 && t.w.abs() == 1.0, "{v:?}");
    }
}

#[test]
fn obj_quad_with_normals_and_uvs() {
    let mesh = load(
        "# a unit quad\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
         f 1/1/1 2/2/1 3/3/1 4/4/1\n",
    )
    .unwrap();
    assert!(mesh.name.ends_with("model.obj"));
    assert_eq!(mesh.vertices.len(), 4);
    assert_eq!(mesh.indices, [0, 1, 2, 0, 2, 3]);
    assert_eq!(mesh.vertices[2].position, [1.0, 1.0, 0.0]);
    assert_eq!(mesh.vertices[2].uv, [1.0, 1.0]);
    for v in &mesh.vertices {
        assert_eq!(v.normal, [0.0, 0.0, 1.0]);
        assert_eq!(v.tangent, [1.0, 0.0, 0.0, 1.0]);
    }
}

#[test]
fn obj_mirrored_uvs_flip_handedness() {
    let mesh = load(
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
         vt 1 0\nvt 0 0\nvt 0 1\nvt 1 1\n\
         f 1/1 2/2 3/3 4/4\n",
    )
    .unwrap();
    assert_valid(&mesh);
    for v in &mesh.vertices {
        assert_eq!(v.tangent, [-1.0, 0.0, 0.0, -1.0]);
    }
}

#[test]
fn obj_without_normals_gets_smooth_normals() {
    // A tetrahedron corner: three faces meeting at the origin, facing
    // -x, -y and -z, so the shared vertex's normal is their average.
    let mesh = load(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
         f 1 3 2\nf 1 4 3\nf 1 2 4\n",
    )
    .unwrap();
    assert_valid(&mesh);
    assert_eq!(mesh.vertices.len(), 4);
    let corner = Vec3::from(mesh.vertices[0].normal);
    assert!(corner.abs_diff_eq(Vec3::splat(-1.0).normalize(), 1e-6), "{corner}");
    // Without UVs the tangent is some unit vector orthogonal to the normal.
    assert!(mesh.vertices.iter().all(|v| v.uv == [0.0, 0.0]));
}

#[test]
fn obj_zero_normal_is_replaced_by_the_face_normal() {
    let mesh = load("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0\nf 1//1 2//1 3//1\n").unwrap();
    assert_valid(&mesh);
    for v in &mesh.vertices {
        assert_eq!(v.normal, [0.0, 0.0, 1.0]);
    }
}

#[test]
fn obj_degenerate_faces_stay_finite() {
    let mesh = load(
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nvt 0 0\nvt 0 0\nvt 0 0\nvn 0 0 0\n\
         f 1/1/1 2/2/1 3/3/1\nf 1/1 2/2 4/3\n",
    )
    .unwrap();
    assert_valid(&mesh);
}

#[test]
fn obj_models_are_merged() {
    let mesh = load(
        "o first\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n\
         o second\nv 0 0 1\nv 1 0 1\nv 0 1 1\nvt 0 0\nvt 1 0\nvt 0 1\nf 4/1 5/2 6/3\n\
         g third\nusemtl missing\nmtllib missing.mtl\nf -3/1 -2/2 -1/3\nl 1 2\np 3\n",
    )
    .unwrap();
    assert_valid(&mesh);
    assert_eq!(mesh.indices.len(), 9);
    assert_eq!(mesh.vertices.len(), 9);
    assert!(mesh.indices.iter().all(|&i| (i as usize) < mesh.vertices.len()));
    let positions: Vec<[f32; 3]> = mesh
        .indices
        .iter()
        .map(|&i| mesh.vertices[i as usize].position)
        .collect();
    assert_eq!(positions[3], [0.0, 0.0, 1.0]);
    assert_eq!(positions[8], [0.0, 1.0, 1.0]);
    // The first object had no UVs: fallback tangents, zero UVs; the others
    // follow theirs.
    assert_eq!(mesh.vertices[mesh.indices[0] as usize].uv, [0.0, 0.0]);
    assert_eq!(mesh.vertices[mesh.indices[4] as usize].tangent, [1.0, 0.0, 0.0, 1.0]);
}

#[test]
fn broken_obj_files_are_reported() {
    assert_eq!(obj_error(""), "no triangles");
    assert_eq!(obj_error("v 0 0 0\nv 1 0 0\n"), "no triangles");
    assert_eq!(obj_error("v 0 0 0\nv 1 0 0\nl 1 2\n"), "no triangles");
    assert_eq!(obj_error("v 0 0\nf 1 1 1\n"), "invalid OBJ: position parse error");
    assert_eq!(
        obj_error("v 0 0 0\nv 1 0 0\nf 1 2 x\n"),
        "invalid OBJ: face parse error"
    );
    assert!(obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n").starts_with("invalid OBJ: face vertex"));
    assert!(obj_error(&format!("{TRIANGLE_OBJ}vt 0 0\nf 1/2 2/1 3/1\n")).starts_with("invalid OBJ: face texcoord"));
    assert_eq!(
        obj_error("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
        "vertex 1: position [NaN, 0.0, 0.0] is not finite"
    );
    assert_eq!(
        obj_error("v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n"),
        "vertex 2: position [0.0, inf, 0.0] is not finite"
    );
    assert_eq!(
        obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 nan 1\nf 1//1 2//1 3//1\n"),
        "vertex 0: normal [0.0, NaN, 1.0] is not finite"
    );
    // Lines tobj does not recognise are skipped.
    assert_eq!(obj_error("\u{0}\u{1}binary\n"), "no triangles");
}

#[test]
fn missing_obj_is_reported_with_the_object_and_the_file() {
    let dir = TempDir::new();
    let message = Scene::from_toml("[[objects]]\nmesh = \"models/pot.obj\"\n", "s.toml", &dir.0)
        .unwrap_err()
        .to_string();
    let expected = format!(
        "s.toml: objects[0].mesh = \"models/pot.obj\": {}: cannot read: ",
        dir.0.join("models/pot.obj").display()
    );
    assert!(message.starts_with(&expected), "{message}");
}

#[test]
fn broken_obj_in_a_scene_is_reported_with_the_object_and_the_file() {
    let dir = TempDir::new();
    let obj = dir.write("bad.obj", "v 0 0 0\nf 1 2 3\n");
    let message = Scene::from_toml(&format!("{CUBE}[[objects]]\nmesh = \"bad.obj\"\n"), "s.toml", &dir.0)
        .unwrap_err()
        .to_string();
    assert_eq!(
        message,
        format!(
            "s.toml: objects[1].mesh = \"bad.obj\": {}: invalid OBJ: face vertex index out of bounds",
            obj.display()
        )
    );
}

/// `[shadows] bounce` is read, defaults to off, is saved only when on, and picks the largest
/// `builtin:plane` as the ground (none without a plane or with bounce off).
#[test]
fn bounce_is_read_defaulted_saved_and_finds_the_largest_plane() {
    let planes = "[[objects]]\nmesh = \"builtin:plane\"\nscale = 2.0\n\
                  [[objects]]\nmesh = \"builtin:plane\"\nscale = 6.0\nposition = [0.0, -1.0, 0.0]\n";
    let text = format!("{CUBE}{planes}[shadows]\nbounce = true\n");
    let scene = Scene::from_toml(&text, "scene.toml", Path::new("")).unwrap();
    assert!(scene.bounce);
    let ground = scene.bounce_ground().expect("a ground");
    assert_eq!((ground.scale, ground.position.y), (6.0, -1.0));
    let saved = scene.to_file().to_toml().unwrap();
    assert!(
        saved.contains("bounce = true") && !saved.contains("resolution"),
        "{saved}"
    );
    assert!(Scene::from_toml(&saved, "saved.toml", Path::new("")).unwrap().bounce);
    let off = Scene::from_toml(&format!("{CUBE}{planes}"), "scene.toml", Path::new("")).unwrap();
    assert!(!off.bounce && off.bounce_ground().is_none());
    assert!(!off.to_file().to_toml().unwrap().contains("[shadows]"));
    let no_plane = Scene::from_toml(&format!("{CUBE}[shadows]\nbounce = true\n"), "s.toml", Path::new("")).unwrap();
    assert!(no_plane.bounce_ground().is_none());
}

/// The builtin sphere at its 32 cells and the torus gather the bounce at their vertices; a
/// sphere of 16 cells and the cube, whose edges are long beside them, at their pixels.
#[test]
fn fine_meshes_gather_the_bounce_at_their_vertices() {
    let share = |mesh: Mesh| {
        let extent = mesh.extent();
        (extent.longest_edge / extent.radius, Scene::bounce_at_vertices(extent))
    };
    let builtin = |name: &str| Mesh::builtin(&format!("{BUILTIN_PREFIX}{name}")).expect("a builtin mesh");
    let (sphere, torus) = (share(builtin("sphere")), share(builtin("torus")));
    let (coarse, cube) = (share(Mesh::sphere(16)), share(builtin("cube")));
    eprintln!("longest edge over radius: sphere {sphere:?}, torus {torus:?}, 16 cells {coarse:?}, cube {cube:?}");
    assert!(sphere.1 && torus.1 && !coarse.1 && !cube.1);
}

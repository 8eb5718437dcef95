//! The viewer's UI: a panel on the left with the scene, camera, materials, lights,
//! environment, debug view and timings, and a keyboard help window. Widgets edit the
//! scene in place; the renderer uploads materials and lights every frame, so edits are live.

use std::ops::RangeInclusive;

use egui::{Color32, RichText, Ui};
use glam::Vec3;
use serde::Serialize;

use super::camera_control::{CameraControl, Mode};
use super::timings::Timings;
use crate::render::gpu_scene::MAX_POINT_LIGHTS;
use crate::render::DebugView;
use crate::scene::{
    DetailBlend, DiffuseModel, Distribution, Environment, Geometry, Horizon, MapRef, Material, PointLight, Reflection,
    ReflectionMode, Scene, SpecularModel, Subsurface,
};

/// Width of the left panel in points; nothing of the UI is drawn right of it, but for its
/// border line straddling the edge, unless the help window is open.
pub const PANEL_WIDTH: f32 = 320.0;

const DIFFUSE_MODELS: [DiffuseModel; 4] = [
    DiffuseModel::Lambert,
    DiffuseModel::OrenNayar,
    DiffuseModel::Eon,
    DiffuseModel::None,
];
const SPECULAR_MODELS: [SpecularModel; 4] = [
    SpecularModel::CookTorrance,
    SpecularModel::TorranceSparrow,
    SpecularModel::BlinnPhong,
    SpecularModel::None,
];
const DISTRIBUTIONS: [Distribution; 2] = [Distribution::Ggx, Distribution::Beckmann];
const GEOMETRIES: [Geometry; 2] = [Geometry::SmithCorrelated, Geometry::SmithSeparable];
const SUBSURFACE_MODELS: [Subsurface; 4] = [
    Subsurface::None,
    Subsurface::Seed,
    Subsurface::EnergyConservingWrap,
    Subsurface::PreIntegrated,
];

/// The keys of the viewer, for the help window.
pub const KEYS: &[(&str, &str)] = &[
    ("W A S D", "fly forward / left / back / right (orbit: zoom, turn)"),
    ("Q E", "down / up (orbit: tilt)"),
    ("right mouse button", "look around (orbit: turn around the object)"),
    ("wheel", "fly speed (orbit: zoom)"),
    ("Shift", "faster"),
    ("Tab or O", "fly / orbit around the selected object"),
    ("F", "frame the scene"),
    ("F12", "screenshot of the frame without UI"),
    ("Ctrl+S", "save the scene to its file"),
    ("H or F1", "this help"),
];

/// What the UI shows and remembers besides the scene.
pub struct ViewState {
    pub debug_view: DebugView,
    /// Whether the lights cast shadows (the renderer's toggle).
    pub shadows: bool,
    pub exposure: f32,
    /// The object the orbit mode circles.
    pub selected_object: usize,
    /// The material the material panel edits.
    pub selected_material: usize,
    pub show_help: bool,
    /// The last failure: a scene file that does not load, a save or screenshot that failed.
    pub error: Option<String>,
    /// The last success worth telling: saved, reloaded, screenshot written.
    pub notice: Option<String>,
    pub timings: Timings,
    pub device_name: String,
    /// Where Save writes.
    pub save_path: String,
}

impl ViewState {
    /// Keeps the selections valid for a scene (after a reload).
    pub fn clamp_selection(&mut self, scene: &Scene) {
        if self.selected_object >= scene.objects.len() {
            self.selected_object = 0;
        }
        if self.selected_material >= scene.materials.len() {
            self.selected_material = 0;
        }
    }
}

/// What the user asked for through the UI this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Actions {
    pub save: bool,
    pub screenshot: bool,
    pub frame_scene: bool,
}

/// Splits an RGB quantity into a colour whose largest component is 1 (white for black) and
/// the scale that multiplies it back.
pub fn split_color(v: Vec3) -> (Vec3, f32) {
    let scale = v.max_element();
    if scale > 0.0 {
        (v / scale, scale)
    } else {
        (Vec3::ONE, 0.0)
    }
}

/// The name of a model choice as the scene file spells it (`"oren-nayar"`).
pub fn file_name<T: Serialize>(value: &T) -> String {
    match toml::Value::try_from(value) {
        Ok(toml::Value::String(s)) => s,
        _ => "?".to_owned(),
    }
}

/// Shows the whole UI for one frame.
pub fn show(ui: &mut Ui, scene: &mut Scene, view: &mut ViewState, camera: &mut CameraControl) -> Actions {
    let mut actions = Actions::default();
    egui::Panel::left("argil-panel")
        .exact_size(PANEL_WIDTH)
        .resizable(false)
        .show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                scene_section(ui, view, &mut actions);
                section(ui, "Camera", true, |ui| {
                    camera_section(ui, scene, view, camera, &mut actions)
                });
                section(ui, "Materials", true, |ui| materials_section(ui, scene, view));
                section(ui, "Lights", false, |ui| lights_section(ui, scene));
                section(ui, "Shadows", false, |ui| {
                    super::shadow_panel::shadows_section(ui, scene, &mut view.shadows)
                });
                section(ui, "Environment", false, |ui| environment_section(ui, scene));
                section(ui, "Debug view", true, |ui| debug_section(ui, view));
                section(ui, "Timings", true, |ui| timings_section(ui, view));
            });
        });
    let mut open = view.show_help;
    egui::Window::new("Keyboard")
        .open(&mut open)
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::RIGHT_TOP, [-10.0, 10.0])
        .show(ui.ctx(), |ui| {
            grid(ui, "keys", |ui| {
                for (key, what) in KEYS {
                    ui.label(RichText::new(*key).strong());
                    ui.label(*what);
                    ui.end_row();
                }
            });
        });
    view.show_help = open;
    actions
}

fn section(ui: &mut Ui, title: &str, open: bool, body: impl FnOnce(&mut Ui)) {
    egui::CollapsingHeader::new(title).default_open(open).show(ui, body);
}

fn grid(ui: &mut Ui, id: &str, rows: impl FnOnce(&mut Ui)) {
    egui::Grid::new(id).num_columns(2).striped(true).show(ui, rows);
}

fn scene_section(ui: &mut Ui, view: &mut ViewState, actions: &mut Actions) {
    ui.heading("argil");
    ui.label(format!("file: {}", view.save_path));
    ui.horizontal(|ui| {
        actions.save |= ui.button("Save (Ctrl+S)").clicked();
        actions.screenshot |= ui.button("Screenshot (F12)").clicked();
        if ui.button("Help (H)").clicked() {
            view.show_help = !view.show_help;
        }
    });
    if let Some(error) = &view.error {
        ui.colored_label(Color32::from_rgb(255, 110, 110), error);
        ui.label("The last good scene stays on screen.");
    } else if let Some(notice) = &view.notice {
        ui.label(notice);
    }
    ui.separator();
}

fn camera_section(ui: &mut Ui, scene: &Scene, view: &mut ViewState, camera: &mut CameraControl, actions: &mut Actions) {
    ui.horizontal(|ui| {
        ui.radio_value(&mut camera.mode, Mode::Fly, "fly");
        ui.radio_value(&mut camera.mode, Mode::Orbit, "orbit (Tab)");
        actions.frame_scene |= ui.button("Frame (F)").clicked();
    });
    grid(ui, "camera", |ui| {
        ui.label("fly speed");
        ui.add(
            egui::DragValue::new(&mut camera.speed)
                .speed(0.05)
                .range(0.05..=200.0)
                .suffix(" /s"),
        );
        ui.end_row();
        ui.label("orbit around");
        let name = |i: usize| object_name(scene, i);
        egui::ComboBox::from_id_salt("object")
            .selected_text(name(view.selected_object))
            .show_ui(ui, |ui| {
                for i in 0..scene.objects.len() {
                    if ui.selectable_value(&mut view.selected_object, i, name(i)).clicked() {
                        view.selected_material = scene.objects[i].material;
                    }
                }
            });
        ui.end_row();
        ui.label("exposure");
        ui.add(egui::Slider::new(&mut view.exposure, 0.05..=20.0).logarithmic(true));
        ui.end_row();
    });
}

fn object_name(scene: &Scene, i: usize) -> String {
    let o = &scene.objects[i];
    format!(
        "{i}: {} ({})",
        scene.meshes[o.mesh].name, scene.materials[o.material].name
    )
}

fn materials_section(ui: &mut Ui, scene: &mut Scene, view: &mut ViewState) {
    let Some(selected) = scene.materials.get(view.selected_material).map(|m| m.name.clone()) else {
        return;
    };
    egui::ComboBox::from_id_salt("material")
        .selected_text(selected)
        .show_ui(ui, |ui| {
            for (i, m) in scene.materials.iter().enumerate() {
                ui.selectable_value(&mut view.selected_material, i, m.name.as_str());
            }
        });
    if let Some(m) = scene.materials.get_mut(view.selected_material) {
        grid(ui, "material", |ui| material_fields(ui, m));
    }
}

/// One line per material parameter, named as in the scene file.
fn material_fields(ui: &mut Ui, m: &mut Material) {
    choice(ui, "diffuse", &mut m.diffuse, &DIFFUSE_MODELS);
    choice(ui, "specular", &mut m.specular, &SPECULAR_MODELS);
    choice(ui, "distribution", &mut m.distribution, &DISTRIBUTIONS);
    choice(ui, "geometry", &mut m.geometry, &GEOMETRIES);
    color(ui, "base_color", &mut m.base_color);
    number(ui, "roughness", &mut m.roughness, 0.0..=1.0);
    number(ui, "f0", &mut m.f0, 0.0..=1.0);
    number(ui, "diffuse_roughness", &mut m.diffuse_roughness, 0.0..=1.0);
    color(ui, "specular_color", &mut m.specular_color);
    number(ui, "wrap", &mut m.wrap, 0.0..=1.0);
    number(ui, "wrap_width", &mut m.wrap_width, 0.01..=1.0);
    color(ui, "wrap_color", &mut m.wrap_color);
    number(ui, "wrap_intensity", &mut m.wrap_intensity, 0.0..=4.0);
    choice(ui, "subsurface", &mut m.subsurface, &SUBSURFACE_MODELS);
    color(ui, "scatter_color", &mut m.scatter_color);
    number(ui, "scatter_radius", &mut m.scatter_radius, 0.0..=2.0);
    choice(ui, "horizon", &mut m.horizon, &[Horizon::Smooth, Horizon::Seed]);
    let maps = &mut m.maps;
    if maps.detail.is_some() {
        let blends = [
            DetailBlend::Rnm,
            DetailBlend::Udn,
            DetailBlend::Whiteout,
            DetailBlend::Seed,
        ];
        choice(ui, "detail_blend", &mut maps.detail_blend, &blends);
    }
    // A map's texture is fixed by the scene file; its parameters are live.
    for (name, map) in [
        ("base_color_map", &mut maps.base_color),
        ("normal_map", &mut maps.normal),
        ("detail_map", &mut maps.detail),
        ("noise_map", &mut maps.noise),
    ] {
        if let Some(map) = map {
            map_fields(ui, name, map);
        }
    }
}

fn map_fields(ui: &mut Ui, name: &str, map: &mut MapRef) {
    number(ui, &format!("{name}.strength"), &mut map.strength, 0.0..=8.0);
    ui.label(format!("{name}.uv_scale"));
    ui.horizontal(|ui| {
        ui.add(egui::DragValue::new(&mut map.uv_scale.x).speed(0.05).range(0.01..=1e4));
        ui.add(egui::DragValue::new(&mut map.uv_scale.y).speed(0.05).range(0.01..=1e4));
    });
    ui.end_row();
    ui.label(format!("{name}.uv_offset"));
    ui.horizontal(|ui| {
        ui.add(egui::DragValue::new(&mut map.uv_offset.x).speed(0.01));
        ui.add(egui::DragValue::new(&mut map.uv_offset.y).speed(0.01));
    });
    ui.end_row();
    if name != "base_color_map" && name != "noise_map" {
        ui.label(format!("{name}.green"));
        ui.checkbox(&mut map.green_down, "down (DirectX)");
        ui.end_row();
    }
}

fn choice<T: Copy + PartialEq + Serialize>(ui: &mut Ui, label: &str, value: &mut T, options: &[T]) {
    ui.label(label);
    egui::ComboBox::from_id_salt(label)
        .selected_text(file_name(value))
        .show_ui(ui, |ui| {
            for option in options {
                ui.selectable_value(value, *option, file_name(option));
            }
        });
    ui.end_row();
}

fn number(ui: &mut Ui, label: &str, value: &mut f32, range: RangeInclusive<f32>) {
    ui.label(label);
    ui.add(egui::Slider::new(value, range));
    ui.end_row();
}

/// A linear RGB colour picker; the value is written only when the user changes it.
fn color(ui: &mut Ui, label: &str, value: &mut Vec3) {
    ui.label(label);
    let mut rgb = value.to_array();
    if ui.color_edit_button_rgb(&mut rgb).changed() {
        *value = Vec3::from(rgb);
    }
    ui.end_row();
}

/// A colour and a scale (e.g. W/sr) that multiply into `value`, written only when changed.
fn scaled_color(ui: &mut Ui, label: &str, value: &mut Vec3, unit: &str) {
    let (mut tint, mut scale) = split_color(*value);
    color(ui, &format!("{label} colour"), &mut tint);
    ui.label(label);
    let speed = (scale * 0.01).max(0.001);
    if ui
        .add(
            egui::DragValue::new(&mut scale)
                .speed(speed)
                .range(0.0..=1e5)
                .suffix(unit),
        )
        .changed()
        | (tint != split_color(*value).0)
    {
        *value = tint * scale;
    }
    ui.end_row();
}

fn vector(ui: &mut Ui, label: &str, value: &mut Vec3) {
    ui.label(label);
    ui.horizontal(|ui| {
        for c in value.as_mut() {
            ui.add(egui::DragValue::new(c).speed(0.05).max_decimals(3));
        }
    });
    ui.end_row();
}

fn lights_section(ui: &mut Ui, scene: &mut Scene) {
    for (i, light) in scene.lights.iter_mut().enumerate() {
        ui.label(RichText::new(format!("light {i}")).strong());
        grid(ui, &format!("light {i}"), |ui| {
            vector(ui, "position", &mut light.position);
            scaled_color(ui, "intensity", &mut light.intensity, " W/sr");
        });
    }
    ui.horizontal(|ui| {
        if scene.lights.len() < MAX_POINT_LIGHTS && ui.button("Add a light").clicked() {
            scene.lights.push(PointLight::new(scene.camera.position, Vec3::splat(20.0)));
        }
        if !scene.lights.is_empty() && ui.button("Remove the last").clicked() {
            scene.lights.pop();
        }
    });
}

/// The environment kinds the panel can switch between; a map needs a file, so it is only
/// kept, never chosen.
#[derive(Clone, Copy, PartialEq)]
enum EnvironmentKind {
    None,
    Uniform,
    Studio,
    Map,
}

fn environment_section(ui: &mut Ui, scene: &mut Scene) {
    let kind = match &scene.environment {
        Environment::None => EnvironmentKind::None,
        Environment::Uniform { .. } => EnvironmentKind::Uniform,
        Environment::Studio { .. } => EnvironmentKind::Studio,
        Environment::Map { .. } => EnvironmentKind::Map,
    };
    let mut chosen = kind;
    ui.horizontal(|ui| {
        ui.radio_value(&mut chosen, EnvironmentKind::None, "none");
        ui.radio_value(&mut chosen, EnvironmentKind::Uniform, "uniform");
        ui.radio_value(&mut chosen, EnvironmentKind::Studio, "studio");
        if kind == EnvironmentKind::Map {
            ui.radio_value(&mut chosen, EnvironmentKind::Map, "map");
        }
    });
    if chosen != kind {
        let reflection = scene.environment.reflection().copied().unwrap_or_default();
        scene.environment = match chosen {
            EnvironmentKind::Uniform => Environment::Uniform {
                radiance: Vec3::splat(0.05),
                reflection,
            },
            EnvironmentKind::Studio => Environment::Studio {
                intensity: 1.0,
                rotation_degrees: 0.0,
                reflection,
            },
            EnvironmentKind::None | EnvironmentKind::Map => Environment::None,
        };
    }
    let reflection = match &mut scene.environment {
        Environment::None => return,
        Environment::Uniform { radiance, reflection } => {
            grid(ui, "environment", |ui| {
                scaled_color(ui, "radiance", radiance, " W/sr/m²")
            });
            reflection
        }
        Environment::Studio {
            intensity,
            rotation_degrees,
            reflection,
        }
        | Environment::Map {
            intensity,
            rotation_degrees,
            reflection,
            ..
        } => {
            grid(ui, "environment", |ui| {
                number(ui, "intensity", intensity, 0.0..=8.0);
                number(ui, "rotation °", rotation_degrees, -180.0..=180.0);
            });
            reflection
        }
    };
    grid(ui, "reflection", |ui| {
        ui.label("reflection");
        egui::ComboBox::from_id_salt("reflection mode")
            .selected_text(format!("{:?}", reflection.mode))
            .show_ui(ui, |ui| {
                for mode in [ReflectionMode::SplitSum, ReflectionMode::Seed, ReflectionMode::Sampled] {
                    ui.selectable_value(&mut reflection.mode, mode, format!("{mode:?}"));
                }
            });
        ui.end_row();
        match reflection.mode {
            ReflectionMode::Sampled => {
                ui.label("samples");
                ui.add(egui::Slider::new(&mut reflection.samples, 1..=Reflection::MAX_SAMPLES).logarithmic(true));
                ui.end_row();
            }
            ReflectionMode::Seed => number(ui, "seed strength", &mut reflection.seed_strength, 0.0..=1.0),
            ReflectionMode::SplitSum => {}
        }
    });
}

fn debug_section(ui: &mut Ui, view: &mut ViewState) {
    egui::ComboBox::from_id_salt("debug view")
        .selected_text(view.debug_view.label())
        .show_ui(ui, |ui| {
            for v in DebugView::ALL {
                ui.selectable_value(&mut view.debug_view, v, v.label());
            }
        });
}

fn timings_section(ui: &mut Ui, view: &ViewState) {
    ui.label(&view.device_name);
    let mean = view.timings.mean();
    grid(ui, "timings", |ui| {
        ui.label("CPU frame");
        ui.label(format!("{:.2} ms", mean.cpu_ms));
        ui.end_row();
        for (name, ms) in view.timings.pass_names.iter().zip(&mean.gpu_ms) {
            ui.label(format!("GPU {name}"));
            ui.label(format!("{ms:.2} ms"));
            ui.end_row();
        }
    });
    history_graph(ui, &view.timings);
}

const CPU_COLOR: Color32 = Color32::from_rgb(120, 200, 255);
const GPU_COLOR: Color32 = Color32::from_rgb(255, 170, 80);

/// CPU frame time and total GPU time of the last frames, scaled to the peak.
fn history_graph(ui: &mut Ui, timings: &Timings) {
    let size = egui::vec2(ui.available_width(), 60.0);
    let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, Color32::from_gray(20));
    let peak = timings.peak_ms().max(1e-3);
    let n = timings.history().len();
    let point = |i: usize, ms: f64| {
        let x = rect.right() - (n - 1 - i) as f32 * rect.width() / super::timings::HISTORY as f32;
        egui::pos2(x, rect.bottom() - (ms / peak) as f32 * rect.height())
    };
    let cpu = timings.history().enumerate().map(|(i, t)| point(i, t.cpu_ms)).collect();
    let gpu = timings
        .history()
        .enumerate()
        .map(|(i, t)| point(i, t.gpu_total_ms()))
        .collect();
    painter.add(egui::Shape::line(cpu, egui::Stroke::new(1.0, CPU_COLOR)));
    painter.add(egui::Shape::line(gpu, egui::Stroke::new(1.0, GPU_COLOR)));
    ui.horizontal(|ui| {
        ui.colored_label(CPU_COLOR, "CPU frame");
        ui.colored_label(GPU_COLOR, "GPU total");
        ui.label(format!("peak {peak:.1} ms"));
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state() -> ViewState {
        ViewState {
            debug_view: DebugView::Shaded,
            shadows: true,
            exposure: 1.0,
            selected_object: 0,
            selected_material: 0,
            show_help: false,
            error: Some("scene.toml: materials.clay.roughness = 2.0: must be a finite number in [0, 1]".into()),
            notice: None,
            timings: Timings::new(vec!["forward", "tonemap", "ui"]),
            device_name: "test device".into(),
            save_path: "scene.toml".into(),
        }
    }

    /// The rightmost x any drawn triangle reaches, within its clip rectangle.
    fn right_edge(primitives: &[egui::ClippedPrimitive]) -> f32 {
        primitives
            .iter()
            .filter_map(|p| match &p.primitive {
                egui::epaint::Primitive::Mesh(m) => {
                    let right = m.vertices.iter().map(|v| v.pos.x).fold(f32::MIN, f32::max);
                    Some(right.min(p.clip_rect.max.x))
                }
                egui::epaint::Primitive::Callback(_) => None,
            })
            .fold(0.0, f32::max)
    }

    /// Runs the UI for a few frames without a window and returns the tessellated meshes.
    fn run(scene: &mut Scene, view: &mut ViewState) -> Vec<egui::ClippedPrimitive> {
        let ctx = egui::Context::default();
        let mut camera = CameraControl::default();
        let mut primitives = Vec::new();
        for _ in 0..3 {
            let input = egui::RawInput {
                screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1280.0, 720.0))),
                ..Default::default()
            };
            let output = ctx.run_ui(input, |ui| {
                let actions = show(ui, scene, view, &mut camera);
                assert_eq!(actions, Actions::default(), "nothing clicked");
            });
            primitives = ctx.tessellate(output.shapes, output.pixels_per_point);
        }
        primitives
    }

    #[test]
    fn the_panel_stays_left_of_its_width_and_leaves_the_scene_alone() {
        let mut scene = Scene::default_scene();
        let before = scene.clone();
        let mut view = state();
        let primitives = run(&mut scene, &mut view);
        assert!(!primitives.is_empty());
        let right = right_edge(&primitives);
        assert!(right <= PANEL_WIDTH + 1.0, "the UI reaches x = {right}");
        assert_eq!(scene, before, "showing the UI changes nothing");
    }

    #[test]
    fn help_window_opens_at_the_right() {
        let mut scene = Scene::default_scene();
        let mut view = ViewState {
            show_help: true,
            ..state()
        };
        let primitives = run(&mut scene, &mut view);
        let right = right_edge(&primitives);
        assert!(right > 1000.0, "help window at x = {right}");
        assert!(view.show_help);
    }

    #[test]
    fn colours_split_into_tint_and_scale() {
        let (tint, scale) = split_color(Vec3::new(32.0, 30.0, 27.0));
        assert_eq!(scale, 32.0);
        assert_eq!(tint.max_element(), 1.0);
        assert!((tint * scale - Vec3::new(32.0, 30.0, 27.0)).length() < 1e-5);
        assert_eq!(split_color(Vec3::ZERO), (Vec3::ONE, 0.0));
    }

    #[test]
    fn model_names_are_the_scene_files() {
        assert_eq!(file_name(&DiffuseModel::OrenNayar), "oren-nayar");
        assert_eq!(file_name(&SpecularModel::CookTorrance), "cook-torrance");
        assert_eq!(file_name(&Geometry::SmithSeparable), "smith-separable");
    }

    #[test]
    fn selections_are_clamped_to_a_reloaded_scene() {
        let scene = Scene::default_scene();
        let mut view = ViewState {
            selected_object: 99,
            selected_material: 7,
            ..state()
        };
        view.clamp_selection(&scene);
        assert_eq!((view.selected_object, view.selected_material), (0, 0));
    }
}

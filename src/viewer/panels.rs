//! The viewer's UI: a panel on the left with the scene, camera, materials, lights,
//! environment, debug view and timings, and a keyboard help window. Widgets edit the
//! scene in place; the renderer uploads materials and lights every frame, so edits are live.

use std::ops::RangeInclusive;
use std::path::PathBuf;

use egui::{Color32, RichText, Ui};
use glam::Vec3;
use serde::Serialize;

use super::camera_control::{CameraControl, Mode};
use super::rebuild::Rebuild;
use super::timings::Timings;
use crate::render::accumulate::{Accumulated, CONVERGED_LOOKUPS};
use crate::render::exposure::PERCENTILE;
use crate::render::gpu_scene::MAX_POINT_LIGHTS;
use crate::render::DebugView;
pub use crate::scene::file::file_name;
use crate::scene::map_slots::{SlotInfo, SLOTS};
use crate::scene::material_keys::{Edit, MAP_STRENGTH, MAX_UV_SCALE};
use crate::scene::{Environment, MapRef, Material, PointLight, Preset, Reflection, ReflectionMode, Scene, TextureRole};

/// Width of the left panel in points when the viewer opens; it can be dragged wider or
/// narrower, or collapsed.
pub const PANEL_WIDTH: f32 = 320.0;
const PANEL_WIDTHS: RangeInclusive<f32> = 200.0..=600.0;

const REFLECTION_MODES: [ReflectionMode; 3] = [ReflectionMode::SplitSum, ReflectionMode::Seed, ReflectionMode::Sampled];

/// The keys of the viewer, for the help window.
pub const KEYS: &[(&str, &str)] = &[
    ("W A S D", "fly forward / left / back / right (orbit: zoom, turn)"),
    ("Q E", "down / up (orbit: tilt)"),
    ("right mouse button", "look around (orbit: turn around the object)"),
    ("wheel", "fly speed (orbit: zoom)"),
    ("Shift", "faster"),
    ("Tab or O", "fly / orbit around the selected object"),
    ("F", "frame the objects (the selected one in orbit mode)"),
    ("R", "back to the camera of the scene file"),
    ("U", "hide / show all UI"),
    ("V", "split view: the right half in another configuration"),
    ("F12", "screenshot of the frame without UI"),
    ("Ctrl+S", "save the scene to its file"),
    ("Ctrl+Z, Ctrl+Y", "undo, redo an edit"),
    ("H or F1", "this help"),
    ("Esc", "quit (asks when there are unsaved changes)"),
];

/// A question the viewer waits for the user to answer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Question {
    /// Save would replace this file, which is not the scene's own.
    Overwrite(PathBuf),
    /// Quitting would lose unsaved changes.
    Quit,
    /// The scene file changed on disk; reading it would lose unsaved changes.
    Reload,
}

/// What the UI shows and remembers besides the scene.
pub struct ViewState {
    pub debug_view: DebugView,
    /// Whether the lights cast shadows (the renderer's toggle).
    pub shadows: bool,
    /// Samples per pixel the device draws the scene's `msaa` with.
    pub msaa_samples: u32,
    /// Whether a scene's occlusion applies (the renderer's toggle).
    pub occlusion: bool,
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
    /// The scene file, absolute, or what Save does without one.
    pub file: String,
    /// The Save As field.
    pub save_as: String,
    pub question: Option<Question>,
    /// The scene differs from the file (camera aside).
    pub modified: bool,
    pub can_undo: bool,
    pub can_redo: bool,
    pub panel_open: bool,
    /// All UI hidden (the U key).
    pub hide_ui: bool,
    /// Where the 3D view is, in points: the window beside the panel. Set by [`show`].
    pub view_rect: egui::Rect,
    /// The frame's size in pixels, for the timings.
    pub frame_size: (u32, u32),
    /// The running mean of the sampled reflection as of the last frame drawn.
    pub accumulated: Option<Accumulated>,
    /// Whether debug views of radiance are exposed from their own luminance.
    pub auto_exposure: bool,
    /// The exposure of the last frame drawn: `exposure`, or the auto exposure's.
    pub exposure_in_use: f32,
    /// The Files section's path field.
    pub path: String,
    pub split: super::split_view::SplitView,
    pub reference: super::reference_view::ReferenceView,
}

impl ViewState {
    pub fn new(exposure: f32, timings: Timings, file: String) -> ViewState {
        ViewState {
            debug_view: DebugView::Shaded,
            shadows: true,
            msaa_samples: 1,
            occlusion: true,
            exposure,
            selected_object: 0,
            selected_material: 0,
            show_help: false,
            error: None,
            notice: None,
            timings,
            device_name: String::new(),
            save_as: String::new(),
            file,
            question: None,
            modified: false,
            can_undo: false,
            can_redo: false,
            panel_open: true,
            hide_ui: false,
            view_rect: egui::Rect::NOTHING,
            frame_size: (0, 0),
            accumulated: None,
            auto_exposure: true,
            exposure_in_use: exposure,
            path: String::new(),
            split: Default::default(),
            reference: Default::default(),
        }
    }

    /// Whether the frame is auto exposed: a debug view of radiance with auto exposure on.
    pub fn auto_exposed(&self) -> bool {
        self.auto_exposure && self.debug_view.is_radiance()
    }

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
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Actions {
    pub save: bool,
    /// Save to the Save As field's path.
    pub save_as: bool,
    /// Save to this path, replacing the file there (the user said so).
    pub overwrite: Option<PathBuf>,
    /// Quit: `Some(false)` asks first when there are changes, `Some(true)` discards them.
    pub quit: Option<bool>,
    pub screenshot: bool,
    pub frame_scene: bool,
    pub reset_view: bool,
    pub undo: bool,
    pub redo: bool,
    /// An edit of what the scene loads: a preset, a texture, an environment map, a mesh.
    pub rebuild: Option<Rebuild>,
    /// Read the scene file again, losing unsaved changes (the user said so).
    pub reload: bool,
}

impl Actions {
    /// Adds what `other` asks for.
    pub fn merge(&mut self, other: Actions) {
        self.save |= other.save;
        self.save_as |= other.save_as;
        self.overwrite = self.overwrite.take().or(other.overwrite);
        self.quit = match (self.quit, other.quit) {
            (Some(a), Some(b)) => Some(a || b),
            (a, b) => a.or(b),
        };
        self.screenshot |= other.screenshot;
        self.reload |= other.reload;
        self.frame_scene |= other.frame_scene;
        self.reset_view |= other.reset_view;
        self.undo |= other.undo;
        self.redo |= other.redo;
        self.rebuild = self.rebuild.take().or(other.rebuild);
    }
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

/// What a section of the panel edits.
pub struct Panel<'a> {
    pub scene: &'a mut Scene,
    pub view: &'a mut ViewState,
    pub camera: &'a mut CameraControl,
    pub actions: &'a mut Actions,
}

/// A section of the panel: its title, whether it starts open, and what draws it. A new
/// section is one function and one line in [`SECTIONS`].
type Section = (&'static str, bool, fn(&mut Ui, &mut Panel));

const SECTIONS: &[Section] = &[
    ("Camera", true, camera_section),
    ("Materials", true, materials_section),
    ("Lights", false, |ui, p| lights_section(ui, p.scene)),
    ("Shadows", false, |ui, p| {
        super::shadow_panel::shadows_section(ui, p.scene, &mut p.view.shadows)
    }),
    ("Anti-aliasing", false, |ui, p| {
        super::antialiasing_panel::antialiasing_section(ui, p.scene, p.view.msaa_samples)
    }),
    ("Occlusion", false, |ui, p| {
        super::occlusion_panel::occlusion_section(ui, p.scene, &mut p.view.occlusion)
    }),
    ("Environment", false, |ui, p| environment_section(ui, p.scene)),
    ("Files", false, files_section),
    ("Split view", false, |ui, p| {
        super::split_view::section(ui, &mut p.view.split)
    }),
    ("Reference", false, |ui, p| {
        super::reference_view::section(ui, &mut p.view.reference)
    }),
    ("Debug view", true, |ui, p| debug_section(ui, p.view)),
    ("Timings", true, |ui, p| timings_section(ui, p.view)),
];

/// Shows the whole UI for one frame; returns what was asked for, and sets
/// `view.view_rect` to the part of the window the panel leaves to the 3D view.
pub fn show(ui: &mut Ui, scene: &mut Scene, view: &mut ViewState, camera: &mut CameraControl) -> Actions {
    let mut actions = Actions::default();
    if view.hide_ui {
        view.view_rect = ui.available_rect_before_wrap();
        return actions;
    }
    let mut open = view.panel_open;
    egui::Panel::left("argil-panel")
        .resizable(true)
        .default_size(PANEL_WIDTH)
        .size_range(PANEL_WIDTHS)
        .show_collapsible(ui, &mut open, |ui| {
            let mut panel = Panel {
                scene,
                view,
                camera,
                actions: &mut actions,
            };
            // Above the scrolled sections, so that it is seen wherever the panel is scrolled.
            file_header(ui, &mut panel);
            egui::ScrollArea::vertical().show(ui, |ui| {
                for (title, open, body) in SECTIONS {
                    egui::CollapsingHeader::new(*title)
                        .default_open(*open)
                        .show(ui, |ui| body(ui, &mut panel));
                }
            });
        });
    view.panel_open = open;
    if !view.panel_open {
        egui::Area::new(egui::Id::new("argil-panel-open"))
            .anchor(egui::Align2::LEFT_TOP, [4.0, 4.0])
            .show(ui.ctx(), |ui| {
                if ui.button("▶ panel").on_hover_text("Show the panel again").clicked() {
                    view.panel_open = true;
                }
            });
    }
    view.view_rect = ui.available_rect_before_wrap();
    super::split_view::overlay(ui.ctx(), view.view_rect, &view.split);
    if view.debug_view == DebugView::Curvature {
        super::legend::show(ui.ctx(), view.view_rect, view.exposure_in_use);
    }
    help_window(ui, view);
    question_window(ui, view, &mut actions);
    actions
}

fn help_window(ui: &mut Ui, view: &mut ViewState) {
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
}

/// The question the viewer waits on, in the middle of the window, until answered.
fn question_window(ui: &mut Ui, view: &mut ViewState, actions: &mut Actions) {
    let Some(question) = view.question.clone() else { return };
    egui::Window::new("argil")
        .collapsible(false)
        .resizable(false)
        .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
        .show(ui.ctx(), |ui| match question {
            Question::Overwrite(path) => {
                ui.label(format!("{} already exists. Replace it?", path.display()));
                ui.horizontal(|ui| {
                    if ui.button("Replace").clicked() {
                        actions.overwrite = Some(path);
                        view.question = None;
                    }
                    if ui.button("Cancel").clicked() {
                        view.question = None;
                    }
                });
            }
            Question::Quit => {
                ui.label("The scene has unsaved changes.");
                ui.horizontal(|ui| {
                    if ui.button("Save and quit").clicked() {
                        actions.save = true;
                        actions.quit = Some(false);
                        view.question = None;
                    }
                    if ui.button("Quit without saving").clicked() {
                        actions.quit = Some(true);
                        view.question = None;
                    }
                    if ui.button("Cancel").clicked() {
                        view.question = None;
                    }
                });
            }
            Question::Reload => {
                ui.label("The scene file changed on disk, and the scene has unsaved changes.");
                ui.horizontal(|ui| {
                    if ui.button("Read the file, losing the changes").clicked() {
                        actions.reload = true;
                        view.question = None;
                    }
                    if ui.button("Keep the changes").clicked() {
                        view.question = None;
                    }
                });
            }
        });
}

fn grid(ui: &mut Ui, id: &str, rows: impl FnOnce(&mut Ui)) {
    egui::Grid::new(id).num_columns(2).striped(true).show(ui, rows);
}

/// The file, Save / Save As / undo, and the last error or notice.
fn file_header(ui: &mut Ui, p: &mut Panel) {
    let view = &mut *p.view;
    let actions = &mut *p.actions;
    ui.horizontal(|ui| {
        ui.heading("argil");
        if view.modified {
            ui.label(RichText::new("● modified").color(Color32::from_rgb(255, 200, 90)))
                .on_hover_text("The scene differs from its file (the camera aside); Ctrl+S saves it");
        }
    });
    ui.label(format!("file: {}", view.file));
    ui.horizontal_wrapped(|ui| {
        actions.save |= ui
            .button("Save (Ctrl+S)")
            .on_hover_text("Writes the edits into the scene file, keeping its comments, order and presets")
            .clicked();
        actions.undo |= ui.add_enabled(view.can_undo, egui::Button::new("Undo")).clicked();
        actions.redo |= ui.add_enabled(view.can_redo, egui::Button::new("Redo")).clicked();
        actions.screenshot |= ui
            .button("Shot (F12)")
            .on_hover_text("Writes argil-screenshot-N.png: the frame without UI")
            .clicked();
        if ui.button("Keys (H)").clicked() {
            view.show_help = !view.show_help;
        }
    });
    ui.horizontal(|ui| {
        ui.add(
            egui::TextEdit::singleline(&mut view.save_as)
                .hint_text("new-scene.toml")
                .desired_width(ui.available_width() - 70.0),
        )
        .on_hover_text("A path for Save As, relative to the working directory; the viewer then edits that file");
        actions.save_as |= ui
            .add_enabled(!view.save_as.trim().is_empty(), egui::Button::new("Save As"))
            .clicked();
    });
    if let Some(error) = &view.error {
        ui.colored_label(Color32::from_rgb(255, 110, 110), error);
    } else if let Some(notice) = &view.notice {
        ui.label(notice);
    }
    ui.separator();
}

fn camera_section(ui: &mut Ui, p: &mut Panel) {
    let (scene, view, camera, actions) = (&mut *p.scene, &mut *p.view, &mut *p.camera, &mut *p.actions);
    ui.horizontal_wrapped(|ui| {
        ui.radio_value(&mut camera.mode, Mode::Fly, "fly");
        ui.radio_value(&mut camera.mode, Mode::Orbit, "orbit (Tab)");
        actions.frame_scene |= ui
            .button("Frame (F)")
            .on_hover_text("Fits the objects other than the ground (orbit: the selected one) into the view")
            .clicked();
        actions.reset_view |= ui
            .button("Reset (R)")
            .on_hover_text("Back to the camera of the scene file")
            .clicked();
    });
    grid(ui, "camera", |ui| {
        ui.label("fly speed")
            .on_hover_text("Scene units per second; the wheel over the view changes it");
        ui.add(
            egui::DragValue::new(&mut camera.speed)
                .speed(0.05)
                .range(0.05..=200.0)
                .suffix(" /s"),
        );
        ui.end_row();
        number(
            ui,
            "field of view",
            "The vertical field of view in degrees (fov_y_degrees)",
            &mut scene.camera.fov_y_degrees,
            5.0..=120.0,
        );
        ui.label("orbit around")
            .on_hover_text("The object the orbit mode circles and F frames in orbit mode");
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
        ui.label("exposure")
            .on_hover_text("Multiplies the radiance before tone mapping (Khronos PBR Neutral); not saved");
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

fn materials_section(ui: &mut Ui, p: &mut Panel) {
    let (scene, view, actions) = (&mut *p.scene, &mut *p.view, &mut *p.actions);
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
    let Some(m) = scene.materials.get_mut(view.selected_material) else {
        return;
    };
    ui.horizontal(|ui| {
        ui.label("preset").on_hover_text(
            "A documented parameter set for a kind of clay (docs/scene-format.md); choosing one \
             gives the material all of its values, maps included",
        );
        let name = |p: Option<Preset>| p.map_or_else(|| "none".to_owned(), |p| file_name(&p));
        egui::ComboBox::from_id_salt("preset")
            .selected_text(name(m.preset))
            .show_ui(ui, |ui| {
                for preset in std::iter::once(None).chain(Preset::ALL.map(Some)) {
                    if ui.selectable_label(m.preset == preset, name(preset)).clicked() {
                        actions.rebuild = Some(Rebuild::Preset {
                            material: m.name.clone(),
                            preset,
                        });
                    }
                }
            });
        if ui
            .button("Reset")
            .on_hover_text("Back to the preset's values (or the built-in defaults without one)")
            .clicked()
        {
            actions.rebuild = Some(Rebuild::Preset {
                material: m.name.clone(),
                preset: m.preset,
            });
        }
    });
    grid(ui, "material", |ui| material_fields(ui, m));
}

/// One line per material key that applies to the chosen models (`material_keys` declares
/// each key's widget, range and tooltip), then the maps' parameters.
fn material_fields(ui: &mut Ui, m: &mut Material) {
    for (key, edit) in m.edits() {
        match edit {
            Edit::Number(value, range) => number(ui, key.label, &key.tip, value, range),
            Edit::Color(value, range) => color(ui, key.label, &key.tip, value, range),
            Edit::Toggle(value) => {
                ui.label(key.label).on_hover_text(&key.tip);
                ui.checkbox(value, "").on_hover_text(&key.tip);
                ui.end_row();
            }
            Edit::Choice(mut chooser) => {
                let names = chooser.names();
                let tip = key.tip.as_str();
                ui.label(key.label).on_hover_text(tip);
                let selected = chooser
                    .selected()
                    .and_then(|i| names.get(i))
                    .map_or("?", String::as_str);
                egui::ComboBox::from_id_salt(key.name)
                    .selected_text(selected)
                    .show_ui(ui, |ui| {
                        for (i, name) in names.iter().enumerate() {
                            if ui.selectable_label(chooser.selected() == Some(i), name).clicked() {
                                chooser.select(i);
                            }
                        }
                    })
                    .response
                    .on_hover_text(tip);
                ui.end_row();
            }
        }
    }
    // A map's texture is fixed by the scene file; its parameters are live.
    for (slot, map) in m.maps.iter_mut() {
        if let Some(map) = map {
            map_fields(ui, slot.info(), map);
        }
    }
}

/// A map's live parameters.
fn map_fields(ui: &mut Ui, slot: &SlotInfo, map: &mut MapRef) {
    let (name, words) = (slot.key, slot.label);
    number(
        ui,
        &format!("{words} strength"),
        &format!("{name}.strength: how much of the map applies"),
        &mut map.strength,
        MAP_STRENGTH.slider_range(),
    );
    const SAMPLED_AT: &str = "the map is sampled at uv · uv_scale, turned uv_rotation_degrees, + uv_offset";
    ui.label(format!("{words} scale"))
        .on_hover_text(format!("{name}.uv_scale: {SAMPLED_AT}"));
    ui.horizontal(|ui| {
        ui.add(
            egui::DragValue::new(&mut map.uv_scale.x)
                .speed(0.05)
                .range(0.01..=MAX_UV_SCALE),
        );
        ui.add(
            egui::DragValue::new(&mut map.uv_scale.y)
                .speed(0.05)
                .range(0.01..=MAX_UV_SCALE),
        );
    });
    ui.end_row();
    ui.label(format!("{words} offset"))
        .on_hover_text(format!("{name}.uv_offset: {SAMPLED_AT}"));
    ui.horizontal(|ui| {
        ui.add(egui::DragValue::new(&mut map.uv_offset.x).speed(0.01));
        ui.add(egui::DragValue::new(&mut map.uv_offset.y).speed(0.01));
    });
    ui.end_row();
    ui.label(format!("{words} rotation")).on_hover_text(format!(
        "{name}.uv_rotation_degrees: counter-clockwise, v up the texture; {SAMPLED_AT}"
    ));
    ui.add(egui::DragValue::new(&mut map.uv_rotation_degrees).speed(1.0).suffix("°"));
    ui.end_row();
    if slot.role == TextureRole::Normal {
        ui.label(format!("{words} green")).on_hover_text(format!(
            "{name}.green: which way the map's green channel points (up: OpenGL, down: DirectX)"
        ));
        ui.checkbox(&mut map.green_down, "down (DirectX)");
        ui.end_row();
    }
}

/// A model choice, its options spelled as in the scene file.
fn choice<T: Copy + PartialEq + Serialize>(ui: &mut Ui, label: &str, tip: &str, value: &mut T, options: &[T]) {
    ui.label(label).on_hover_text(tip);
    egui::ComboBox::from_id_salt(label)
        .selected_text(file_name(value))
        .show_ui(ui, |ui| {
            for option in options {
                ui.selectable_value(value, *option, file_name(option));
            }
        })
        .response
        .on_hover_text(tip);
    ui.end_row();
}

fn number(ui: &mut Ui, label: &str, tip: &str, value: &mut f32, range: RangeInclusive<f32>) {
    ui.label(label).on_hover_text(tip);
    ui.add(egui::Slider::new(value, range)).on_hover_text(tip);
    ui.end_row();
}

/// A linear RGB colour as the file stores it: three numbers, a swatch picker, and the
/// sRGB-encoded 8-bit values the swatch shows; written only when the user changes it. The
/// numbers stay in `range`, which for an unbounded colour (emission) does not clamp them to 1.
fn color(ui: &mut Ui, label: &str, tip: &str, value: &mut Vec3, range: RangeInclusive<f32>) {
    ui.label(label).on_hover_text(tip);
    ui.vertical(|ui| {
        let mut rgb = value.to_array();
        let mut changed = false;
        let srgb = egui::Rgba::from_rgb(rgb[0], rgb[1], rgb[2]).to_srgba_unmultiplied();
        ui.horizontal(|ui| {
            changed |= ui.color_edit_button_rgb(&mut rgb).changed();
            ui.small(format!("sRGB {} {} {}", srgb[0], srgb[1], srgb[2]));
        });
        ui.horizontal(|ui| {
            for c in &mut rgb {
                changed |= ui
                    .add(egui::DragValue::new(c).speed(0.005).range(range.clone()).max_decimals(3))
                    .on_hover_text("linear, as the scene file stores it")
                    .changed();
            }
        });
        if changed {
            *value = Vec3::from(rgb);
        }
    });
    ui.end_row();
}

/// A colour and a scale (e.g. W/sr) that multiply into `value`, written only when changed.
fn scaled_color(ui: &mut Ui, label: &str, value: &mut Vec3, unit: &str) {
    let (mut tint, mut scale) = split_color(*value);
    color(
        ui,
        &format!("{label} colour"),
        "the colour, brightest channel 1",
        &mut tint,
        0.0..=1.0,
    );
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
            scene
                .lights
                .push(PointLight::new(scene.camera.position, Vec3::splat(20.0)));
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
                number(
                    ui,
                    "intensity",
                    "intensity: scales the environment's radiance",
                    intensity,
                    0.0..=8.0,
                );
                number(
                    ui,
                    "rotation °",
                    "rotation_degrees: turns the environment about +y",
                    rotation_degrees,
                    -180.0..=180.0,
                );
            });
            reflection
        }
    };
    grid(ui, "reflection", |ui| {
        choice(
            ui,
            "reflection",
            "reflection: split-sum (prefiltered map and BRDF table, Karis 2013), the report's seed \
             lookup, or sampled (importance-sampled lookups per pixel)",
            &mut reflection.mode,
            &REFLECTION_MODES,
        );
        match reflection.mode {
            ReflectionMode::Sampled => {
                ui.label("samples");
                ui.add(egui::Slider::new(&mut reflection.samples, 1..=Reflection::MAX_SAMPLES).logarithmic(true));
                ui.end_row();
            }
            ReflectionMode::Seed => number(
                ui,
                "seed strength",
                "seed_strength: scales the report's reflected lookup",
                &mut reflection.seed_strength,
                0.0..=1.0,
            ),
            ReflectionMode::SplitSum => {}
        }
    });
}

/// A file for the selected material's maps, the environment, or a new object. A path field:
/// no native file dialog works under Xvfb without a desktop portal.
fn files_section(ui: &mut Ui, p: &mut Panel) {
    let (scene, view, actions) = (&*p.scene, &mut *p.view, &mut *p.actions);
    ui.add(
        egui::TextEdit::singleline(&mut view.path)
            .hint_text("textures/clay.png")
            .desired_width(ui.available_width()),
    )
    .on_hover_text("An image (.png, .exr, .hdr …) or an .obj mesh, relative to the working directory");
    super::path_completion::show(ui, &mut view.path);
    let path = view.path.trim().to_owned();
    let Some(material) = scene.materials.get(view.selected_material).map(|m| m.name.clone()) else {
        return;
    };
    ui.add_enabled_ui(!path.is_empty(), |ui| {
        ui.label(format!("use it for {material}'s"));
        ui.horizontal_wrapped(|ui| {
            for slot in SLOTS {
                if ui.button(slot.label).clicked() {
                    actions.rebuild = Some(Rebuild::Texture {
                        material: material.clone(),
                        map: slot.key,
                        path: path.clone(),
                    });
                }
            }
        });
        ui.horizontal_wrapped(|ui| {
            if ui
                .button("as the environment map")
                .on_hover_text("An equirectangular .hdr or .exr")
                .clicked()
            {
                actions.rebuild = Some(Rebuild::EnvironmentMap { path: path.clone() });
            }
            if ui
                .button(format!("add the mesh, in {material}"))
                .on_hover_text("An .obj mesh, placed at the origin")
                .clicked()
            {
                actions.rebuild = Some(Rebuild::Mesh {
                    material: material.clone(),
                    path: path.clone(),
                });
            }
        });
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
    if view.debug_view.is_radiance() {
        ui.checkbox(&mut view.auto_exposure, "auto exposure")
            .on_hover_text(format!(
                "Exposes this term from its own luminance, measured on the GPU a frame or two late: {:.0}% of the \
             lit pixels below the tone curve's shoulder. Off, the Camera section's exposure applies",
                PERCENTILE * 100.0
            ));
        let source = if view.auto_exposed() { "auto" } else { "camera" };
        ui.label(RichText::new(format!("exposure in use {:>10.3} ({source})", view.exposure_in_use)).monospace());
    }
}

fn timings_section(ui: &mut Ui, view: &ViewState) {
    ui.label(&view.device_name);
    let (width, height) = view.frame_size;
    let fps = view
        .timings
        .fps()
        .map_or_else(|| "–".to_owned(), |fps| format!("{fps:.1}"));
    ui.label(format!(
        "{width}×{height} px, {fps} frames/s (frames are drawn only when something changes)"
    ));
    if let Some(a) = view.accumulated {
        let state = if a.converging() { "refining" } else { "converged" };
        ui.label(format!(
            "sampled reflection: {} frames × {} lookups = {} lookups/pixel, {state} (at {CONVERGED_LOOKUPS})",
            a.frames,
            a.lookups_per_frame,
            a.lookups()
        ))
        .on_hover_text("A still view's frames are averaged, each with the next sample set; any change starts again");
    }
    let Some((cpu_ms, gpu_ms)) = view.timings.mean() else {
        return;
    };
    grid(ui, "timings", |ui| {
        ui.label("CPU work")
            .on_hover_text("Camera, UI and recording of a frame, up to its submission; mean over the last second");
        ui.label(milliseconds(cpu_ms));
        ui.end_row();
        for (name, ms) in view.timings.pass_names.iter().zip(&gpu_ms) {
            ui.label(format!("GPU {name}"))
                .on_hover_text("Timestamp queries around the pass; mean over the last second");
            ui.label(milliseconds(*ms));
            ui.end_row();
        }
    });
    history_graph(ui, &view.timings);
}

/// A time in a fixed width, so that the grid's columns do not change with the numbers: egui
/// draws a frame again whenever they do, which would keep an idle viewer drawing.
fn milliseconds(ms: f64) -> RichText {
    RichText::new(format!("{ms:>9.2} ms")).monospace()
}

const CPU_COLOR: Color32 = Color32::from_rgb(120, 200, 255);
const GPU_COLOR: Color32 = Color32::from_rgb(255, 170, 80);

/// CPU work and total GPU time of the last frames, on a scale from 0 to the peak with
/// gridlines.
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
    for fraction in [0.5, 1.0] {
        let y = rect.bottom() - fraction * rect.height();
        painter.hline(rect.x_range(), y, egui::Stroke::new(1.0, Color32::from_gray(60)));
        painter.text(
            egui::pos2(rect.left() + 2.0, y),
            egui::Align2::LEFT_TOP,
            format!("{:.1} ms", peak * f64::from(fraction)),
            egui::FontId::monospace(9.0),
            Color32::from_gray(150),
        );
    }
    let cpu = timings.history().enumerate().map(|(i, t)| point(i, t.cpu_ms)).collect();
    let gpu = timings
        .history()
        .enumerate()
        .map(|(i, t)| point(i, t.gpu_total_ms()))
        .collect();
    painter.add(egui::Shape::line(cpu, egui::Stroke::new(1.0, CPU_COLOR)));
    painter.add(egui::Shape::line(gpu, egui::Stroke::new(1.0, GPU_COLOR)));
    ui.horizontal(|ui| {
        ui.colored_label(CPU_COLOR, "CPU work");
        ui.colored_label(GPU_COLOR, "GPU total");
        ui.label(format!("last {n} frames"));
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{DiffuseModel, Geometry, SpecularModel};

    fn state() -> ViewState {
        ViewState {
            error: Some("scene.toml: materials.clay.roughness = 2.0: must be a finite number in [0, 1]".into()),
            device_name: "test device".into(),
            ..ViewState::new(1.0, Timings::new(vec!["forward", "tonemap", "ui"]), "scene.toml".into())
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
        // The ball's material has the most controls.
        let mut view = ViewState {
            selected_material: scene.objects[0].material,
            ..state()
        };
        let primitives = run(&mut scene, &mut view);
        assert!(!primitives.is_empty());
        let right = right_edge(&primitives);
        assert!(right <= PANEL_WIDTH + 1.0, "the UI reaches x = {right}");
        assert_eq!(scene, before, "showing the UI changes nothing");
        // The 3D view is the rest of the window, so the camera's aspect follows it.
        let view_rect = view.view_rect;
        assert!(
            (view_rect.min.x - PANEL_WIDTH).abs() <= 2.0 && view_rect.max.x == 1280.0,
            "view at {view_rect:?}"
        );
    }

    #[test]
    fn a_collapsed_panel_or_hidden_ui_leaves_the_whole_window_to_the_view() {
        let mut scene = Scene::default_scene();
        let mut view = ViewState {
            panel_open: false,
            ..state()
        };
        let primitives = run(&mut scene, &mut view);
        assert!(right_edge(&primitives) < 120.0, "only the button that opens it again");
        assert_eq!(view.view_rect.min.x, 0.0);
        let mut view = ViewState {
            hide_ui: true,
            ..state()
        };
        let primitives = run(&mut scene, &mut view);
        assert!(primitives.is_empty(), "no UI at all");
        assert_eq!(view.view_rect.width(), 1280.0);
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

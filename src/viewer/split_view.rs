//! The split view: the left half of the 3D view as the scene is, the right half in one of
//! `argil bench`'s configurations of it (src/bench/plan.rs edits the scene file the same
//! way), for example `seed` (the report's reflection) or `report` (its reflection, horizon
//! and subsurface). The renderer draws the two halves in one frame (src/render/split.rs),
//! so only what the forward pass draws may differ: the materials and the reflection mode.


use anyhow::{bail, Context, Result};
use egui::{Color32, RichText, Stroke, Ui};

use crate::bench::plan;
use crate::render::Split;
use crate::scene::{Environment, Material, Scene};

/// The configuration the right half starts with.
const FIRST: &str = "seed";

/// The bench configurations that edit the scene file (not the floor's, the generic
/// pipelines' or the drafts' renderer flags, nor what moves between frames), in the
/// bench's order.
pub fn configurations() -> Vec<String> {
    plan::configuration_names()
        .into_iter()
        .filter(|n| !plan::is_floor(n) && !plan::is_generic(n) && plan::moving(n).is_none())
        .collect()
}

/// `name` if it is one of [`configurations`]; for `argil view --split`.
pub fn parse_configuration(name: &str) -> Result<String, String> {
    let names = configurations();
    if names.iter().any(|n| n == name) {
        Ok(name.to_owned())
    } else {
        Err(format!("not a configuration; one of {}", names.join(", ")))
    }
}

/// The right half's materials and environment: `scene` edited as the bench edits its file
/// for `configuration`. An error when the configuration draws the scene unchanged, or
/// changes more than the forward pass can draw differently in one half.
pub fn derive(scene: &Scene, configuration: &str) -> Result<(Vec<Material>, Environment)> {
    let file = plan::configured(&scene.to_file(), configuration)?;
    let base_dir = scene.folder();
    let mut right = Scene::from_file(&file, &format!("the {configuration} configuration"), base_dir)?;
    let materials = std::mem::replace(&mut right.materials, scene.materials.clone());
    let environment = std::mem::replace(&mut right.environment, scene.environment.clone());
    right.source = scene.source.clone();
    right.camera = scene.camera;
    if right != *scene {
        bail!(
            "{configuration} changes more than the materials' values and the reflection mode (meshes, textures, \
             lights, shadows, anti-aliasing or occlusion), which the split view cannot draw in one half"
        );
    }
    if materials == scene.materials && environment == scene.environment {
        bail!("{configuration} draws this scene as it is: nothing to compare");
    }
    let split = Split {
        materials,
        environment,
        x: 0,
    };
    split
        .check(scene)
        .with_context(|| format!("{configuration} cannot be drawn in one half"))?;
    Ok((split.materials, split.environment))
}

/// The right half as derived from the scene's materials and environment as they were.
struct Derived {
    configuration: String,
    materials: Vec<Material>,
    environment: Environment,
    right: Result<(Vec<Material>, Environment), String>,
}

/// The split view's state: on or off, the right half's configuration, and the right half
/// derived again whenever the scene's materials or environment change.
pub struct SplitView {
    pub on: bool,
    pub configuration: String,
    derived: Option<Derived>,
}

impl Default for SplitView {
    fn default() -> Self {
        Self {
            on: false,
            configuration: FIRST.to_owned(),
            derived: None,
        }
    }
}

impl SplitView {
    /// What the renderer draws this frame: the right half from column `x` of the frame, or
    /// `None` when the split view is off or its configuration cannot be drawn.
    pub fn split(&mut self, scene: &Scene, x: u32) -> Option<Split> {
        if !self.on {
            return None;
        }
        let stale = self.derived.as_ref().is_none_or(|d| {
            d.configuration != self.configuration
                || d.materials != scene.materials
                || d.environment != scene.environment
        });
        if stale {
            self.derived = Some(Derived {
                configuration: self.configuration.clone(),
                materials: scene.materials.clone(),
                environment: scene.environment.clone(),
                right: derive(scene, &self.configuration).map_err(|e| format!("{e:#}")),
            });
        }
        let (materials, environment) = self.derived.as_ref()?.right.as_ref().ok()?;
        Some(Split {
            materials: materials.clone(),
            environment: environment.clone(),
            x,
        })
    }

    /// Why the right half is not drawn, when the split view is on.
    fn error(&self) -> Option<&str> {
        let d = self.derived.as_ref().filter(|_| self.on)?;
        d.right.as_ref().err().map(String::as_str)
    }

    /// Whether the last frame was drawn split.
    fn shown(&self) -> bool {
        self.on && self.derived.as_ref().is_some_and(|d| d.right.is_ok())
    }
}

/// The panel's "Split view" section.
pub fn section(ui: &mut Ui, split: &mut SplitView) {
    ui.checkbox(&mut split.on, "split view (V)").on_hover_text(
        "The left half as the scene is, the right half in one of argil bench's configurations of it; both halves \
         share the camera, lights, shadows, occlusion, exposure and display transform",
    );
    ui.add_enabled_ui(split.on, |ui| {
        ui.horizontal(|ui| {
            ui.label("right half");
            egui::ComboBox::from_id_salt("split configuration")
                .selected_text(&split.configuration)
                .show_ui(ui, |ui| {
                    for name in configurations() {
                        let label = name.clone();
                        ui.selectable_value(&mut split.configuration, name, label);
                    }
                })
                .response
                .on_hover_text(
                    "The scene file edited as argil bench edits it: seed is the report's reflection, report its \
                     reflection, horizon and subsurface on every material, no-subsurface and maps-off what they say",
                );
        });
    });
    if let Some(error) = split.error() {
        ui.label(RichText::new(error).color(Color32::LIGHT_RED));
    }
}

/// The divider down the middle of `view` (the 3D view, in points) and a label on each half.
pub fn overlay(ctx: &egui::Context, view: egui::Rect, split: &SplitView) {
    if !split.shown() {
        return;
    }
    let x = view.center().x;
    let painter = ctx.layer_painter(egui::LayerId::new(
        egui::Order::Background,
        egui::Id::new("argil-split-view"),
    ));
    painter.line_segment(
        [egui::pos2(x, view.min.y), egui::pos2(x, view.max.y)],
        Stroke::new(1.5, Color32::WHITE),
    );
    let font = egui::FontId::proportional(14.0);
    let label = |at: egui::Pos2, align: egui::Align2, text: &str| {
        let galley = painter.layout_no_wrap(text.to_owned(), font.clone(), Color32::WHITE);
        let rect = align.anchor_size(at, galley.size());
        painter.rect_filled(rect.expand(3.0), 3.0, Color32::from_black_alpha(160));
        painter.galley(rect.min, galley, Color32::WHITE);
    };
    let y = view.max.y - 8.0;
    label(egui::pos2(x - 8.0, y), egui::Align2::RIGHT_BOTTOM, "as the scene is");
    label(egui::pos2(x + 8.0, y), egui::Align2::LEFT_BOTTOM, &split.configuration);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Horizon, ReflectionMode, Subsurface};

    #[test]
    fn seed_and_report_change_only_what_the_forward_pass_draws() {
        let scene = Scene::default_scene();
        let (materials, environment) = derive(&scene, "seed").expect("seed");
        assert_eq!(materials, scene.materials);
        assert_eq!(environment.reflection().map(|r| r.mode), Some(ReflectionMode::Seed));
        let (materials, environment) = derive(&scene, "report").expect("report");
        assert!(materials
            .iter()
            .all(|m| m.horizon == Horizon::Seed && m.subsurface == Subsurface::Seed));
        assert_eq!(environment.reflection().map(|r| r.mode), Some(ReflectionMode::Seed));
    }

    #[test]
    fn configurations_the_split_cannot_draw_are_refused_by_name() {
        let scene = Scene::default_scene();
        let unchanged = derive(&scene, "split-sum").expect_err("argil's defaults are the scene");
        assert!(unchanged.to_string().contains("nothing to compare"), "{unchanged:#}");
        for name in ["no-shadows", "msaa-4", "occlusion", "no-environment", "sphere-8"] {
            let error = derive(&scene, name).expect_err(name);
            assert!(error.to_string().starts_with(name), "{error:#}");
            assert!(!error.to_string().contains("nothing to compare"), "{error:#}");
        }
        assert!(parse_configuration("floor").is_err());
        assert!(parse_configuration("generic-maps-off").is_err());
        assert_eq!(parse_configuration("report").as_deref(), Ok("report"));
    }

    #[test]
    fn the_right_half_follows_material_edits() {
        let mut scene = Scene::default_scene();
        let mut view = SplitView {
            on: true,
            ..SplitView::default()
        };
        let first = view.split(&scene, 10).expect("seed is drawn");
        scene.materials[0].roughness = 0.9;
        let edited = view.split(&scene, 10).expect("seed is drawn");
        assert_ne!(first.materials, edited.materials);
        assert_eq!(edited.materials[0].roughness, 0.9);
        view.configuration = "no-shadows".to_owned();
        assert!(view.split(&scene, 10).is_none());
        assert!(view.error().is_some());
        view.on = false;
        assert!(view.split(&scene, 10).is_none() && view.error().is_none());
    }
}

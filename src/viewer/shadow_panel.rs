//! The viewer's shadow settings: the renderer-wide toggle, the maps' resolution, a soft
//! shadow's taps, the light bounced off the ground, the ground's shadows from a map, and
//! each light's `shadows` and `radius` (saved with the scene).

use egui::Ui;

use crate::scene::{Scene, SHADOW_RESOLUTION_RANGE, SHADOW_TAPS_RANGE};

/// The "Shadows" section; `enabled` is the renderer's toggle (not saved).
pub fn shadows_section(ui: &mut Ui, scene: &mut Scene, enabled: &mut bool) {
    ui.checkbox(enabled, "shadows (all lights)");
    egui::Grid::new("shadows").num_columns(2).striped(true).show(ui, |ui| {
        ui.label("map resolution");
        ui.add(
            egui::DragValue::new(&mut scene.shadow_resolution)
                .range(SHADOW_RESOLUTION_RANGE)
                .speed(16.0)
                .suffix(" texels"),
        );
        ui.end_row();
        ui.label("soft-shadow taps");
        ui.add(egui::DragValue::new(&mut scene.shadow_taps).range(SHADOW_TAPS_RANGE).speed(0.25));
        ui.end_row();
        ui.label("bounce");
        ui.checkbox(&mut scene.bounce, "light bounced off the ground");
        ui.end_row();
        ui.label("ground map").on_hover_text(
            "[shadows] ground_map: the ground's soft shadows computed once per change at the texels of a map over \
             it, rather than at every pixel",
        );
        ui.checkbox(&mut scene.shadow_ground_map, "from a map");
        ui.end_row();
        ui.label("per vertex").on_hover_text(
            "[shadows] per_vertex: the soft shadows of finely tessellated objects computed once per change at \
             their vertices and interpolated, rather than at every pixel",
        );
        ui.checkbox(&mut scene.shadow_per_vertex, "at the vertices");
        ui.end_row();
        for (i, light) in scene.lights.iter_mut().enumerate() {
            ui.label(format!("light {i}"));
            ui.horizontal(|ui| {
                ui.checkbox(&mut light.shadows, "casts shadows");
                ui.add(
                    egui::DragValue::new(&mut light.radius)
                        .range(0.0..=1e3)
                        .speed(0.01)
                        .prefix("radius "),
                );
            });
            ui.end_row();
        }
    });
}

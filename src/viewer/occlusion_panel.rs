//! The viewer's ambient occlusion settings: the renderer-wide toggle and the scene's
//! `[occlusion]` keys (saved with the scene).

use egui::Ui;

use crate::scene::{Scene, OCCLUSION_SAMPLES_RANGE};

/// The "Occlusion" section; `allowed` is the renderer's toggle (not saved).
pub fn occlusion_section(ui: &mut Ui, scene: &mut Scene, allowed: &mut bool) {
    ui.checkbox(allowed, "occlusion (renderer)");
    let occlusion = &mut scene.occlusion;
    egui::Grid::new("occlusion")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            ui.label("scene");
            ui.checkbox(&mut occlusion.enabled, "enabled");
            ui.end_row();
            ui.label("radius");
            ui.add(
                egui::DragValue::new(&mut occlusion.radius)
                    .range(1e-3..=1e3)
                    .speed(0.01)
                    .suffix(" units"),
            );
            ui.end_row();
            ui.label("slices");
            ui.add(egui::DragValue::new(&mut occlusion.slices).range(OCCLUSION_SAMPLES_RANGE));
            ui.end_row();
            ui.label("steps per side");
            ui.add(egui::DragValue::new(&mut occlusion.steps).range(OCCLUSION_SAMPLES_RANGE));
            ui.end_row();
            ui.label("bounce");
            ui.checkbox(&mut occlusion.multi_bounce, "multi-bounce fit");
            ui.end_row();
            ui.label("objects")
                .on_hover_text("[occlusion] objects: each object, as spheres, hides the environment's light it subtends (Snyder 1996's clipped cap) and reflects its own");
            ui.checkbox(&mut occlusion.objects, "occlude as spheres");
            ui.end_row();
            ui.label("ground map").on_hover_text(
                "[occlusion] ground_map: the objects' occlusion of the ground read from a map over it, computed \
                 once per change, rather than from every sphere at every pixel",
            );
            ui.add_enabled(occlusion.objects, egui::Checkbox::new(&mut occlusion.ground_map, "from a map"));
            ui.end_row();
            ui.label("per vertex").on_hover_text(
                "[occlusion] per_vertex: each object's occlusion by the others computed at its vertices and \
                 interpolated, where its triangles are small against its distance to them, rather than at \
                 every pixel",
            );
            ui.add_enabled(occlusion.objects, egui::Checkbox::new(&mut occlusion.per_vertex, "at vertices"));
            ui.end_row();
        });
}

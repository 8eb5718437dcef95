//! The viewer's anti-aliasing settings, `[antialiasing]` (saved with the scene).

use egui::Ui;

use crate::scene::{Scene, MSAA_COUNTS};

/// The "Anti-aliasing" section; `supported` is the sample count the device draws the
/// scene's `msaa` with (the largest it supports up to it).
pub fn antialiasing_section(ui: &mut Ui, scene: &mut Scene, supported: u32) {
    let a = &mut scene.antialiasing;
    ui.horizontal(|ui| {
        ui.label("MSAA");
        for count in MSAA_COUNTS {
            ui.selectable_value(&mut a.msaa, count, format!("{count}×"));
        }
    });
    if supported != a.msaa {
        ui.label(format!(
            "this device draws {supported}× (its largest up to {}×)",
            a.msaa
        ));
    }
    ui.checkbox(&mut a.specular, "specular anti-aliasing (normal variance)");
}

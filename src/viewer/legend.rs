//! The curvature view's legend: a colour bar from concave (blue) to convex (red), with
//! ticks at values of the mean curvature κ in 1/world units. Its colours are the shader's
//! map (`curvature_color`, the twin of debug_views.glsl) through the same display
//! transform and exposure as the frame, so a colour in the view reads off the bar.

use egui::{Color32, Rect, Sense, Stroke, Ui};

use crate::brdf::tonemap::display_srgb8;
use crate::render::debug_view::{curvature_at_brightness, curvature_color};

/// The bar spans brightness −0.98 (concave) to 0.98 (convex): |κ| up to 7.8 at the
/// scale of 0.5, beyond which the view's colours barely change.
const MAX_BRIGHTNESS: f64 = 0.98;
/// |κ| of the ticks on each side of 0.
const TICKS: [f64; 3] = [1.0, 2.0, 4.0];
/// Colour strips the bar is drawn with.
const STRIPS: usize = 96;

/// What the display shows for curvature `kappa` at `exposure`.
pub fn curvature_legend_color(kappa: f64, exposure: f32) -> Color32 {
    let [r, g, b] = display_srgb8(curvature_color(kappa).map(|c| c * f64::from(exposure)));
    Color32::from_rgb(r, g, b)
}

/// Where κ lies on the bar, from −1 (most concave shown) to 1: the view's brightness.
fn bar_position(kappa: f64) -> f64 {
    kappa.signum() * curvature_color(kappa).iter().sum::<f64>() / MAX_BRIGHTNESS
}

/// The κ shown at bar position `t` in [−1, 1].
fn curvature_at(t: f64) -> f64 {
    t.signum() * curvature_at_brightness(t.abs() * MAX_BRIGHTNESS)
}

/// The legend over the bottom-left corner of the 3D view `view` (in points).
pub fn show(ctx: &egui::Context, view: Rect, exposure: f32) {
    egui::Area::new(egui::Id::new("argil-curvature-legend"))
        .pivot(egui::Align2::LEFT_BOTTOM)
        .fixed_pos(view.left_bottom() + egui::vec2(10.0, -10.0))
        .interactable(false)
        .show(ctx, |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| bar(ui, exposure));
        });
}

fn bar(ui: &mut Ui, exposure: f32) {
    ui.label("mean curvature κ (1/world units): blue concave, red convex");
    let width = 280.0;
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 30.0), Sense::hover());
    let bar = Rect::from_min_size(rect.min, egui::vec2(width, 14.0));
    let painter = ui.painter_at(rect);
    let x_of = |t: f64| bar.left() + (t as f32 + 1.0) * 0.5 * bar.width();
    for i in 0..STRIPS {
        let at = |strip: usize| 2.0 * strip as f64 / STRIPS as f64 - 1.0;
        let (t0, t1) = (at(i), at(i + 1));
        let strip = Rect::from_x_y_ranges(x_of(t0)..=x_of(t1), bar.y_range());
        painter.rect_filled(
            strip,
            0.0,
            curvature_legend_color(curvature_at(0.5 * (t0 + t1)), exposure),
        );
    }
    let text = ui.visuals().text_color();
    let ticks = TICKS.iter().flat_map(|&k| [-k, k]).chain([0.0]);
    for kappa in ticks {
        let x = x_of(bar_position(kappa));
        painter.line_segment(
            [egui::pos2(x, bar.top()), egui::pos2(x, bar.bottom() + 3.0)],
            Stroke::new(1.0, text),
        );
        painter.text(
            egui::pos2(x, bar.bottom() + 3.0),
            egui::Align2::CENTER_TOP,
            format!("{kappa}"),
            egui::FontId::proportional(11.0),
            text,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_sit_where_the_bar_shows_their_curvature() {
        for kappa in [-4.0, -1.0, 0.5, 2.0, 7.0] {
            let t = bar_position(kappa);
            assert!((-1.0..=1.0).contains(&t), "{kappa}: {t}");
            assert!(
                (curvature_at(t) - kappa).abs() < 1e-9,
                "{kappa} → {t} → {}",
                curvature_at(t)
            );
        }
        assert_eq!(bar_position(0.0), 0.0);
        // Red for convex, blue for concave, black for flat, brighter with |κ|.
        let (convex, concave) = (curvature_legend_color(2.0, 1.0), curvature_legend_color(-2.0, 1.0));
        assert!(convex.r() > 0 && convex.g() == 0 && convex.b() == 0, "{convex:?}");
        assert!(concave.b() > 0 && concave.r() == 0 && concave.g() == 0, "{concave:?}");
        assert_eq!(curvature_legend_color(0.0, 1.0), Color32::BLACK);
        assert!(curvature_legend_color(4.0, 1.0).r() > convex.r());
    }
}

//! The plot of `argil bench`: shading time (as a ratio to the floor) against ꟻLIP, log–log,
//! one mark per configuration, the Pareto front drawn and the report's composition labelled.

use std::path::Path;

use anyhow::{anyhow, Context, Result};
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

use super::report::Row;
use crate::atomic::write_atomically;

const SIZE: (u32, u32) = (960, 640);
const FONT: &str = "sans-serif";

/// Draws `rows` (one scene; the floor left out, as it is the unit of the x axis) into the
/// PNG `path`, their ꟻLIP against the `shadows` reference: the error of the renderer's
/// approximations alone. A row at another size than the first is labelled with its size.
pub fn plot(path: &Path, title: &str, rows: &[&Row]) -> Result<()> {
    // Registering twice keeps the first; the font is one egui embeds already.
    register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow!("the plot's font cannot be read"))?;
    let Some(first) = rows.first() else {
        return Ok(());
    };
    let points: Vec<(f64, f64, String, bool)> = rows
        .iter()
        .map(|r| {
            let name = if (r.width, r.height) == (first.width, first.height) {
                r.configuration.clone()
            } else {
                format!("{} at {}×{}", r.configuration, r.width, r.height)
            };
            (r.forward_ratio_to_floor, r.error_shadows.flip_mean, name, r.report)
        })
        .filter(|(x, y, ..)| x.is_finite() && y.is_finite() && *x > 0.0 && *y > 0.0)
        .collect();
    anyhow::ensure!(!points.is_empty(), "no finite point to plot for {title}");
    let range = |values: Vec<f64>| {
        let (lo, hi) = values
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        // A quarter of a decade of margin each side, so marks and labels fit.
        lo / 10f64.powf(0.25)..hi * 10f64.powf(0.25)
    };
    let x_range = range(points.iter().map(|p| p.0).collect());
    let y_range = range(points.iter().map(|p| p.1).collect());

    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        root.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, (FONT, 22))
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(x_range.log_scale(), y_range.log_scale())?;
        chart
            .configure_mesh()
            .x_desc("forward pass GPU time / the floor's (log)")
            .y_desc("mean FLIP against the shadows reference (log)")
            .label_style((FONT, 15))
            // Log axes put ticks at binary fractions (0.30000000000000004).
            .x_label_formatter(&|x| format!("{}", (x * 1e3).round() / 1e3))
            .y_label_formatter(&|y| format!("{}", (y * 1e4).round() / 1e4))
            .draw()?;
        chart.draw_series(LineSeries::new(pareto_front(&points), BLUE.stroke_width(2)))?;
        chart.draw_series(points.iter().map(|&(x, y, _, report)| {
            let colour = if report { RED } else { BLACK };
            Circle::new((x, y), 5, colour.filled())
        }))?;
        chart.draw_series(points.iter().map(|(x, y, name, report)| {
            let (x, y, report) = (*x, *y, *report);
            let label = if report {
                format!("{name} (the report's composition)")
            } else {
                name.to_owned()
            };
            let colour = if report { RED } else { BLACK };
            Text::new(label, (x * 1.04, y * 1.04), (FONT, 14).into_font().color(&colour))
        }))?;
        root.present()?;
    }
    let image = image::RgbImage::from_raw(SIZE.0, SIZE.1, rgb).context("plot buffer of the wrong size")?;
    write_atomically(path, |sink| Ok(image.write_to(sink, image::ImageFormat::Png)?))
}

/// The points no other point beats in both time and error, by increasing time.
fn pareto_front<L>(points: &[(f64, f64, L, bool)]) -> Vec<(f64, f64)> {
    let mut sorted: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.1)).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(f64, f64)> = Vec::new();
    for p in sorted {
        if front.last().is_none_or(|last| p.1 < last.1) {
            front.push(p);
        }
    }
    front
}

#[cfg(test)]
mod tests {
    use super::pareto_front;

    #[test]
    fn the_pareto_front_keeps_only_points_nothing_beats() {
        let points = [
            (4.0, 0.1, "b", false),
            (1.0, 0.5, "a", false),
            (2.0, 0.6, "dominated by a", false),
            (8.0, 0.01, "c", false),
            (9.0, 0.02, "dominated by c", false),
        ];
        assert_eq!(pareto_front(&points), vec![(1.0, 0.5), (4.0, 0.1), (8.0, 0.01)]);
    }
}

//! The plot of `argil bench`: shading time (as a ratio to the floor) against ꟻLIP, log–log,
//! one mark per configuration, the Pareto front drawn and the report's composition labelled,
//! and every other mark whose label finds room.

use std::ops::Range;
use std::path::Path;

use anyhow::{anyhow, Context, Result};
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

use super::plan::DEFAULTS;
use super::report::Row;
use crate::atomic::{write_atomically, Existing};

const SIZE: (u32, u32) = (960, 640);
const FONT: &str = "sans-serif";

/// Draws `rows` (one scene; the floor left out, as it is the unit of the x axis) into the
/// PNG `path`, their ꟻLIP against the `shadows` reference: the error of the renderer's
/// approximations alone. A row at another size than the first is labelled with its size and
/// left out of the Pareto front: its ratio to the floor is of another size's floor, which
/// shading outgrows as pixels grow.
pub fn plot(path: &Path, title: &str, rows: &[&Row]) -> Result<()> {
    // Registering twice keeps the first; the font is one egui embeds already.
    register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
        .map_err(|_| anyhow!("the plot's font cannot be read"))?;
    let Some(first) = rows.first() else {
        return Ok(());
    };
    let points: Vec<(f64, f64, String, bool, bool)> = rows
        .iter()
        .map(|r| {
            let first_size = (r.width, r.height) == (first.width, first.height);
            let name = if first_size {
                r.configuration.clone()
            } else {
                format!("{} at {}×{}", r.configuration, r.width, r.height)
            };
            (r.forward_ratio_to_floor, r.error_shadows.flip_mean, name, r.report, first_size)
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
        let front = pareto_front(points.iter().filter(|p| p.4).map(|p| (p.0, p.1)));
        chart.draw_series(LineSeries::new(front.iter().copied(), BLUE.stroke_width(2)))?;
        chart.draw_series(points.iter().map(|&(x, y, _, report, _)| {
            let colour = if report { RED } else { BLACK };
            Circle::new((x, y), 5, colour.filled())
        }))?;
        let labels: Vec<(String, TextStyle)> = points
            .iter()
            .map(|(_, _, name, report, _)| {
                let (text, colour) = if *report {
                    (format!("{name} (the report's composition)"), RED)
                } else {
                    (name.clone(), BLACK)
                };
                (text, (FONT, 14).into_font().color(&colour))
            })
            .collect();
        let marks: Vec<(i32, i32)> = points.iter().map(|&(x, y, ..)| chart.backend_coord(&(x, y))).collect();
        let sizes = labels
            .iter()
            .map(|(text, style)| root.estimate_text_size(text, style))
            .collect::<Result<Vec<_>, _>>()?;
        // The report's label first, argil's defaults', the front's, then the others from
        // the cheapest.
        let mut order: Vec<usize> = (0..points.len()).collect();
        order.sort_by_key(|&i| {
            let (x, y, name, report, _) = &points[i];
            (!report, name != DEFAULTS, !front.contains(&(*x, *y)), marks[i].0)
        });
        let (x_pixels, y_pixels) = chart.plotting_area().get_pixel_range();
        let placed = place_labels(&marks, &sizes, &order, (x_pixels, y_pixels));
        for ((text, style), corner) in labels.iter().zip(&placed) {
            if let Some(corner) = corner {
                root.draw(&Text::new(text.as_str(), *corner, style.clone()))?;
            }
        }
        let unlabelled = placed.iter().filter(|p| p.is_none()).count();
        if unlabelled > 0 {
            // In the bottom margin, right-aligned.
            let note = format!("{unlabelled} marks crowded out of labels: results.md lists every row");
            let style = (FONT, 13).into_font().color(&BLACK);
            let (width, _) = root.estimate_text_size(&note, &style)?;
            root.draw(&Text::new(note, (SIZE.0 as i32 - width as i32 - 10, SIZE.1 as i32 - 17), style))?;
        }
        root.present()?;
    }
    let image = image::RgbImage::from_raw(SIZE.0, SIZE.1, rgb).context("plot buffer of the wrong size")?;
    write_atomically(path, Existing::Replace, |sink| Ok(image.write_to(sink, image::ImageFormat::Png)?))
}

/// The top-left corners of the labels of `marks` (pixels), each of its size in `sizes`,
/// placed in `order` beside its mark (right, left, above or below) where it stays inside
/// `bounds` and clear of every mark and every label placed before it; `None` where no
/// place is clear, so that a crowded plot leaves labels out rather than overprinting them.
fn place_labels(
    marks: &[(i32, i32)],
    sizes: &[(u32, u32)],
    order: &[usize],
    bounds: (Range<i32>, Range<i32>),
) -> Vec<Option<(i32, i32)>> {
    // Boxes as (left, top, right, bottom); a mark's is its circle's with a pixel to spare.
    type Box = (i32, i32, i32, i32);
    let apart = |a: &Box, b: &Box| a.2 <= b.0 || b.2 <= a.0 || a.3 <= b.1 || b.3 <= a.1;
    let inside = |b: &Box| bounds.0.start <= b.0 && b.2 <= bounds.0.end && bounds.1.start <= b.1 && b.3 <= bounds.1.end;
    const MARK: i32 = 6;
    let mut taken: Vec<Box> = marks.iter().map(|&(x, y)| (x - MARK, y - MARK, x + MARK, y + MARK)).collect();
    let mut placed = vec![None; marks.len()];
    for &i in order {
        let ((x, y), (w, h)) = (marks[i], (sizes[i].0 as i32, sizes[i].1 as i32));
        let candidates = [
            (x + MARK + 2, y - h / 2),
            (x - MARK - 2 - w, y - h / 2),
            (x - w / 2, y - MARK - 2 - h),
            (x - w / 2, y + MARK + 2),
        ];
        let clear = candidates
            .into_iter()
            .map(|(l, t)| (l, t, l + w, t + h))
            .find(|b| inside(b) && taken.iter().all(|t| apart(b, t)));
        if let Some(b) = clear {
            placed[i] = Some((b.0, b.1));
            taken.push(b);
        }
    }
    placed
}

/// The points no other point beats in both time and error, by increasing time.
fn pareto_front(points: impl IntoIterator<Item = (f64, f64)>) -> Vec<(f64, f64)> {
    let mut sorted: Vec<(f64, f64)> = points.into_iter().collect();
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
    use super::{pareto_front, place_labels};

    /// Labels never overprint each other or a mark, stay inside the plot, and the first in
    /// order always finds a place; a crowded cluster loses the labels that do not fit.
    #[test]
    fn labels_are_placed_clear_of_each_other_or_left_out() {
        let bounds = (0..400, 0..300);
        // A cluster of marks 4 pixels apart, and one alone.
        let mut marks: Vec<(i32, i32)> = (0..8).map(|k| (100 + 4 * k, 150)).collect();
        marks.push((300, 50));
        let sizes = vec![(60, 14); marks.len()];
        let order: Vec<usize> = (0..marks.len()).rev().collect();
        let placed = place_labels(&marks, &sizes, &order, bounds.clone());
        assert!(placed[8].is_some() && placed[7].is_some(), "{placed:?}");
        assert!(placed.iter().any(Option::is_none), "a crowded cluster keeps every label: {placed:?}");
        let boxes: Vec<(i32, i32, i32, i32)> = placed.iter().flatten().map(|&(l, t)| (l, t, l + 60, t + 14)).collect();
        for (a, b) in boxes.iter().enumerate().flat_map(|(i, a)| boxes[i + 1..].iter().map(move |b| (a, b))) {
            assert!(a.2 <= b.0 || b.2 <= a.0 || a.3 <= b.1 || b.3 <= a.1, "{a:?} overlaps {b:?}");
        }
        for b in &boxes {
            assert!(bounds.0.contains(&b.0) && b.2 <= bounds.0.end && bounds.1.contains(&b.1) && b.3 <= bounds.1.end);
            for &(x, y) in &marks {
                let clear = b.2 <= x - 6 || x + 6 <= b.0 || b.3 <= y - 6 || y + 6 <= b.1;
                assert!(clear, "{b:?} covers the mark at ({x}, {y})");
            }
        }
    }

    #[test]
    fn the_pareto_front_keeps_only_points_nothing_beats() {
        let points = [
            (4.0, 0.1),   // on it
            (1.0, 0.5),   // on it
            (2.0, 0.6),   // beaten by (1.0, 0.5)
            (8.0, 0.01),  // on it
            (9.0, 0.02),  // beaten by (8.0, 0.01)
        ];
        assert_eq!(pareto_front(points), vec![(1.0, 0.5), (4.0, 0.1), (8.0, 0.01)]);
    }
}

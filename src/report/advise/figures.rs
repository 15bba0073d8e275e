//! `hemilab advise`'s figures, one function each: error against time per image for every
//! configuration with the budgets marked, and the winner map (per pixel, which configuration has
//! the least error at a budget).

use crate::report::axis::{Frame, log_log_chart, tick};
use crate::report::backend::{FONT, Format, render};
use crate::report::canvas::{Align, Canvas, text_size};
use crate::report::plot::PALETTE;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One configuration's measured points (time per image in ms, error, its spread). Highlighted
/// curves get a colour and a legend entry; the rest are drawn thin and grey, as context.
pub struct TimeCurve {
    pub label: String,
    pub points: Vec<(f64, f64, f64)>,
    pub highlight: bool,
}

const W: u32 = 1000;
const H: u32 = 640;
const LEGEND_PX: f64 = 17.0;
const CONTEXT: RGBColor = RGBColor(205, 205, 205);
const BUDGET: RGBColor = RGBColor(90, 90, 90);

/// Log-log error against time per image: grey context curves, highlighted ones in colour with
/// markers and error bars, and a dashed vertical line at each budget, labelled with its value.
pub fn error_time_plot(
    title: &str,
    y_label: &str,
    curves: &[TimeCurve],
    budgets_ms: &[f64],
    format: Format,
) -> Result<Vec<u8>, String> {
    let ok = |p: &(f64, f64, f64)| p.0.is_finite() && p.0 > 0.0 && p.1.is_finite() && p.1 > 0.0 && p.2 >= 0.0;
    if let Some(c) = curves.iter().find(|c| c.points.is_empty() || !c.points.iter().all(ok)) {
        return Err(format!("curve '{}' has no points or a point a log-log plot cannot show", c.label));
    }
    if curves.is_empty() || budgets_ms.iter().any(|b| !(b.is_finite() && *b > 0.0)) {
        return Err("an error-time plot needs curves and positive budgets".into());
    }
    let xs = curves.iter().flat_map(|c| c.points.iter().map(|p| p.0)).chain(budgets_ms.iter().copied());
    let (x0, x1) = xs.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    let ys = curves.iter().flat_map(|c| c.points.iter().map(|p| p.1));
    let (y0, y1) = ys.fold((f64::INFINITY, 0.0f64), |(a, b), y| (a.min(y), b.max(y)));
    let ranges = (x0 / 1.15, x1 * 1.15, y0 / 1.3, y1 * 1.3);
    let others = curves.iter().filter(|c| !c.highlight).count();
    let mut entries: Vec<String> = curves.iter().filter(|c| c.highlight).map(|c| c.label.clone()).collect();
    if others > 0 {
        entries.push(format!("{others} other configurations"));
    }
    entries.push("budgets".into());
    let legend_w = entries.iter().map(|e| text_size(e, LEGEND_PX, false).0).max().unwrap_or(0) + 70;
    let h = H.max(90 + 24 * entries.len() as u32);
    render!(format, W + legend_w, h, |root: &DrawingArea<_, Shift>| {
        draw(root, title, y_label, curves, budgets_ms, Frame { ranges, entries: &entries, legend_w })
    })
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    y_label: &str,
    curves: &[TimeCurve],
    budgets_ms: &[f64],
    frame: Frame,
) -> Result<(), String> {
    let Frame { ranges: (x0, x1, y0, y1), entries, legend_w } = frame;
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (w, _) = root.dim_in_pixel();
    let (plot, legend) = root.split_horizontally(w - legend_w);
    let x_label = "time per image (ms; one thread, thread CPU time)";
    let mut chart = log_log_chart(&plot, title, (x_label, y_label), (x0, x1, y0, y1))?;
    for c in curves.iter().filter(|c| !c.highlight) {
        let line = LineSeries::new(c.points.iter().map(|p| (p.0, p.1)), CONTEXT.stroke_width(1));
        chart.draw_series(line).map_err(err)?;
    }
    let label_font = (FONT, 16.0).into_font().color(&BUDGET).pos(Pos::new(HPos::Left, VPos::Top));
    for &b in budgets_ms {
        let line = DashedLineSeries::new([(b, y0), (b, y1)], 8, 6, BUDGET.stroke_width(2));
        chart.draw_series(line).map_err(err)?;
        let text = format!("{} ms", tick(b));
        chart.draw_series([Text::new(text, (b * 1.02, y1 / 1.05), label_font.clone())]).map_err(err)?;
    }
    for (i, c) in curves.iter().filter(|c| c.highlight).enumerate() {
        let col = PALETTE[i % PALETTE.len()];
        let line = LineSeries::new(c.points.iter().map(|p| (p.0, p.1)), col.stroke_width(2));
        chart.draw_series(line).map_err(err)?;
        for &(x, m, sd) in &c.points {
            let (lo, hi) = (if m - sd > y0 { m - sd } else { y0 }, (m + sd).min(y1));
            chart
                .draw_series([PathElement::new(vec![(x, lo), (x, hi)], col.stroke_width(2))])
                .map_err(err)?;
            let dot = EmptyElement::at((x, m)) + Circle::new((0, 0), 4, col.filled());
            chart.draw_series([dot]).map_err(err)?;
        }
    }
    let font = (FONT, LEGEND_PX).into_font().color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center));
    let highlighted = curves.iter().filter(|c| c.highlight).count();
    for (i, e) in entries.iter().enumerate() {
        let y = 70 + 24 * i as i32;
        let (col, width, dashed) = if i < highlighted {
            (PALETTE[i % PALETTE.len()], 2, false)
        } else if i + 1 < entries.len() {
            (CONTEXT, 1, false)
        } else {
            (BUDGET, 2, true)
        };
        if dashed {
            legend.draw(&PathElement::new(vec![(8, y), (20, y)], col.stroke_width(width))).map_err(err)?;
            legend.draw(&PathElement::new(vec![(30, y), (44, y)], col.stroke_width(width))).map_err(err)?;
        } else {
            legend.draw(&PathElement::new(vec![(8, y), (44, y)], col.stroke_width(width))).map_err(err)?;
        }
        legend.draw_text(e, &font, (54, y)).map_err(err)?;
    }
    Ok(())
}

/// Categorical colours of the winner map (Tableau 10 without its grey, which means "no
/// significant winner" here), then black for every further configuration.
pub const WINNER_COLOURS: [[u8; 3]; 9] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [188, 189, 34],
    [23, 190, 207],
];
/// Configurations beyond the palette.
pub const OTHER_WINNER: [u8; 3] = [0, 0, 0];
/// Covered pixels without a significant winner.
pub const UNRESOLVED: [u8; 3] = [200, 200, 200];

/// One panel: a caption and its pixels' colours at image size (row-major).
pub struct Panel {
    pub caption: String,
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<[u8; 3]>,
}

const PAD: i64 = 16;
const PANELS_PER_ROW: usize = 3;

/// Panels side by side (three per row), enlarged by whole pixels to about 420 px wide, under a
/// title, with a legend of colour swatches below and a note (what "significant" means) under it.
pub fn winner_map(
    title: &str,
    panels: &[Panel],
    legend: &[(String, [u8; 3])],
    note: &str,
) -> Result<Vec<u8>, String> {
    let first = panels.first().ok_or("a winner map needs at least one panel")?;
    if let Some(p) =
        panels.iter().find(|p| p.rgb.len() != p.width as usize * p.height as usize || p.width == 0)
    {
        return Err(format!(
            "panel '{}' has {} colours for {}x{} pixels",
            p.caption,
            p.rgb.len(),
            p.width,
            p.height
        ));
    }
    let scale = 420u32.div_ceil(first.width).max(1);
    let (pw, ph) = (first.width * scale, first.height * scale);
    let cols = panels.len().min(PANELS_PER_ROW);
    let rows = panels.len().div_ceil(PANELS_PER_ROW);
    let legend_cols = 2usize;
    let legend_rows = legend.len().div_ceil(legend_cols) as u32;
    let width = (PAD as u32 * (cols as u32 + 1) + pw * cols as u32).max(900);
    let top = 56u32;
    let cell_h = ph + 36;
    let height = top + rows as u32 * cell_h + 24 + legend_rows * 28 + 60;
    let mut c = Canvas::new(width, height, [255, 255, 255])?;
    c.label(title, PAD, 26, 24.0, Align::Left, true);
    for (k, p) in panels.iter().enumerate() {
        let x = PAD + (k % PANELS_PER_ROW) as i64 * (pw as i64 + PAD);
        let y = top as i64 + (k / PANELS_PER_ROW) as i64 * cell_h as i64 + 28;
        c.label(&p.caption, x, y - 14, 17.0, Align::Left, false);
        for py in 0..p.height.min(first.height) {
            for px in 0..p.width.min(first.width) {
                let col = p.rgb[(py * p.width + px) as usize];
                c.fill_rect(x + (px * scale) as i64, y + (py * scale) as i64, scale, scale, col);
            }
        }
        c.outline(x, y, pw, ph, [120, 120, 120]);
    }
    let ly = (top + rows as u32 * cell_h + 20) as i64;
    let col_w = (width as i64 - 2 * PAD) / legend_cols as i64;
    for (i, (label, colour)) in legend.iter().enumerate() {
        let x = PAD + (i % legend_cols) as i64 * col_w;
        let y = ly + (i / legend_cols) as i64 * 28;
        c.fill_rect(x, y, 20, 20, *colour);
        c.outline(x, y, 20, 20, [120, 120, 120]);
        let max = col_w as u32 - 40;
        let text = if text_size(label, 16.0, false).0 > max { shorten(label, max) } else { label.clone() };
        c.label(text, x + 30, y + 10, 16.0, Align::Left, false);
    }
    let ny = ly + legend_rows as i64 * 28 + 18;
    c.label(note, PAD, ny, 15.0, Align::Left, false);
    c.into_png()
}

/// `s` cut (with an ellipsis) to fit `max` px at 16 px.
fn shorten(s: &str, max: u32) -> String {
    let mut t: String = s.to_string();
    while !t.is_empty() && text_size(&format!("{t}…"), 16.0, false).0 > max {
        t.pop();
    }
    format!("{t}…")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::backend::decode_png;

    #[test]
    fn error_time_plot_marks_budgets_and_names_highlights() {
        let curve = |label: &str, k: f64, highlight| TimeCurve {
            label: label.into(),
            points: [1.0, 2.0, 4.0].map(|t: f64| (t, k / t, 0.01 * k / t)).to_vec(),
            highlight,
        };
        let curves =
            [curve("winner", 0.1, true), curve("paper default", 0.3, true), curve("ctx", 0.2, false)];
        let svg = error_time_plot("RMSE at equal time", "RMSE", &curves, &[1.5, 3.0], Format::Svg).unwrap();
        let svg = String::from_utf8(svg).unwrap();
        for want in [
            "winner",
            "paper default",
            "1 other configurations",
            "budgets",
            "1.5 ms",
            "3 ms",
            "thread CPU time",
        ] {
            assert!(svg.contains(want), "SVG lacks {want}");
        }
        assert!(!svg.contains(">ctx<"), "context curves are not in the legend");
        let (w, h, _) = decode_png(&error_time_plot("t", "y", &curves, &[2.0], Format::Png).unwrap());
        assert!(w > W && h == H, "{w}x{h}");
        assert!(error_time_plot("t", "y", &[], &[1.0], Format::Png).is_err());
        assert!(error_time_plot("t", "y", &curves, &[0.0], Format::Png).is_err());
        let bad = [TimeCurve { label: "b".into(), points: vec![(1.0, 0.0, 0.0)], highlight: true }];
        assert!(error_time_plot("t", "y", &bad, &[1.0], Format::Png).is_err());
    }

    #[test]
    fn winner_map_enlarges_panels_and_draws_the_colours() {
        let rgb = vec![WINNER_COLOURS[0], UNRESOLVED, OTHER_WINNER, [96, 112, 128]];
        let panel = |c: &str| Panel { caption: c.into(), width: 2, height: 2, rgb: rgb.clone() };
        let legend =
            vec![("a/b/c".to_string(), WINNER_COLOURS[0]), ("not significant".to_string(), UNRESOLVED)];
        let png = winner_map("Winner map", &[panel("1 ms"), panel("2 ms")], &legend, "note").unwrap();
        let (w, h, px) = decode_png(&png);
        assert!(w >= 900 && h > 420, "{w}x{h}");
        // The first panel's top-left image pixel, enlarged 210 times, is the first colour.
        let at = |x: u32, y: u32| px[(y * w + x) as usize];
        assert_eq!(at(16 + 100, 56 + 28 + 100), WINNER_COLOURS[0]);
        assert_eq!(at(16 + 210 + 100, 56 + 28 + 100), UNRESOLVED);
        assert!(winner_map("t", &[], &legend, "").is_err());
        let short = Panel { caption: "x".into(), width: 2, height: 2, rgb: vec![UNRESOLVED] };
        assert!(winner_map("t", &[short], &legend, "").is_err());
    }
}

//! The banding figure: a structured-error metric per configuration as horizontal bars.

use super::backend::{FONT, Format, render};
use super::canvas::text_size;
use super::plot::{W, bounds, series_style};
use plotters::coord::Shift;
use plotters::coord::ranged1d::SegmentValue;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Horizontal bars of a structured-error metric (e.g. the low-frequency ratio: 1 for independent
/// per-pixel noise, below for blue noise, above for blotches and bands) per configuration, mean ± sd
/// over replicates; `marks` are vertical lines at values a reader compares against (white noise, the
/// structured threshold), each labelled.
pub fn banding_plot(
    title: &str,
    x_label: &str,
    bars: &[(String, f64, f64)],
    marks: &[(f64, String)],
    format: Format,
) -> Result<Vec<u8>, String> {
    if bars.is_empty() {
        return Err("a banding plot needs at least one bar".into());
    }
    if let Some(b) = bars.iter().find(|b| !(b.1.is_finite() && b.2.is_finite() && b.2 >= 0.0)) {
        return Err(format!("bar '{}': mean {} ± sd {} must be finite with sd >= 0", b.0, b.1, b.2));
    }
    if let Some(m) = marks.iter().find(|m| !m.0.is_finite()) {
        return Err(format!("mark '{}' at {} must be finite", m.1, m.0));
    }
    let (lo, _) = bounds(bars.iter().map(|b| b.1 - b.2).chain(marks.iter().map(|m| m.0)).chain([0.0]));
    let (_, hi) = bounds(bars.iter().map(|b| b.1 + b.2).chain(marks.iter().map(|m| m.0)).chain([0.0]));
    let span = if hi - lo > 0.0 { hi - lo } else { 1.0 };
    let range = (lo - 0.05 * span * (lo < 0.0) as u8 as f64, hi + 0.25 * span);
    let label_w = bars.iter().map(|b| text_size(&b.0, 18.0, false).0).max().unwrap_or(0) + 24;
    let h = 140 + 44 * bars.len() as u32 + (MARK_LINE as usize * marks.len()) as u32;
    render!(format, W, h, |root: &DrawingArea<_, Shift>| draw_banding(
        root,
        (title, x_label),
        bars,
        marks,
        range,
        label_w
    ))
}

/// Height of a mark's label line above the bars, in pixels.
const MARK_LINE: i32 = 18;

fn draw_banding<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    (title, x_label): (&str, &str),
    bars: &[(String, f64, f64)],
    marks: &[(f64, String)],
    (x0, x1): (f64, f64),
    label_w: u32,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let n = bars.len();
    let area =
        root.margin(14, 0, 0, 0).titled(title, (FONT, 28.0, FontStyle::Bold).into_font()).map_err(err)?;
    let mut chart = ChartBuilder::on(&area)
        .margin(16)
        // Room between the title and the bars for the marks' labels, one line each.
        .margin_top(8 + MARK_LINE * marks.len() as i32)
        .x_label_area_size(56)
        .y_label_area_size(label_w)
        .build_cartesian_2d(x0..x1, (0..n - 1).into_segmented())
        .map_err(err)?;
    // Bars are listed top to bottom in the order given.
    let slot = |i: usize| n - 1 - i;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .axis_desc_style((FONT, 21.0))
        .label_style((FONT, 18.0))
        .y_labels(n)
        .y_label_formatter(&|v| match v {
            SegmentValue::CenterOf(j) if *j < n => bars[n - 1 - j].0.clone(),
            _ => String::new(),
        })
        .disable_y_mesh()
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(200, 200, 200))
        .draw()
        .map_err(err)?;
    // Marks first, so the bars and their numbers lie over the lines; each mark's label on its own
    // line above the bars, so that close marks cannot collide.
    let grey = RGBColor(110, 110, 110);
    let small = (FONT, 15.0).into_font().color(&grey).pos(Pos::new(HPos::Left, VPos::Bottom));
    for (k, (x, label)) in marks.iter().enumerate() {
        let top = (*x, SegmentValue::Last);
        let line = PathElement::new(vec![(*x, SegmentValue::Exact(0)), top.clone()], grey.stroke_width(1));
        chart.draw_series([line]).map_err(err)?;
        // The label in the margin above the plot, on the root's pixels (the chart clips to its own).
        let (px, py) = chart.backend_coord(&top);
        let rise = MARK_LINE * (marks.len() - k) as i32 - MARK_LINE + 4;
        root.draw(&PathElement::new(vec![(px, py), (px, py - rise)], grey.stroke_width(1))).map_err(err)?;
        root.draw(&Text::new(label.clone(), (px + 3, py - rise), small.clone())).map_err(err)?;
    }
    let font = (FONT, 17.0).into_font().color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center));
    for (i, (_, m, sd)) in bars.iter().enumerate() {
        let j = slot(i);
        let (c, _) = series_style(i);
        let mut rect = Rectangle::new(
            [(0.0, SegmentValue::Exact(j)), (*m, SegmentValue::Exact(j + 1))],
            c.mix(0.8).filled(),
        );
        rect.set_margin(7, 7, 0, 0);
        chart.draw_series([rect]).map_err(err)?;
        let y = SegmentValue::CenterOf(j);
        let (a, b) = (m - sd, m + sd);
        chart
            .draw_series([PathElement::new(vec![(a, y.clone()), (b, y.clone())], BLACK.stroke_width(2))])
            .map_err(err)?;
        for x in [a, b] {
            let cap = EmptyElement::at((x, y.clone()))
                + PathElement::new(vec![(0, -7), (0, 7)], BLACK.stroke_width(2));
            chart.draw_series([cap]).map_err(err)?;
        }
        let text = format!("{m:.3} ± {sd:.3}");
        let at = EmptyElement::at((b.max(0.0), y.clone())) + Text::new(text, (10, 0), font.clone());
        chart.draw_series([at]).map_err(err)?;
    }
    // The zero line, so negative (anti-correlated) values read as such.
    chart
        .draw_series([PathElement::new(
            vec![(0.0, SegmentValue::Exact(0)), (0.0, SegmentValue::Last)],
            BLACK.stroke_width(1),
        )])
        .map_err(err)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::backend::decode_png;

    #[test]
    fn banding_plot_lists_every_configuration() {
        let bars = vec![("random".to_string(), -0.02, 0.01), ("fibonacci static".to_string(), 0.95, 0.02)];
        let marks = [(1.0, "white noise".to_string()), (1.5, "structured".to_string())];
        let svg = banding_plot("Banding", "lag-1 autocorrelation", &bars, &marks, Format::Svg).unwrap();
        let svg = String::from_utf8(svg).unwrap();
        for label in [
            "<svg",
            "Banding",
            "lag-1 autocorrelation",
            "random",
            "fibonacci static",
            "0.950 ± 0.020",
            "white noise",
            "structured",
        ] {
            assert!(svg.contains(label), "SVG lacks {label}");
        }
        let (w, _, _) = decode_png(&banding_plot("b", "x", &bars, &marks, Format::Png).unwrap());
        assert_eq!(w, W);
        let one = vec![("only".to_string(), 0.0, 0.0)];
        assert!(banding_plot("b", "x", &one, &[], Format::Png).is_ok());
        assert!(banding_plot("b", "x", &[], &[], Format::Png).is_err());
        assert!(banding_plot("b", "x", &[("n".into(), f64::NAN, 0.0)], &[], Format::Png).is_err());
        assert!(banding_plot("b", "x", &[("n".into(), 0.1, -1.0)], &[], Format::Svg).is_err());
        assert!(banding_plot("b", "x", &one, &[(f64::INFINITY, "m".into())], Format::Svg).is_err());
    }
}

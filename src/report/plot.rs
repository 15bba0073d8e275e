//! Plots, one function per kind of figure: a log-log plot of per-configuration curves with error
//! bars in y (and optionally x) and guide lines (error against ray count or run time with the
//! reference's own noise as a floor and the per-image overhead as a wall; efficiency against ray
//! count), and the structured-error (banding) metric per configuration.

use super::axis::{Frame, log_log_chart};
use super::backend::{FONT, Format, render};
use super::canvas::text_size;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One configuration's curve: (x, y, spread of y) per point, optionally an x range per point
/// (e.g. min..max of timed renders; empty = none), and a note for the legend (e.g. its slope).
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64, f64)>,
    pub x_range: Vec<(f64, f64)>,
    pub note: Option<String>,
}

impl Series {
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64, f64)>) -> Self {
        Self { label: label.into(), points, x_range: Vec::new(), note: None }
    }
}

/// A guide across the plot, named in the legend.
#[derive(Debug, Clone, PartialEq)]
pub enum Guide {
    /// y = value and a band below it (e.g. the reference's noise floor: no error can be measured
    /// in the band). Far below the data it is not drawn, so it cannot squash the curves into a
    /// corner: the legend gives its value instead.
    Horizontal(f64, String),
    /// x = value (e.g. the time of an image with no AO rays).
    Vertical(f64, String),
}

impl Guide {
    fn value(&self) -> f64 {
        match self {
            Guide::Horizontal(v, _) | Guide::Vertical(v, _) => *v,
        }
    }

    /// Horizontal guides black, vertical ones grey, so the legend tells them apart.
    fn colour(&self) -> RGBColor {
        match self {
            Guide::Horizontal(..) => BLACK,
            Guide::Vertical(..) => RGBColor(130, 130, 130),
        }
    }

    fn label(&self) -> &str {
        match self {
            Guide::Horizontal(_, l) | Guide::Vertical(_, l) => l,
        }
    }
}

/// Tableau 10, then six darker colours unlike any of them and unlike the guides' black and grey
/// (a sweep may have a dozen rows, e.g. the paper's 12): distinguishable, and still
/// distinguishable for the common colour-vision deficiencies when paired with the marker shapes
/// below. Series from the eleventh on are also dashed.
pub(super) const PALETTE: [RGBColor; 16] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 128),
    RGBColor(128, 0, 0),
    RGBColor(0, 110, 100),
    RGBColor(200, 150, 0),
    RGBColor(190, 0, 190),
    RGBColor(90, 140, 0),
];

/// How far below the lowest point (error bar included) a horizontal guide may lie and still be
/// drawn: farther, and a third of the plot would be empty.
const GUIDE_REACH: f64 = 4.0;

/// Series `i`'s colour and whether its line is dashed (beyond Tableau's ten).
pub(super) fn series_style(i: usize) -> (RGBColor, bool) {
    (PALETTE[i % PALETTE.len()], i >= 10)
}
pub(super) const W: u32 = 960;
const H: u32 = 620;
const LEGEND_PX: f64 = 18.0;

/// Draws series `$i`'s marker at `$at` on `$area`; shapes cycle (circle, triangle, square) so
/// series stay apart in grey print and for readers who confuse colours.
macro_rules! marker {
    ($area:expr, $i:expr, $at:expr, $c:expr) => {{
        let c: RGBColor = $c;
        match $i % 3 {
            0 => $area.draw(&(EmptyElement::at($at) + Circle::new((0, 0), 5, c.filled()))),
            1 => $area.draw(&(EmptyElement::at($at) + TriangleMarker::new((0, 0), 7, c.filled()))),
            _ => $area.draw(&(EmptyElement::at($at) + Rectangle::new([(-4, -4), (5, 5)], c.filled()))),
        }
    }};
}

/// Log-log plot of y ± spread against x for every series (x error bars where a series has
/// `x_range`), with dashed guide lines; a horizontal guide such as the reference's noise floor
/// marks what no configuration can be measured below.
pub fn convergence_plot(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    guides: &[Guide],
    format: Format,
) -> Result<Vec<u8>, String> {
    if series.is_empty() {
        return Err("a convergence plot needs at least one series".into());
    }
    for s in series {
        if s.points.is_empty() {
            return Err(format!("series '{}' has no points", s.label));
        }
        if let Some(p) = s.points.iter().find(|(x, m, sd)| {
            !(x.is_finite() && *x > 0.0 && m.is_finite() && *m > 0.0 && sd.is_finite() && *sd >= 0.0)
        }) {
            return Err(format!(
                "series '{}': point {p:?} cannot go on a log-log plot (x and y must be positive, spread >= 0)",
                s.label
            ));
        }
        if !s.x_range.is_empty() && s.x_range.len() != s.points.len() {
            return Err(format!(
                "series '{}': {} x ranges for {} points",
                s.label,
                s.x_range.len(),
                s.points.len()
            ));
        }
        if let Some(r) =
            s.x_range.iter().find(|(a, b)| !(a.is_finite() && b.is_finite() && *a > 0.0 && a <= b))
        {
            return Err(format!("series '{}': x range {r:?} must be positive and ordered", s.label));
        }
    }
    if let Some(g) = guides.iter().find(|g| !(g.value().is_finite() && g.value() > 0.0)) {
        return Err(format!("guide '{}' at {} must be a positive number", g.label(), g.value()));
    }
    let pts = || series.iter().flat_map(|s| s.points.iter());
    let ranges = || series.iter().flat_map(|s| s.x_range.iter());
    let low = |p: &(f64, f64, f64)| if p.1 - p.2 > 0.0 { p.1 - p.2 } else { p.1 };
    let (data_low, _) = bounds(pts().map(low));
    // Horizontal guides far below the data stay off the axis (named in the legend with their value).
    let shown: Vec<Guide> = guides
        .iter()
        .filter(|g| !matches!(g, Guide::Horizontal(v, _) if *v < data_low / GUIDE_REACH))
        .cloned()
        .collect();
    let hs = || shown.iter().filter(|g| matches!(g, Guide::Horizontal(..))).map(Guide::value);
    let vs = || shown.iter().filter(|g| matches!(g, Guide::Vertical(..))).map(Guide::value);
    let (x0, _) = bounds(pts().map(|p| p.0).chain(ranges().map(|r| r.0)).chain(vs()));
    let (_, x1) = bounds(pts().map(|p| p.0).chain(ranges().map(|r| r.1)).chain(vs()));
    let (y0, _) = bounds(pts().map(low).chain(hs()));
    let (_, y1) = bounds(pts().map(|p| p.1 + p.2).chain(hs()));
    let ranges = (x0 / 1.25, x1 * 1.25, y0 / 1.4, y1 * 1.4);
    let entries: Vec<String> = series
        .iter()
        .map(|s| match &s.note {
            Some(n) => format!("{} ({n})", s.label),
            None => s.label.clone(),
        })
        .chain(guides.iter().map(|g| match g {
            Guide::Horizontal(v, l) if !shown.contains(g) => format!("{l}: {v:.1e} (below the axis)"),
            _ => g.label().to_string(),
        }))
        .collect();
    let legend_w = entries.iter().map(|e| text_size(e, LEGEND_PX, false).0).max().unwrap_or(0) + 70;
    let h = H.max(80 + 26 * entries.len() as u32);
    render!(format, W + legend_w, h, |root: &DrawingArea<_, Shift>| {
        draw_convergence(
            root,
            title,
            (x_label, y_label),
            series,
            (guides, &shown),
            Frame { ranges, entries: &entries, legend_w },
        )
    })
}

pub(super) fn bounds(v: impl Iterator<Item = f64>) -> (f64, f64) {
    v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)))
}

fn draw_convergence<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    (x_label, y_label): (&str, &str),
    series: &[Series],
    (guides, shown): (&[Guide], &[Guide]),
    frame: Frame,
) -> Result<(), String> {
    let Frame { ranges: (x0, x1, y0, y1), entries, legend_w } = frame;
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (w, _) = root.dim_in_pixel();
    let (plot, legend) = root.split_horizontally(w - legend_w);
    let mut chart = log_log_chart(&plot, title, (x_label, y_label), (x0, x1, y0, y1))?;
    // Bands first, under everything: below a noise floor no error can be measured.
    for g in shown {
        if let Guide::Horizontal(v, _) = g {
            chart
                .draw_series([Rectangle::new([(x0, y0), (x1, *v)], g.colour().mix(0.08).filled())])
                .map_err(err)?;
        }
    }
    for (i, s) in series.iter().enumerate() {
        let (c, dashed) = series_style(i);
        let line = s.points.iter().map(|p| (p.0, p.1));
        if dashed {
            chart.draw_series(DashedLineSeries::new(line, 9, 5, c.stroke_width(2))).map_err(err)?;
        } else {
            chart.draw_series(LineSeries::new(line, c.stroke_width(2))).map_err(err)?;
        }
        for &(x, m, sd) in &s.points {
            let lo = if m - sd > y0 { m - sd } else { y0 };
            let hi = (m + sd).min(y1);
            let cap =
                |y| EmptyElement::at((x, y)) + PathElement::new(vec![(-5, 0), (5, 0)], c.stroke_width(2));
            chart.draw_series([PathElement::new(vec![(x, lo), (x, hi)], c.stroke_width(2))]).map_err(err)?;
            chart.draw_series([cap(lo), cap(hi)]).map_err(err)?;
        }
        for (&(xa, xb), &(_, m, _)) in s.x_range.iter().zip(&s.points) {
            let (xa, xb) = (xa.max(x0), xb.min(x1));
            let tick =
                |x| EmptyElement::at((x, m)) + PathElement::new(vec![(0, -4), (0, 4)], c.stroke_width(1));
            chart.draw_series([PathElement::new(vec![(xa, m), (xb, m)], c.stroke_width(1))]).map_err(err)?;
            chart.draw_series([tick(xa), tick(xb)]).map_err(err)?;
        }
        for &(x, m, _) in &s.points {
            marker!(chart.plotting_area(), i, (x, m), c).map_err(err)?;
        }
    }
    for g in shown {
        let line = match g {
            Guide::Horizontal(v, _) => [(x0, *v), (x1, *v)],
            Guide::Vertical(v, _) => [(*v, y0), (*v, y1)],
        };
        chart.draw_series(DashedLineSeries::new(line, 10, 6, g.colour().stroke_width(2))).map_err(err)?;
    }
    let font = (FONT, LEGEND_PX).into_font().color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center));
    for (i, e) in entries.iter().enumerate() {
        let y = 70 + 26 * i as i32;
        if i < series.len() {
            let (c, dashed) = series_style(i);
            if dashed {
                for (a, b) in [(8, 16), (22, 30), (36, 44)] {
                    legend.draw(&PathElement::new(vec![(a, y), (b, y)], c.stroke_width(2))).map_err(err)?;
                }
            } else {
                legend.draw(&PathElement::new(vec![(8, y), (44, y)], c.stroke_width(2))).map_err(err)?;
            }
            marker!(legend, i, (26, y), c).map_err(err)?;
        } else {
            let c = guides[i - series.len()].colour();
            legend.draw(&PathElement::new(vec![(8, y), (20, y)], c.stroke_width(2))).map_err(err)?;
            legend.draw(&PathElement::new(vec![(30, y), (44, y)], c.stroke_width(2))).map_err(err)?;
        }
        legend.draw_text(e, &font, (54, y)).map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::backend::decode_png;

    fn signed(k: f64) -> String {
        format!("{}{:.2}", if k < 0.0 { "−" } else { "+" }, k.abs())
    }

    fn series(slope: f64, label: &str) -> Series {
        let points =
            [1.0, 4.0, 16.0, 64.0].map(|n: f64| (n, 0.3 * n.powf(slope), 0.02 * n.powf(slope))).to_vec();
        Series { note: Some(format!("slope {}", signed(slope))), ..Series::new(label, points) }
    }

    fn floor() -> Vec<Guide> {
        vec![Guide::Horizontal(1e-3, "reference noise floor".into())]
    }

    #[test]
    fn convergence_plot_is_png_and_svg_with_legend() {
        let s = [series(-0.5, "random"), series(-0.75, "fibonacci"), series(-1.0, "sobol")];
        let png = convergence_plot("RMSE", "rays", "RMSE", &s, &floor(), Format::Png).unwrap();
        let (w, h, _) = decode_png(&png);
        assert!(w > W && h == H, "{w}x{h}");
        let svg =
            convergence_plot("RMSE vs rays", "rays per pixel", "RMSE", &s, &floor(), Format::Svg).unwrap();
        let svg = String::from_utf8(svg).unwrap();
        for label in [
            "<svg",
            "RMSE vs rays",
            "rays per pixel",
            "random (slope −0.50)",
            "sobol (slope −1.00)",
            "reference noise floor",
        ] {
            assert!(svg.contains(label), "SVG lacks {label}");
        }
        let no_floor = convergence_plot("t", "x", "y", &s[..1], &[], Format::Svg).unwrap();
        assert!(!String::from_utf8(no_floor).unwrap().contains("noise floor"));
        // sd larger than the mean: the bar is cut at the axis instead of going to log(0).
        let wide = Series::new("w", vec![(1.0, 0.1, 0.5), (2.0, 0.05, 0.0)]);
        assert!(convergence_plot("t", "x", "y", &[wide], &[], Format::Png).is_ok());
        // x ranges and a vertical guide, e.g. timed renders' min..max and the overhead.
        let timed = Series {
            x_range: vec![(0.9, 1.2), (1.8, 2.1)],
            ..Series::new("t", vec![(1.0, 0.1, 0.01), (2.0, 0.05, 0.0)])
        };
        let wall = [Guide::Vertical(0.5, "no AO rays".into())];
        let svg = String::from_utf8(convergence_plot("t", "x", "y", &[timed], &wall, Format::Svg).unwrap())
            .unwrap();
        assert!(svg.contains("no AO rays"));
    }

    /// The tick labels of an SVG plot: the short texts that parse as numbers.
    fn numbers(svg: &str) -> Vec<f64> {
        svg.split('>')
            .filter_map(|t| t.split('<').next())
            .filter_map(|t| t.trim().parse::<f64>().ok())
            .collect()
    }

    #[test]
    fn a_short_log_axis_gets_enough_ticks() {
        // Render times from 1.7 to 50 ms, as on a fast scene: 2, 5, 10, 20 (and 50 at the end) labelled.
        let s = Series::new("t", vec![(1.7, 0.3, 0.0), (6.0, 0.1, 0.0), (50.0, 0.03, 0.0)]);
        let svg =
            String::from_utf8(convergence_plot("t", "ms", "RMSE", &[s], &[], Format::Svg).unwrap()).unwrap();
        let x: Vec<f64> = numbers(&svg).into_iter().filter(|&v| v >= 1.0).collect();
        assert!(x.len() >= 4, "only {x:?} labelled on a 1.7–50 ms axis");
        for want in [2.0, 5.0, 10.0, 20.0] {
            assert!(x.contains(&want), "{want} unlabelled: {x:?}");
        }
    }

    #[test]
    fn a_floor_far_below_the_data_stays_off_the_axis() {
        let s = [series(-0.5, "random")];
        // 0.3 · 64^−0.5 ± 0.02 · 64^−0.5: the data reach down to about 0.035.
        let near = [Guide::Horizontal(0.02, "reference noise floor".into())];
        let svg =
            String::from_utf8(convergence_plot("t", "x", "y", &s, &near, Format::Svg).unwrap()).unwrap();
        assert!(svg.contains("reference noise floor") && !svg.contains("below the axis"), "drawn when near");
        let far = [Guide::Horizontal(7e-5, "reference noise floor".into())];
        let svg = String::from_utf8(convergence_plot("t", "x", "y", &s, &far, Format::Svg).unwrap()).unwrap();
        assert!(
            svg.contains("reference noise floor: 7.0e-5 (below the axis)"),
            "named with its value instead"
        );
        let lowest = numbers(&svg).into_iter().filter(|&v| v > 0.0 && v < 1.0).fold(1.0, f64::min);
        assert!(lowest > 1e-3, "the y axis stays near the data: lowest tick {lowest}");
    }

    #[test]
    fn twelve_series_have_twelve_styles() {
        let styles: Vec<_> = (0..16).map(series_style).collect();
        for (i, a) in styles.iter().enumerate() {
            assert!(styles[..i].iter().all(|b| b != a), "series {i} looks like an earlier one");
        }
    }

    #[test]
    fn convergence_plot_rejects_what_a_log_axis_cannot_show() {
        let p = |points| vec![Series::new("s", points)];
        let f = Format::Png;
        assert!(convergence_plot("t", "x", "y", &[], &[], f).is_err());
        assert!(convergence_plot("t", "x", "y", &p(vec![]), &[], f).is_err());
        assert!(convergence_plot("t", "x", "y", &p(vec![(0.0, 0.1, 0.0)]), &[], f).is_err());
        assert!(convergence_plot("t", "x", "y", &p(vec![(1.0, 0.0, 0.0)]), &[], f).is_err());
        assert!(convergence_plot("t", "x", "y", &p(vec![(1.0, f64::NAN, 0.0)]), &[], f).is_err());
        assert!(convergence_plot("t", "x", "y", &p(vec![(1.0, 0.1, -0.1)]), &[], f).is_err());
        let zero = [Guide::Horizontal(0.0, "floor".into())];
        assert!(convergence_plot("t", "x", "y", &p(vec![(1.0, 0.1, 0.0)]), &zero, f).is_err());
        let bad_range = Series { x_range: vec![(2.0, 1.0)], ..Series::new("s", vec![(1.0, 0.1, 0.0)]) };
        assert!(convergence_plot("t", "x", "y", &[bad_range], &[], f).is_err());
        let short = Series { x_range: vec![], ..Series::new("s", vec![(1.0, 0.1, 0.0)]) };
        assert!(convergence_plot("t", "x", "y", &[short], &[], f).is_ok(), "one point is a plot");
    }
}

//! Plots, one function per kind of figure: a log-log plot of per-configuration curves with error
//! bars in y (and optionally x) and guide lines (error against ray count or run time with the
//! reference's own noise as a floor and the per-image overhead as a wall; efficiency against ray
//! count), and the structured-error (banding) metric per configuration.

use super::canvas::text_size;
use super::{FONT, Format, render};
use plotters::coord::Shift;
use plotters::coord::ranged1d::SegmentValue;
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

/// A dashed guide line across the plot, named in the legend.
#[derive(Debug, Clone, PartialEq)]
pub enum Guide {
    /// y = value (e.g. the reference's noise floor).
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

/// Tableau 10: distinguishable, and still distinguishable for the common colour-vision deficiencies
/// when paired with the marker shapes below.
pub(super) const PALETTE: [RGBColor; 10] = [
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
];
const W: u32 = 960;
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
    let hs = || guides.iter().filter(|g| matches!(g, Guide::Horizontal(..))).map(Guide::value);
    let vs = || guides.iter().filter(|g| matches!(g, Guide::Vertical(..))).map(Guide::value);
    let (x0, _) = bounds(pts().map(|p| p.0).chain(ranges().map(|r| r.0)).chain(vs()));
    let (_, x1) = bounds(pts().map(|p| p.0).chain(ranges().map(|r| r.1)).chain(vs()));
    let lows = pts().map(|p| if p.1 - p.2 > 0.0 { p.1 - p.2 } else { p.1 }).chain(hs());
    let (y0, _) = bounds(lows);
    let (_, y1) = bounds(pts().map(|p| p.1 + p.2).chain(hs()));
    let ranges = (x0 / 1.25, x1 * 1.25, y0 / 1.4, y1 * 1.4);
    let entries: Vec<String> = series
        .iter()
        .map(|s| match &s.note {
            Some(n) => format!("{} ({n})", s.label),
            None => s.label.clone(),
        })
        .chain(guides.iter().map(|g| g.label().to_string()))
        .collect();
    let legend_w = entries.iter().map(|e| text_size(e, LEGEND_PX, false).0).max().unwrap_or(0) + 70;
    let h = H.max(80 + 26 * entries.len() as u32);
    render!(format, W + legend_w, h, |root: &DrawingArea<_, Shift>| {
        draw_convergence(root, title, (x_label, y_label), series, guides, ranges, &entries, legend_w)
    })
}

fn bounds(v: impl Iterator<Item = f64>) -> (f64, f64) {
    v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)))
}

#[allow(clippy::too_many_arguments)]
fn draw_convergence<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    (x_label, y_label): (&str, &str),
    series: &[Series],
    guides: &[Guide],
    (x0, x1, y0, y1): (f64, f64, f64, f64),
    entries: &[String],
    legend_w: u32,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let (w, _) = root.dim_in_pixel();
    let (plot, legend) = root.split_horizontally(w - legend_w);
    let mut chart = ChartBuilder::on(&plot)
        .caption(title, (FONT, 28.0, FontStyle::Bold).into_font())
        .margin(16)
        .x_label_area_size(56)
        .y_label_area_size(84)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .axis_desc_style((FONT, 21.0))
        .label_style((FONT, 18.0))
        .x_label_formatter(&|v| log_tick(*v, x1 / x0))
        .y_label_formatter(&|v| log_tick(*v, y1 / y0))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(200, 200, 200))
        .draw()
        .map_err(err)?;
    for (i, s) in series.iter().enumerate() {
        let c = PALETTE[i % PALETTE.len()];
        chart
            .draw_series(LineSeries::new(s.points.iter().map(|p| (p.0, p.1)), c.stroke_width(2)))
            .map_err(err)?;
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
    for g in guides {
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
            let c = PALETTE[i % PALETTE.len()];
            legend.draw(&PathElement::new(vec![(8, y), (44, y)], c.stroke_width(2))).map_err(err)?;
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

/// Tick text on a log axis spanning `ratio` (max / min): over more than a decade plotters puts a
/// tick at every 1..9 × 10^k, whose labels overlap near each decade's end, so only 1, 2 and 5 ×
/// 10^k are labelled (the grid lines stay).
pub(super) fn log_tick(v: f64, ratio: f64) -> String {
    if ratio > 10.0 && v > 0.0 {
        let m = v / 10f64.powf(v.log10().floor());
        if ![1.0, 2.0, 5.0, 10.0].iter().any(|k| (m - k).abs() < 1e-6 * k) {
            return String::new();
        }
    }
    tick(v)
}

/// Tick text for log axes: plain numbers for the usual range, exponent form outside it.
fn tick(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        let digits = (3 - a.log10().floor() as i32 - 1).clamp(0, 4) as usize;
        let s = format!("{v:.digits$}");
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
    } else {
        format!("{v:.0e}")
    }
}

/// Horizontal bars of a structured-error metric (e.g. lag-1 error autocorrelation: near 0 for
/// independent per-pixel noise, near 1 for banding) per configuration, mean ± sd over replicates.
pub fn banding_plot(
    title: &str,
    x_label: &str,
    bars: &[(String, f64, f64)],
    format: Format,
) -> Result<Vec<u8>, String> {
    if bars.is_empty() {
        return Err("a banding plot needs at least one bar".into());
    }
    if let Some(b) = bars.iter().find(|b| !(b.1.is_finite() && b.2.is_finite() && b.2 >= 0.0)) {
        return Err(format!("bar '{}': mean {} ± sd {} must be finite with sd >= 0", b.0, b.1, b.2));
    }
    let (lo, _) = bounds(bars.iter().map(|b| b.1 - b.2).chain([0.0]));
    let (_, hi) = bounds(bars.iter().map(|b| b.1 + b.2).chain([0.0]));
    let span = if hi - lo > 0.0 { hi - lo } else { 1.0 };
    let range = (lo - 0.05 * span * (lo < 0.0) as u8 as f64, hi + 0.25 * span);
    let label_w = bars.iter().map(|b| text_size(&b.0, 18.0, false).0).max().unwrap_or(0) + 24;
    let h = 140 + 44 * bars.len() as u32;
    render!(format, W, h, |root: &DrawingArea<_, Shift>| draw_banding(
        root, title, x_label, bars, range, label_w
    ))
}

fn draw_banding<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    bars: &[(String, f64, f64)],
    (x0, x1): (f64, f64),
    label_w: u32,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let n = bars.len();
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, 28.0, FontStyle::Bold).into_font())
        .margin(16)
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
    let font = (FONT, 17.0).into_font().color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center));
    for (i, (_, m, sd)) in bars.iter().enumerate() {
        let j = slot(i);
        let c = PALETTE[i % PALETTE.len()];
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
    use crate::report::decode_png;

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

    #[test]
    fn banding_plot_lists_every_configuration() {
        let bars = vec![("random".to_string(), -0.02, 0.01), ("fibonacci static".to_string(), 0.95, 0.02)];
        let svg =
            String::from_utf8(banding_plot("Banding", "lag-1 autocorrelation", &bars, Format::Svg).unwrap())
                .unwrap();
        for label in
            ["<svg", "Banding", "lag-1 autocorrelation", "random", "fibonacci static", "0.950 ± 0.020"]
        {
            assert!(svg.contains(label), "SVG lacks {label}");
        }
        let (w, _, _) = decode_png(&banding_plot("b", "x", &bars, Format::Png).unwrap());
        assert_eq!(w, W);
        let one = vec![("only".to_string(), 0.0, 0.0)];
        assert!(banding_plot("b", "x", &one, Format::Png).is_ok());
        assert!(banding_plot("b", "x", &[], Format::Png).is_err());
        assert!(banding_plot("b", "x", &[("n".into(), f64::NAN, 0.0)], Format::Png).is_err());
        assert!(banding_plot("b", "x", &[("n".into(), 0.1, -1.0)], Format::Svg).is_err());
    }

    #[test]
    fn ticks_read_as_plain_numbers() {
        assert_eq!(tick(1.0), "1");
        assert_eq!(tick(1000.0), "1000");
        assert_eq!(tick(0.001), "0.001");
        assert_eq!(tick(0.05), "0.05");
        assert_eq!(tick(1e-5), "1e-5");
        assert_eq!(log_tick(0.05, 100.0), "0.05");
        assert_eq!(log_tick(0.07, 100.0), "", "crowded ticks of a wide axis go unlabelled");
        assert_eq!(log_tick(0.07, 3.0), "0.07", "a narrow axis keeps them");
        assert_eq!(log_tick(100.0, 1000.0), "100");
    }
}

//! Plots, one function per kind of figure: a log-log plot of per-configuration curves with error
//! bars in y (and optionally x) and guide lines (error against ray count or run time with the
//! reference's own noise as a floor and the per-image overhead as a wall; efficiency against ray
//! count), and the structured-error (banding) metric per configuration.

use super::canvas::text_size;
use super::{FONT, Format, render};
use plotters::coord::Shift;
use plotters::coord::combinators::{LogCoord, WithKeyPoints};
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
fn series_style(i: usize) -> (RGBColor, bool) {
    (PALETTE[i % PALETTE.len()], i >= 10)
}
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
            ranges,
            &entries,
            legend_w,
        )
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
    (guides, shown): (&[Guide], &[Guide]),
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
        .build_cartesian_2d(log_axis(x0, x1), log_axis(y0, y1))
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .axis_desc_style((FONT, 21.0))
        .label_style((FONT, 18.0))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(200, 200, 200))
        .draw()
        .map_err(err)?;
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

/// A log axis from `lo` to `hi` with its ticks chosen here: plotters ticks a log axis only from the
/// first power of ten inside it, so a 1.7–50 ms axis got 10, 20 and 50 alone. Labelled: 1, 2 and
/// 5 × 10^k (every 1..9 × 10^k on an axis within a decade, and more decades than fit: powers of
/// ten only); grid lines at every 1..9 × 10^k.
fn log_axis(lo: f64, hi: f64) -> WithKeyPoints<LogCoord<f64>> {
    let (bold, light) = log_ticks(lo, hi);
    (lo..hi).log_scale().with_key_points(bold).with_light_points(light)
}

/// (labelled, grid-only) tick values of a log axis over [lo, hi].
fn log_ticks(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let decades = (hi / lo).log10();
    let labelled: &[f64] = if decades <= 1.0 {
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    } else if decades <= 5.0 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0]
    };
    let (mut bold, mut light) = (Vec::new(), Vec::new());
    for k in lo.log10().floor() as i32..=hi.log10().ceil() as i32 {
        for m in 1..=9 {
            // Through the decimal text, so 0.3 is 0.3 and not 0.30000000000000004.
            let v: f64 = format!("{m}e{k}").parse().unwrap_or(f64::NAN);
            if v >= lo && v <= hi {
                if labelled.contains(&(m as f64)) { bold.push(v) } else { light.push(v) }
            }
        }
    }
    (bold, light)
}

/// Tick text on a log axis spanning `ratio` (max / min): over more than a decade only 1, 2 and 5 ×
/// 10^k are labelled (for plots that keep plotters' own ticks, e.g. `advice`).
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
        let (bold, light) = log_ticks(0.004, 0.3);
        assert_eq!(bold, [0.005, 0.01, 0.02, 0.05, 0.1, 0.2], "crowded ticks of a wide axis go unlabelled");
        assert!(light.contains(&0.07) && light.contains(&0.3) && !light.contains(&0.05));
        assert_eq!(
            log_ticks(1.7, 9.0).0,
            [2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
            "a narrow axis keeps them"
        );
        assert_eq!(
            log_ticks(0.5, 2e6).0,
            [1.0, 10.0, 100.0, 1e3, 1e4, 1e5, 1e6],
            "many decades: powers of ten"
        );
    }
}

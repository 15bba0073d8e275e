//! Log axes with ticks chosen here, shared by every log-log figure (convergence, efficiency,
//! advise's error against time).

use super::backend::FONT;
use plotters::coord::Shift;
use plotters::coord::combinators::{LogCoord, WithKeyPoints};
use plotters::prelude::*;

/// The caption's type size, when the title fits.
const TITLE_PX: f64 = 27.0;

/// A log-log figure's frame: its data ranges (x0, x1, y0, y1), and its legend's entries and width
/// in pixels.
pub(super) struct Frame<'a> {
    pub ranges: (f64, f64, f64, f64),
    pub entries: &'a [String],
    pub legend_w: u32,
}

/// A log-log chart's coordinates.
pub(super) type LogLog = Cartesian2d<WithKeyPoints<LogCoord<f64>>, WithKeyPoints<LogCoord<f64>>>;

/// The log-log chart of every error figure (convergence, efficiency, advise's error against time):
/// caption, axis labels, these log axes, grid and tick text in one look. `plot`: the area left of
/// the figure's legend.
pub(super) fn log_log_chart<'a, DB: DrawingBackend>(
    plot: &'a DrawingArea<DB, Shift>,
    title: &str,
    (x_label, y_label): (&str, &str),
    (x0, x1, y0, y1): (f64, f64, f64, f64),
) -> Result<ChartContext<'a, DB, LogLog>, String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    // A title wider than the plot would be cut at both ends: smaller type instead.
    let width = plot.dim_in_pixel().0 as f64 - 24.0;
    let wide = super::canvas::text_size(title, TITLE_PX, true).0 as f64;
    let px = if wide > width { (TITLE_PX * width / wide).max(12.0) } else { TITLE_PX };
    let mut chart = ChartBuilder::on(plot)
        .caption(title, (FONT, px, FontStyle::Bold).into_font())
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
        .light_line_style(RGBColor(236, 236, 236))
        .bold_line_style(RGBColor(202, 202, 202))
        .draw()
        .map_err(err)?;
    Ok(chart)
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

/// Tick text for log axes: plain numbers for the usual range, exponent form outside it.
pub(super) fn tick(v: f64) -> String {
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

#[cfg(test)]
mod tests {
    use super::*;

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

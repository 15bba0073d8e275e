//! Point sets on the hemisphere as the paper draws them (Table 1, Figures 2-4): a top view of the
//! unit disk (x, y), and optionally a side view (x, z) that shows how points crowd towards the pole
//! or thin out towards the horizon.

use super::backend::{FONT, Format, render};
use super::canvas::text_size;
use crate::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use glam::{Vec2, Vec3};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One panel: unit directions in the local frame (z = normal) and the panel's title.
pub struct PointSet {
    pub title: String,
    pub dirs: Vec<Vec3>,
}

const R: i32 = 140;
const PAD: i32 = 18;
const TITLE_H: i32 = 54;
const HEAD_H: i32 = 36;
/// Room under the top view for its label.
const TOP_LABEL_H: i32 = 26;
const POINT: RGBColor = RGBColor(20, 50, 140);
const EDGE: RGBColor = RGBColor(150, 150, 150);

/// A table of panels: `rows` are (row label, panels); every row must have the same number of panels.
pub fn point_panels(
    title: &str,
    rows: &[(String, Vec<PointSet>)],
    side_view: bool,
    format: Format,
) -> Result<Vec<u8>, String> {
    validate(rows)?;
    let ncols = rows[0].1.len() as i32;
    let left = rows.iter().map(|(l, _)| text_size(l, 21.0, true).0 as i32).max().unwrap_or(0) + 2 * PAD;
    let left = if rows.len() == 1 && rows[0].0.is_empty() { PAD } else { left };
    let panel_w = 2 * R + 2 * PAD;
    let panel_h = HEAD_H + 2 * R + TOP_LABEL_H + PAD + if side_view { R + PAD + 30 } else { 0 };
    let w = (left + ncols * panel_w + PAD) as u32;
    let h = (TITLE_H + rows.len() as i32 * panel_h + PAD) as u32;
    let title_w = text_size(title, 28.0, true).0 + 2 * PAD as u32;
    // A title wider than the panels: the panels go in the middle, under it.
    let left = left + (title_w.saturating_sub(w) / 2) as i32;
    let w = w.max(title_w);
    render!(format, w, h, |root: &DrawingArea<_, Shift>| draw(
        root, title, rows, side_view, left, panel_w, panel_h
    ))
}

fn validate(rows: &[(String, Vec<PointSet>)]) -> Result<(), String> {
    let ncols = rows.first().map(|r| r.1.len()).unwrap_or(0);
    if ncols == 0 {
        return Err("a point figure needs at least one row with at least one panel".into());
    }
    for (label, sets) in rows {
        if sets.len() != ncols {
            return Err(format!("row '{label}' has {} panels, the first row has {ncols}", sets.len()));
        }
        for s in sets {
            if s.dirs.is_empty() {
                return Err(format!("panel '{}' of row '{label}' has no points", s.title));
            }
            if let Some((i, d)) = s
                .dirs
                .iter()
                .enumerate()
                .find(|(_, d)| !d.is_finite() || d.z < -1e-4 || (d.length() - 1.0).abs() > 1e-3)
            {
                return Err(format!(
                    "panel '{}' of row '{label}': point {i} = {d} is not a unit direction on the upper hemisphere",
                    s.title
                ));
            }
        }
    }
    Ok(())
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    rows: &[(String, Vec<PointSet>)],
    side_view: bool,
    left: i32,
    panel_w: i32,
    panel_h: i32,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let centred = |px: f64| (FONT, px).into_font().color(&BLACK).pos(Pos::new(HPos::Center, VPos::Center));
    let (w, _) = root.dim_in_pixel();
    let bold =
        (FONT, 28.0, FontStyle::Bold).into_font().color(&BLACK).pos(Pos::new(HPos::Center, VPos::Center));
    root.draw_text(title, &bold, (w as i32 / 2, TITLE_H / 2)).map_err(err)?;
    let row_font =
        (FONT, 21.0, FontStyle::Bold).into_font().color(&BLACK).pos(Pos::new(HPos::Right, VPos::Center));
    for (r, (label, sets)) in rows.iter().enumerate() {
        let y0 = TITLE_H + r as i32 * panel_h;
        if !label.is_empty() {
            root.draw_text(label, &row_font, (left - PAD, y0 + HEAD_H + R)).map_err(err)?;
        }
        for (c, set) in sets.iter().enumerate() {
            let cx = left + c as i32 * panel_w + panel_w / 2;
            root.draw_text(&set.title, &centred(20.0), (cx, y0 + HEAD_H / 2)).map_err(err)?;
            let cy = y0 + HEAD_H + R;
            let radius = dot_radius(set.dirs.len());
            root.draw(&Circle::new((cx, cy), R, EDGE.stroke_width(1))).map_err(err)?;
            let to_px =
                |a: f32, b: f32| (cx + (a * R as f32).round() as i32, cy - (b * R as f32).round() as i32);
            for d in &set.dirs {
                root.draw(&Circle::new(to_px(d.x, d.y), radius, POINT.filled())).map_err(err)?;
            }
            root.draw_text("top view (x, y)", &centred(18.0), (cx, cy + R + TOP_LABEL_H / 2 + 2))
                .map_err(err)?;
            if side_view {
                let by = cy + R + TOP_LABEL_H + PAD + R;
                let arc: Vec<(i32, i32)> = (0..=64)
                    .map(|k| {
                        let a = std::f32::consts::PI * k as f32 / 64.0;
                        (cx + (R as f32 * a.cos()).round() as i32, by - (R as f32 * a.sin()).round() as i32)
                    })
                    .collect();
                root.draw(&PathElement::new(arc, EDGE.stroke_width(1))).map_err(err)?;
                root.draw(&PathElement::new(vec![(cx - R, by), (cx + R, by)], EDGE.stroke_width(1)))
                    .map_err(err)?;
                let side =
                    |d: &Vec3| (cx + (d.x * R as f32).round() as i32, by - (d.z * R as f32).round() as i32);
                for d in &set.dirs {
                    root.draw(&Circle::new(side(d), radius, POINT.filled())).map_err(err)?;
                }
                root.draw_text("side view (x, z)", &centred(18.0), (cx, by + 16)).map_err(err)?;
            }
        }
    }
    Ok(())
}

/// Dots shrink with the count so 5000 points stay distinguishable yet 500 remain visible
/// (whole pixels: the bitmap backend rounds radii anyway, and equal counts must look alike).
fn dot_radius(n: usize) -> i32 {
    if n <= 1500 { 2 } else { 1 }
}

/// The `count` directions (local frame, z = normal) of pixel 0 of an image sampled with these
/// settings: exactly the set the renderer would use there.
pub fn directions(
    distribution: Distribution,
    sequence: Sequence,
    seed_mode: SeedMode,
    count: u32,
    seed: u64,
) -> crate::error::Result<Vec<Vec3>> {
    let config = SamplerConfig::new(sequence, seed_mode, count, seed)
        .map_err(|e| crate::error::Error::Usage(e.to_string()))?;
    Ok(directions_of(distribution, config))
}

/// As `directions`, for a whole configuration (any frame and schedule).
pub fn directions_of(distribution: Distribution, config: SamplerConfig) -> Vec<Vec3> {
    let mut pts = vec![Vec2::ZERO; config.count as usize];
    config.fill_pixel(0, 0, 0, &mut pts);
    pts.into_iter().map(|u| distribution.sample(u).dir).collect()
}

/// The pixels and frames a grid of a per-pixel seed mode shows (`pixel_frame_rows`): four
/// neighbouring pixels of an image this wide, over three consecutive frames.
pub const GRID_PIXELS: [(u32, u32); 4] = [(0, 0), (1, 0), (0, 1), (1, 1)];
pub const GRID_FRAMES: u32 = 3;
pub const GRID_WIDTH: u32 = 64;

/// Rows of a grid of pixels × frames: a per-pixel seed mode moves the set from pixel to pixel and
/// (by its schedule) from frame to frame, so one panel of pixel 0 says little. Row "frame f" for
/// f from `config.frame`, a panel per pixel (x, y) of an image `GRID_WIDTH` pixels wide: exactly
/// the sets the renderer would use there.
pub fn pixel_frame_rows(distribution: Distribution, config: SamplerConfig) -> Vec<(String, Vec<PointSet>)> {
    (config.frame..config.frame + GRID_FRAMES)
        .map(|f| {
            let c = config.with_frame(f);
            let sets = GRID_PIXELS
                .iter()
                .map(|&(x, y)| {
                    let mut pts = vec![Vec2::ZERO; c.count as usize];
                    c.fill_pixel(x, y, y as u64 * GRID_WIDTH as u64 + x as u64, &mut pts);
                    let dirs = pts.into_iter().map(|u| distribution.sample(u).dir).collect();
                    PointSet { title: format!("pixel ({x}, {y})"), dirs }
                })
                .collect();
            (format!("frame {f}"), sets)
        })
        .collect()
}

/// Rows of a point figure: one row per distribution, one panel per point count ("500 points"), all
/// from pixel 0 of `sequence` with `seed`. Table 1 is the Fibonacci lattice through the three
/// distributions; Figures 2-4 are one pseudo-random row each.
pub fn figure_rows(
    distributions: &[Distribution],
    sequence: Sequence,
    seed_mode: SeedMode,
    counts: &[u32],
    seed: u64,
) -> crate::error::Result<Vec<(String, Vec<PointSet>)>> {
    distributions
        .iter()
        .map(|&d| {
            let sets = counts
                .iter()
                .map(|&n| {
                    Ok(PointSet {
                        title: format!("{n} points"),
                        dirs: directions(d, sequence, seed_mode, n, seed)?,
                    })
                })
                .collect::<crate::error::Result<Vec<_>>>()?;
            Ok((d.name().to_string(), sets))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::backend::decode_png;

    fn ring(n: usize, z: f32) -> Vec<Vec3> {
        let s = (1.0 - z * z).sqrt();
        (0..n).map(|i| (i as f32 * 0.1).sin_cos()).map(|(a, b)| Vec3::new(s * b, s * a, z)).collect()
    }

    #[test]
    fn panels_are_png_and_svg_with_their_labels() {
        let rows: Vec<(String, Vec<PointSet>)> = ["uniform", "sine-cosine"]
            .iter()
            .map(|r| {
                let sets =
                    [10, 20, 2000].map(|n| PointSet { title: format!("{n} points"), dirs: ring(n, 0.5) });
                (r.to_string(), sets.into_iter().collect())
            })
            .collect();
        let (w, h, px) = decode_png(&point_panels("Table 1", &rows, true, Format::Png).unwrap());
        assert!(w >= 3 * 2 * R as u32 && h >= 2 * 3 * R as u32, "{w}x{h}");
        assert!(px.contains(&[POINT.0, POINT.1, POINT.2]), "points are drawn");
        let svg = String::from_utf8(point_panels("Table 1", &rows, false, Format::Svg).unwrap()).unwrap();
        for label in ["<svg", "Table 1", "sine-cosine", "2000 points"] {
            assert!(svg.contains(label), "SVG lacks {label}");
        }
        assert!(!svg.contains("side view"));
        assert_eq!(svg.matches("top view (x, y)").count(), 6, "every panel's top view is labelled");
    }

    #[test]
    fn points_land_inside_the_disk() {
        // The horizon (z = 0) is the disk's rim: every dot centre must be within R of the centre.
        let rows = vec![(String::new(), vec![PointSet { title: "p".into(), dirs: ring(200, 0.0) }])];
        let svg = String::from_utf8(point_panels("t", &rows, false, Format::Svg).unwrap()).unwrap();
        let num = |s: &str, key: &str| -> f32 {
            let i = s.find(key).unwrap() + key.len();
            s[i..].split('"').next().unwrap().parse().unwrap()
        };
        let circles: Vec<&str> = svg.split("<circle").skip(1).collect();
        let (cx, cy) = (num(circles[0], "cx=\""), num(circles[0], "cy=\""));
        assert_eq!(num(circles[0], "r=\""), R as f32, "first circle is the disk outline");
        for c in &circles[1..] {
            let d = (num(c, "cx=\"") - cx).hypot(num(c, "cy=\"") - cy);
            assert!(
                d <= R as f32 + 0.75,
                "dot {d} px from the centre (rounding to whole pixels allows 0.71)"
            );
        }
    }

    #[test]
    fn empty_or_off_hemisphere_points_are_errors() {
        let set = |dirs| vec![(String::from("r"), vec![PointSet { title: "p".into(), dirs }])];
        assert!(point_panels("t", &[], false, Format::Png).is_err());
        assert!(point_panels("t", &set(vec![]), false, Format::Png).is_err());
        assert!(point_panels("t", &set(vec![Vec3::new(0.0, 0.0, -1.0)]), false, Format::Png).is_err());
        assert!(point_panels("t", &set(vec![Vec3::new(f32::NAN, 0.0, 1.0)]), false, Format::Svg).is_err());
        assert!(point_panels("t", &set(vec![Vec3::new(0.0, 0.0, 2.0)]), false, Format::Svg).is_err());
        let mut ragged = set(vec![Vec3::Z]);
        ragged.push(("r2".into(), vec![]));
        assert!(point_panels("t", &ragged, false, Format::Png).is_err());
    }

    #[test]
    fn a_per_pixel_seed_mode_draws_pixels_by_frames_and_they_differ() {
        let c = SamplerConfig::new(Sequence::Fibonacci, SeedMode::Rotation, 16, 1).unwrap().with_frame(5);
        let rows = pixel_frame_rows(Distribution::SineCosine, c);
        assert_eq!(rows.iter().map(|r| r.0.as_str()).collect::<Vec<_>>(), ["frame 5", "frame 6", "frame 7"]);
        assert!(rows.iter().all(|r| r.1.len() == GRID_PIXELS.len()));
        assert_eq!(rows[0].1[1].title, "pixel (1, 0)");
        // Pixel (0, 0) of the first frame is the single panel's set; pixels and frames differ.
        assert_eq!(rows[0].1[0].dirs, directions_of(Distribution::SineCosine, c));
        assert_ne!(rows[0].1[0].dirs, rows[0].1[1].dirs);
        assert_ne!(rows[0].1[0].dirs, rows[1].1[0].dirs);
        assert!(point_panels("grid", &rows, false, Format::Svg).is_ok());
    }

    #[test]
    fn figure_rows_have_one_panel_per_count_on_the_hemisphere() {
        let ds = [Distribution::Uniform, Distribution::Sine, Distribution::SineCosine];
        let rows = figure_rows(&ds, Sequence::Fibonacci, SeedMode::Static, &[5, 50], 1).unwrap();
        assert_eq!(rows.iter().map(|r| r.0.as_str()).collect::<Vec<_>>(), ["uniform", "sine", "sine-cosine"]);
        for (_, sets) in &rows {
            assert_eq!(sets.iter().map(|s| s.dirs.len()).collect::<Vec<_>>(), [5, 50]);
            assert!(sets.iter().flat_map(|s| &s.dirs).all(|d| d.z >= 0.0 && (d.length() - 1.0).abs() < 1e-4));
        }
        assert!(figure_rows(&ds, Sequence::Random, SeedMode::Static, &[0], 1).is_err());
    }
}

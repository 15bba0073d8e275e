//! The paper's Tables 2 and 3 as pictures: AO images in a rows × columns table, each labelled with
//! its row, column and caption (RMSE, error autocorrelation), the reference beside; and the same
//! layout showing the signed error (image − reference) in a diverging colour map with its scale, or
//! per-pixel FLIP maps (computed by the caller) in magma.

use super::canvas::{Align, Canvas, text_size};
use super::colormap::{BACKGROUND, diverging, grey, magma};
use crate::image::Image;

/// One table cell: an AO image (1 = open = white), its coverage mask (0 = no surface) and a caption.
pub struct GridCell<'a> {
    pub image: &'a Image,
    pub mask: Option<&'a Image>,
    pub caption: String,
}

const PAD: i64 = 16;
const TITLE_PX: f64 = 28.0;
const LABEL_PX: f64 = 21.0;
const CAPTION_PX: f64 = 18.0;
/// Small AO images are enlarged by whole pixels to at least this width so noise stays visible
/// as pixels rather than blur; large ones are shrunk to at most `MAX_CELL`.
const MIN_CELL: u32 = 240;
const MAX_CELL: u32 = 480;
const INK: [u8; 3] = [60, 60, 60];

/// A cell already turned into colours at display size.
struct Tile {
    rgb: Vec<[u8; 3]>,
    caption: String,
}

/// What goes in the extra column right of the table.
enum Side {
    Reference(Tile),
    ColourBar { scale: f32 },
    FlipBar,
}

/// AO images (grey, 1 = white) with the reference image beside the first row.
pub fn image_grid(
    title: &str,
    row_labels: &[String],
    col_labels: &[String],
    cells: &[Vec<GridCell>],
    reference: Option<&GridCell>,
) -> Result<Vec<u8>, String> {
    let (w, h) = check(row_labels, col_labels, cells, reference)?;
    let size = display_size(w, h);
    let tiles = cells.iter().map(|row| row.iter().map(|c| tile(c, size, grey)).collect()).collect();
    let side = reference.map(|r| Side::Reference(tile(r, size, grey)));
    compose(title, row_labels, col_labels, tiles, side, size)
}

/// Signed error of each cell against `reference` (blue = too dark, red = too bright, white = exact)
/// on one symmetric scale for the whole table, so cells compare at a glance. `scale` = None uses the
/// 99th percentile of |error| over all covered pixels, so a few outliers do not wash out the rest.
pub fn error_grid(
    title: &str,
    row_labels: &[String],
    col_labels: &[String],
    cells: &[Vec<GridCell>],
    reference: &GridCell,
    scale: Option<f32>,
) -> Result<Vec<u8>, String> {
    let (w, h) = check(row_labels, col_labels, cells, Some(reference))?;
    let size = display_size(w, h);
    let errors: Vec<Vec<Image>> =
        cells.iter().map(|row| row.iter().map(|c| signed_error(c, reference)).collect()).collect();
    let scale = match scale {
        Some(s) if s.is_finite() && s > 0.0 => s,
        Some(s) => return Err(format!("error scale must be a positive number, got {s}")),
        None => robust_scale(errors.iter().flatten()),
    };
    let tiles = cells
        .iter()
        .zip(&errors)
        .map(|(row, errs)| {
            row.iter()
                .zip(errs)
                .map(|(c, e)| {
                    let cell = GridCell { image: e, mask: None, caption: c.caption.clone() };
                    tile(&cell, size, |v| diverging(v / scale))
                })
                .collect()
        })
        .collect();
    compose(title, row_labels, col_labels, tiles, Some(Side::ColourBar { scale }), size)
}

/// FLIP maps (0 = no perceived difference, black; 1 = the most, pale yellow) in a table, each cell's
/// `image` the map and its `mask` the pixels it covers, with a 0–1 colour bar beside.
pub fn flip_grid(
    title: &str,
    row_labels: &[String],
    col_labels: &[String],
    cells: &[Vec<GridCell>],
) -> Result<Vec<u8>, String> {
    let (w, h) = check(row_labels, col_labels, cells, None)?;
    let size = display_size(w, h);
    let tiles = cells.iter().map(|row| row.iter().map(|c| tile(c, size, magma)).collect()).collect();
    compose(title, row_labels, col_labels, tiles, Some(Side::FlipBar), size)
}

/// Validates shapes; returns the common image size.
fn check(
    row_labels: &[String],
    col_labels: &[String],
    cells: &[Vec<GridCell>],
    reference: Option<&GridCell>,
) -> Result<(u32, u32), String> {
    if cells.is_empty() || cells[0].is_empty() {
        return Err("an image grid needs at least one row and one column".into());
    }
    if cells.len() != row_labels.len() {
        return Err(format!("{} rows of images but {} row labels", cells.len(), row_labels.len()));
    }
    let first = cells[0][0].image;
    let (w, h) = (first.width, first.height);
    if w == 0 || h == 0 || first.data.len() != w as usize * h as usize {
        return Err(format!("image of {w}x{h} pixels cannot be shown"));
    }
    for (r, row) in cells.iter().enumerate() {
        if row.len() != col_labels.len() {
            return Err(format!(
                "row {r} has {} images but there are {} column labels",
                row.len(),
                col_labels.len()
            ));
        }
    }
    let all = cells
        .iter()
        .enumerate()
        .flat_map(|(r, row)| row.iter().enumerate().map(move |(c, x)| (format!("cell ({r}, {c})"), x)));
    for (name, cell) in all.chain(reference.map(|r| ("reference".to_string(), r))) {
        for (what, img) in std::iter::once(("image", cell.image)).chain(cell.mask.map(|m| ("mask", m))) {
            if img.width != w || img.height != h || img.data.len() != w as usize * h as usize {
                return Err(format!("{name} {what} is {}x{} but the grid is {w}x{h}", img.width, img.height));
            }
        }
    }
    Ok((w, h))
}

fn display_size(w: u32, h: u32) -> (u32, u32) {
    let (cw, ch) = if w < MIN_CELL {
        let k = MIN_CELL.div_ceil(w);
        (w * k, h * k)
    } else if w > MAX_CELL {
        (MAX_CELL, ((h as u64 * MAX_CELL as u64) / w as u64).max(1) as u32)
    } else {
        (w, h)
    };
    // Very tall images: keep the table on a screen.
    if ch > 2 * MAX_CELL {
        ((cw as u64 * 2 * MAX_CELL as u64 / ch as u64).max(1) as u32, 2 * MAX_CELL)
    } else {
        (cw, ch)
    }
}

/// Resamples (nearest neighbour) to `size`, colouring covered pixels with `color`.
fn tile(cell: &GridCell, size: (u32, u32), color: impl Fn(f32) -> [u8; 3]) -> Tile {
    let (w, h) = (cell.image.width as u64, cell.image.height as u64);
    let (cw, ch) = (size.0 as u64, size.1 as u64);
    let mut rgb = Vec::with_capacity((cw * ch) as usize);
    for y in 0..ch {
        let sy = (y * h / ch) as u32;
        for x in 0..cw {
            let sx = (x * w / cw) as u32;
            let covered = cell.mask.is_none_or(|m| m.at(sx, sy) >= 0.5);
            rgb.push(if covered { color(cell.image.at(sx, sy)) } else { BACKGROUND });
        }
    }
    Tile { rgb, caption: cell.caption.clone() }
}

/// image − reference where both cover the pixel, NaN (background) elsewhere.
fn signed_error(cell: &GridCell, reference: &GridCell) -> Image {
    let covered = |m: Option<&Image>, i: usize| m.is_none_or(|m| m.data[i] >= 0.5);
    let data = (0..cell.image.data.len())
        .map(|i| {
            if covered(cell.mask, i) && covered(reference.mask, i) {
                cell.image.data[i] - reference.image.data[i]
            } else {
                f32::NAN
            }
        })
        .collect();
    Image::from_vec(cell.image.width, cell.image.height, data)
}

pub(crate) fn robust_scale<'a>(errors: impl Iterator<Item = &'a Image>) -> f32 {
    let mut abs: Vec<f32> =
        errors.flat_map(|e| e.data.iter()).filter(|v| v.is_finite()).map(|v| v.abs()).collect();
    if abs.is_empty() {
        return 1.0;
    }
    let k = ((abs.len() - 1) as f64 * 0.99).round() as usize;
    let (_, v, _) = abs.select_nth_unstable_by(k, f32::total_cmp);
    if *v > 0.0 { *v } else { 1e-6 }
}

fn compose(
    title: &str,
    row_labels: &[String],
    col_labels: &[String],
    tiles: Vec<Vec<Tile>>,
    side: Option<Side>,
    (cw, ch): (u32, u32),
) -> Result<Vec<u8>, String> {
    let widest = |texts: &mut dyn Iterator<Item = &str>, px: f64, bold: bool| {
        texts.map(|t| text_size(t, px, bold).0).max().unwrap_or(0)
    };
    let caption_w = widest(&mut tiles.iter().flatten().map(|t| t.caption.as_str()), CAPTION_PX, false);
    let col_w =
        cw.max(caption_w).max(widest(&mut col_labels.iter().map(|s| s.as_str()), LABEL_PX, true)) as i64;
    let left = widest(&mut row_labels.iter().map(|s| s.as_str()), LABEL_PX, true) as i64 + 2 * PAD;
    let title_h = 52i64;
    let head_h = 36i64;
    let cap_h = 32i64;
    let row_h = ch as i64 + cap_h + PAD / 2;
    let side_w = match &side {
        None => 0,
        Some(Side::Reference(t)) => 2 * PAD + col_w.max(text_size(&t.caption, CAPTION_PX, false).0 as i64),
        Some(Side::ColourBar { .. } | Side::FlipBar) => 2 * PAD + 150,
    };
    let ncols = col_labels.len() as i64;
    let width = left + ncols * (col_w + PAD) + side_w + PAD;
    let width = width.max(text_size(title, TITLE_PX, true).0 as i64 + 2 * PAD);
    let height = title_h + head_h + tiles.len() as i64 * row_h + PAD;
    let mut cv = Canvas::new(width as u32, height as u32, [255, 255, 255])?;
    cv.label(title, width / 2, title_h / 2 + 4, TITLE_PX, Align::Center, true);
    let top = title_h + head_h;
    for (c, label) in col_labels.iter().enumerate() {
        let x = left + c as i64 * (col_w + PAD) + col_w / 2;
        cv.label(label.as_str(), x, title_h + head_h / 2, LABEL_PX, Align::Center, true);
    }
    for (r, (label, row)) in row_labels.iter().zip(&tiles).enumerate() {
        let y = top + r as i64 * row_h;
        cv.label(label.as_str(), left - PAD, y + ch as i64 / 2, LABEL_PX, Align::Right, true);
        for (c, t) in row.iter().enumerate() {
            let x = left + c as i64 * (col_w + PAD);
            draw_tile(&mut cv, t, x + (col_w - cw as i64) / 2, y, (cw, ch), x + col_w / 2);
        }
    }
    let sx = left + ncols * (col_w + PAD) + PAD;
    match side {
        None => {}
        Some(Side::Reference(t)) => {
            cv.label("reference", sx + col_w / 2, title_h + head_h / 2, LABEL_PX, Align::Center, true);
            draw_tile(&mut cv, &t, sx + (col_w - cw as i64) / 2, top, (cw, ch), sx + col_w / 2);
        }
        Some(Side::ColourBar { scale }) => colour_bar(&mut cv, sx, top, ch.max(160) as i64, scale),
        Some(Side::FlipBar) => flip_bar(&mut cv, sx, top, ch.max(160) as i64),
    }
    cv.into_png()
}

fn draw_tile(cv: &mut Canvas, t: &Tile, x: i64, y: i64, (cw, ch): (u32, u32), centre: i64) {
    cv.outline(x, y, cw, ch, INK);
    for (i, c) in t.rgb.iter().enumerate() {
        cv.put(x + (i as u32 % cw) as i64, y + (i as u32 / cw) as i64, *c);
    }
    cv.label(t.caption.as_str(), centre, y + ch as i64 + 17, CAPTION_PX, Align::Center, false);
}

/// Vertical bar from +scale (red, top) through 0 (white) to -scale (blue, bottom), with ticks.
fn colour_bar(cv: &mut Canvas, x: i64, y: i64, h: i64, scale: f32) {
    let bw = 24u32;
    cv.label("image − ref.", x, y - 14, CAPTION_PX, Align::Left, false);
    let (y, h) = (y + 8, h - 16);
    for j in 0..h {
        let t = 1.0 - 2.0 * j as f32 / (h - 1).max(1) as f32;
        cv.fill_rect(x, y + j, bw, 1, diverging(t));
    }
    cv.outline(x, y, bw, h as u32, INK);
    for (t, text) in
        [(1.0, format!("+{}", fmt_scale(scale))), (0.0, "0".into()), (-1.0, format!("−{}", fmt_scale(scale)))]
    {
        let ty = y + ((1.0 - t) / 2.0 * (h - 1) as f32).round() as i64;
        cv.fill_rect(x + bw as i64, ty, 6, 1, INK);
        cv.label(text, x + bw as i64 + 10, ty, CAPTION_PX, Align::Left, false);
    }
}

/// Vertical bar from 1 (top) to 0 (bottom) in magma.
fn flip_bar(cv: &mut Canvas, x: i64, y: i64, h: i64) {
    let bw = 24u32;
    cv.label("FLIP", x, y - 14, CAPTION_PX, Align::Left, false);
    let (y, h) = (y + 8, h - 16);
    for j in 0..h {
        cv.fill_rect(x, y + j, bw, 1, magma(1.0 - j as f32 / (h - 1).max(1) as f32));
    }
    cv.outline(x, y, bw, h as u32, INK);
    for (t, text) in [(1.0, "1"), (0.5, "0.5"), (0.0, "0")] {
        let ty = y + ((1.0 - t) * (h - 1) as f32).round() as i64;
        cv.fill_rect(x + bw as i64, ty, 6, 1, INK);
        cv.label(text, x + bw as i64 + 10, ty, CAPTION_PX, Align::Left, false);
    }
}

/// Three significant digits, no exponent for the usual AO error range.
pub(crate) fn fmt_scale(v: f32) -> String {
    if (0.001..1000.0).contains(&v) {
        let digits = (2 - v.log10().floor() as i32).max(0) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::backend::decode_png;

    fn gradient(w: u32, h: u32) -> Image {
        Image::from_vec(w, h, (0..w * h).map(|i| (i % w) as f32 / (w - 1) as f32).collect())
    }

    fn labels(n: usize, what: &str) -> Vec<String> {
        (0..n).map(|i| format!("{what} {i}")).collect()
    }

    #[test]
    fn image_grid_is_a_png_with_enlarged_cells_and_masked_background() {
        let img = gradient(40, 30);
        let mask = Image::from_vec(40, 30, (0..1200).map(|i| if i < 600 { 1.0 } else { 0.0 }).collect());
        let cell = |m| GridCell { image: &img, mask: m, caption: "RMSE 0.0123  ρx 0.02".into() };
        let cells = vec![vec![cell(None), cell(None), cell(None)], vec![cell(None), cell(None), cell(None)]];
        let png = image_grid("t", &labels(2, "row"), &labels(3, "col"), &cells, Some(&cell(None))).unwrap();
        let (w, h, px) = decode_png(&png);
        assert!(w >= 4 * MIN_CELL && h >= 2 * 180, "{w}x{h}");
        assert!(!px.contains(&BACKGROUND), "no mask, no background colour");
        let masked = vec![vec![cell(Some(&mask))]];
        let (_, _, px) =
            decode_png(&image_grid("t", &labels(1, "r"), &labels(1, "c"), &masked, None).unwrap());
        assert!(px.contains(&BACKGROUND), "masked pixels show the background colour");
    }

    #[test]
    fn small_images_grow_by_whole_pixels_and_large_ones_shrink() {
        assert_eq!(display_size(64, 48), (256, 192));
        assert_eq!(display_size(320, 240), (320, 240));
        assert_eq!(display_size(960, 480), (480, 240));
        assert_eq!(display_size(1, 1), (240, 240));
    }

    #[test]
    fn error_is_signed_masked_and_scaled_symmetrically() {
        let reference = gradient(8, 2);
        let mut img = reference.clone();
        img.data[0] += 0.25;
        img.data[1] -= 0.25;
        let mask = Image::from_vec(8, 2, (0..16).map(|i| if i == 2 { 0.0 } else { 1.0 }).collect());
        let cell = GridCell { image: &img, mask: None, caption: String::new() };
        let refc = GridCell { image: &reference, mask: Some(&mask), caption: String::new() };
        let e = signed_error(&cell, &refc);
        assert!((e.data[0] - 0.25).abs() < 1e-6 && (e.data[1] + 0.25).abs() < 1e-6);
        assert!(e.data[2].is_nan(), "uncovered pixel has no error");
        assert_eq!(e.data[3], 0.0);
        assert_eq!(robust_scale([&e].into_iter()), 0.25);
        let zero = Image::new(4, 4);
        assert!(robust_scale([&zero].into_iter()) > 0.0, "an exact image still gets a usable scale");
        let png = error_grid("e", &labels(1, "r"), &labels(1, "c"), &[vec![cell]], &refc, None).unwrap();
        let (_, _, px) = decode_png(&png);
        assert!(px.contains(&diverging(1.0)) && px.contains(&diverging(-1.0)) && px.contains(&BACKGROUND));
    }

    #[test]
    fn a_flip_grid_draws_maps_in_magma_with_its_bar() {
        let map = gradient(8, 2);
        let mask = Image::from_vec(8, 2, (0..16).map(|i| if i == 2 { 0.0 } else { 1.0 }).collect());
        let cell = GridCell { image: &map, mask: Some(&mask), caption: "FLIP 0.5".into() };
        let (_, _, px) =
            decode_png(&flip_grid("f", &labels(1, "r"), &labels(1, "c"), &[vec![cell]]).unwrap());
        assert!(px.contains(&magma(0.0)) && px.contains(&magma(1.0)) && px.contains(&BACKGROUND));
        assert!(flip_grid("f", &labels(1, "r"), &labels(2, "c"), &[vec![]]).is_err());
    }

    #[test]
    fn bad_grids_are_errors_not_panics() {
        let a = gradient(4, 4);
        let b = gradient(5, 4);
        let c = |im| GridCell { image: im, mask: None, caption: String::new() };
        let r1 = labels(1, "r");
        let c1 = labels(1, "c");
        assert!(image_grid("t", &[], &[], &[], None).is_err());
        assert!(image_grid("t", &r1, &c1, &[vec![]], None).is_err());
        assert!(image_grid("t", &labels(2, "r"), &c1, &[vec![c(&a)]], None).is_err());
        assert!(image_grid("t", &r1, &labels(2, "c"), &[vec![c(&a)]], None).is_err());
        assert!(image_grid("t", &r1, &labels(2, "c"), &[vec![c(&a), c(&b)]], None).is_err());
        assert!(image_grid("t", &r1, &c1, &[vec![c(&a)]], Some(&c(&b))).is_err());
        let bad_mask = GridCell { image: &a, mask: Some(&b), caption: String::new() };
        assert!(image_grid("t", &r1, &c1, &[vec![bad_mask]], None).is_err());
        let empty = Image::new(0, 0);
        assert!(image_grid("t", &r1, &c1, &[vec![c(&empty)]], None).is_err());
        assert!(error_grid("t", &r1, &c1, &[vec![c(&a)]], &c(&b), None).is_err());
        for s in [0.0, -1.0, f32::NAN] {
            assert!(error_grid("t", &r1, &c1, &[vec![c(&a)]], &c(&a), Some(s)).is_err());
        }
    }

    #[test]
    fn scale_labels_have_three_significant_digits() {
        assert_eq!(fmt_scale(0.1364), "0.136");
        assert_eq!(fmt_scale(0.01234), "0.0123");
        assert_eq!(fmt_scale(2.5), "2.50");
    }
}

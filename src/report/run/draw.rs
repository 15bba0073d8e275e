//! What every figure of a run's report does the same way: turning a drawing error into one that
//! names the file, writing a figure into the output directory, a log-log plot as PNG with its SVG
//! beside it, and reading a record's kept image back. `figures` and `realtime_figures` both draw
//! through here and never through each other.

use crate::error::{Error, Result};
use crate::image::Image;
use crate::io;
use crate::outdir;
use crate::report::{self, Figure, Format, GridCell, Guide, Series};
use crate::results::JobResult;
use std::path::Path;

pub fn drawn(path: &Path, r: std::result::Result<Vec<u8>, String>) -> Result<Vec<u8>> {
    r.map_err(|e| Error::Refused(format!("{}: cannot draw the figure: {e}", path.display())))
}

pub fn write_figure(
    out: &Path,
    name: &str,
    caption: String,
    links: Vec<String>,
    bytes: Result<Vec<u8>>,
) -> Result<Figure> {
    outdir::write_file(out, name, &bytes?)?;
    Ok(Figure { path: name.to_string(), caption, links })
}

/// A log-log figure as PNG (on the page) and SVG (linked below it).
#[allow(clippy::too_many_arguments)]
pub fn log_log(
    out: &Path,
    base: &str,
    title: &str,
    (x_label, y_label): (&str, &str),
    series: &[Series],
    guides: &[Guide],
    caption: String,
) -> Result<Figure> {
    let svg = format!("{base}.svg");
    let bytes = drawn(
        &out.join(&svg),
        report::convergence_plot(title, x_label, y_label, series, guides, Format::Svg),
    );
    io::write_atomic(&out.join(&svg), &bytes?)?;
    let png = format!("{base}.png");
    let bytes = drawn(
        &out.join(&png),
        report::convergence_plot(title, x_label, y_label, series, guides, Format::Png),
    );
    write_figure(out, &png, caption, vec![svg], bytes)
}

/// A record's kept image (`Y`, what was measured) and its coverage (`A`), read from `out`.
pub fn record_image(out: &Path, r: &JobResult) -> Result<(Image, Image)> {
    let path = out.join(&r.image);
    let channels = io::read_exr(&path)?;
    let take = |name: &str| {
        channels
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, img)| img.clone())
            .ok_or_else(|| Error::input(&path, format!("image lacks channel '{name}'")))
    };
    Ok((take("Y")?, take("A")?))
}

/// Grid cells borrowing rows of (image, coverage, caption), as `report::image_grid` takes them.
pub fn grid_cells(images: &[Vec<(Image, Image, String)>]) -> Vec<Vec<GridCell<'_>>> {
    images
        .iter()
        .map(|row| {
            row.iter().map(|(i, m, c)| GridCell { image: i, mask: Some(m), caption: c.clone() }).collect()
        })
        .collect()
}

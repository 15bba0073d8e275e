//! What every figure of a run's report does the same way: turning a drawing error into one that
//! names the file, adding a figure's bytes to the report's files, and a log-log plot as PNG with
//! its SVG beside it. `figures` and `realtime_figures` both draw through here and never through
//! each other. Nothing here touches the filesystem: the files are written by `outdir`.

use crate::error::{Error, Result};
use crate::image::Image;
use crate::outdir::File;
use crate::report::{self, Figure, Format, GridCell, Guide, Series};

/// A drawing's bytes, or an error naming the file it was for.
pub fn drawn(name: &str, r: std::result::Result<Vec<u8>, String>) -> Result<Vec<u8>> {
    r.map_err(|e| Error::Refused(format!("{name}: cannot draw the figure: {e}")))
}

/// Adds `bytes` as the file `name` to `files`, and returns the page's entry for it.
pub fn add_figure(
    files: &mut Vec<File>,
    name: &str,
    caption: String,
    links: Vec<String>,
    bytes: Result<Vec<u8>>,
) -> Result<Figure> {
    files.push(File::new(name, bytes?));
    Ok(Figure { path: name.to_string(), caption, links })
}

/// What a log-log figure shows: its title, axis labels (x, y), series and guides.
pub struct LogLog<'a> {
    pub title: &'a str,
    pub axes: (&'a str, &'a str),
    pub series: &'a [Series],
    pub guides: &'a [Guide],
}

/// A log-log figure as `base.png` (on the page) and `base.svg` (linked below it).
pub fn log_log(files: &mut Vec<File>, base: &str, plot: LogLog, caption: String) -> Result<Figure> {
    let draw = |format| {
        let (x, y) = plot.axes;
        report::convergence_plot(plot.title, x, y, plot.series, plot.guides, format)
    };
    let svg = format!("{base}.svg");
    files.push(File::new(&svg, drawn(&svg, draw(Format::Svg))?));
    let png = format!("{base}.png");
    let bytes = drawn(&png, draw(Format::Png));
    add_figure(files, &png, caption, vec![svg], bytes)
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

//! Turns results into what a reader of the paper looks at: point panels (Table 1, Figures 2-4),
//! AO image tables and their signed-error maps (Tables 2-3), convergence and banding plots, and one
//! offline HTML / Markdown page.
//!
//! Every function takes plain data (the records and `compare`'s comparisons; the drawing kit's own
//! types here) and returns bytes or a `String`: the report does no statistics of its own, never
//! touches the filesystem and never renders AO. `run/` and `advise/` return their files
//! (`outdir::File`), which the command writes through `outdir::write_files`; an image a figure
//! shows is read for it by the command (`outdir::record_image`).
//!
//! Text is drawn with plotters' `ab_glyph` rasterizer and the DejaVu Sans font shipped inside the
//! `dejavu` crate, so no system font library is needed at run time.

pub mod advise;
pub(crate) mod axis;
pub(crate) mod backend;
mod banding;
pub(crate) mod canvas;
pub mod colormap;
mod grid;
mod html;
pub(crate) mod plot;
mod points;
pub mod run;
pub mod tiles;
pub mod viewer;

pub use backend::Format;
pub use banding::banding_plot;
pub use grid::{GridCell, error_grid, flip_grid, image_grid};
pub use html::{
    Figure, METHOD_SUMMARY, Opening, Page, Table, html_page, html_page_opened, markdown_page,
    markdown_page_opened, markdown_table, referenced_files,
};
pub use plot::{Guide, Series, convergence_plot};
pub use points::{
    GRID_FRAMES, PointSet, directions, directions_of, figure_rows, pixel_frame_rows, point_panels,
};

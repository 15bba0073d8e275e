//! `hemilab advise`'s outputs: its page, `advice.json`, and its figures (error against time, winner
//! maps).

pub mod figures;
pub mod json;
pub mod maps;
pub mod page;
pub mod text;

use crate::advice::analysis::{self, Analysis, Measured};
use crate::error::Result;
use crate::outdir;
use std::path::Path;

/// The winner maps, then figures, advice.json, the pages and the records; returns the text to print.
pub fn write(m: &Measured, mut a: Analysis, out: &Path) -> Result<String> {
    a.maps = analysis::winner_maps(m, &a.curves, &a.rankings);
    a.colours = maps::colours(&a.maps);
    let figures = maps::figures(m, &a, out)?;
    outdir::write_results(out, &m.results)?;
    page::write(m, &a, &figures, out)
}

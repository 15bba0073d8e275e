//! `hemilab advise`'s outputs: its page, `advice.json`, and its figures (error against time, winner
//! maps).

pub mod figures;
pub mod json;
pub mod maps;
pub mod page;
pub mod text;

use crate::advice::analysis::{self, Analysis, Measured};
use crate::error::Result;
use std::path::Path;

/// The winner maps, then figures, advice.json and the pages, into `dir`; returns the text to
/// print, which names `shown` (where the output set will be) as the page's place.
pub fn write(m: &Measured, mut a: Analysis, dir: &Path, shown: &Path) -> Result<String> {
    a.maps = analysis::winner_maps(m, &a);
    a.colours = maps::colours(&a.maps);
    let figures = maps::figures(m, &a, dir)?;
    page::write(m, &a, &figures, dir, shown)
}

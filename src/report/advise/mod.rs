//! `hemilab advise`'s outputs as bytes: its page, `advice.json`, and its figures (error against
//! time, winner maps). The analysis (`advice::analysis`) has computed every number; this module
//! formats them and returns the files, which `outdir::write_files` writes.

pub mod figures;
pub mod frames;
pub mod json;
pub mod maps;
pub mod page;
pub mod text;

use crate::advice::analysis::{Analysis, Measured};
use crate::error::Result;
use crate::outdir::File;
use std::path::Path;

/// advise's files in the order to write them (the page last), the files an earlier advise may have
/// left that this one does not make (they would mislead), the lines to print and the warnings.
pub struct Report {
    pub files: Vec<File>,
    pub stale: Vec<&'static str>,
    pub text: String,
    pub warnings: Vec<String>,
}

/// The figures, advice.json and the pages of `a` (its winner maps already made); the text names
/// `shown` (where the output set will be) as the page's place.
pub fn report(m: &Measured, a: &Analysis, shown: &Path) -> Result<Report> {
    let colours = maps::colours(&a.maps);
    let mut files = Vec::new();
    let mut figures = maps::figures(m, a, &colours, &mut files)?;
    if let Some(t) = &m.tiles {
        figures.insert(
            0,
            crate::report::Figure {
                path: t.name.clone(),
                caption:
                    "Measured on tiles: the frame (a 32-ray preview) with each tile outlined and its widest \
                          apron around it (the filter's reach and the moving camera's motion near \
                          that tile; the still camera's apron is the reach alone)"
                        .into(),
                links: Vec::new(),
            },
        );
        files.push(crate::outdir::File::new(&t.name, t.bytes.clone()));
    }
    let stale = if a.maps.is_empty() { vec![maps::WINNER_MAP] } else { Vec::new() };
    let images = frames::images(m, a, &mut files)?;
    let (text, warnings) = page::page(m, a, (&figures, &images), &mut files, shown);
    Ok(Report { files, stale, text, warnings })
}

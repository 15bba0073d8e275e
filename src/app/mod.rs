//! One thin file per command: parse the arguments, call the stages, print. No command imports
//! another command's file; what two commands share lives in the stage that owns it.

mod advise;
mod bench;
mod merge;
mod plan;
mod points;
mod reference;
mod render;
mod run;

use crate::cli::{Cli, Command};
use crate::error::{Error, Result};
use crate::spec::Row;

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run(args) => run::run(args),
        Command::Plan(args) => plan::run(args),
        Command::Reference(args) => reference::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Render(args) => render::run(args),
        Command::Bench(args) => bench::run(args),
        Command::Points(args) => points::run(&args),
        Command::Advise(args) => advise::run(args),
    }
}

/// Refuses a command line's row that cannot be drawn or rendered (a vector texture without the
/// sine-cosine warp; more points than a file's set holds), naming the flag.
pub fn check_row(row: &Row, count: u32, flag: &str) -> Result<()> {
    if let Some(e) = row.invalid() {
        return Err(Error::Usage(format!("--seed-mode {}: {e}", row.seed_mode)));
    }
    if let Some(max) = row.sequence.imp().max_count()
        && count > max
    {
        return Err(Error::Usage(format!(
            "{flag} {count}: sequence '{}' holds {max} points per pixel; allowed 1..={max}",
            row.sequence
        )));
    }
    Ok(())
}

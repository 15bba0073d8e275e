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
use hemilab::error::Result;

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

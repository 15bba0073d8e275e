//! The one orchestrator: load → validate everything → plan → render → measure → export.
//! Only this module (through `io`) touches the filesystem.

mod figures;
mod jobs;
pub mod points;
mod reference;
pub mod run;

use crate::cli::{Cli, Command};
use crate::error::{Error, Result};

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run(args) => run::run_run(args),
        Command::Plan(args) => run::run_plan(args),
        Command::Reference(args) => run::run_reference(args),
        Command::Render(_) | Command::Bench(_) => {
            Err(Error::Usage("`render` and `bench` arrive with the renderer (issue 3)".into()))
        }
        Command::Points(args) => points::run(&args),
    }
}

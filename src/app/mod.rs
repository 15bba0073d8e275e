//! The one orchestrator: load → validate everything → plan → render → measure → export.
//! Only this module (through `io`) touches the filesystem.

pub mod points;

use crate::cli::{Cli, Command};
use crate::error::{Error, Result};

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run(_) | Command::Plan(_) | Command::Reference(_) => Err(Error::Usage(
            "`run`, `plan` and `reference` arrive with the experiment runner (issue 4)".into(),
        )),
        Command::Render(_) | Command::Bench(_) => {
            Err(Error::Usage("`render` and `bench` arrive with the renderer (issue 3)".into()))
        }
        Command::Points(args) => points::run(&args),
    }
}

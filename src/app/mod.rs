//! The one orchestrator: load → validate everything → plan → render → measure → export.
//! Only this module (through `io`) touches the filesystem.

use crate::cli::{Cli, Command};
use crate::error::{Error, Result};

pub mod render;

pub use render::load_scene;

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run(_) | Command::Plan(_) | Command::Reference(_) => Err(Error::Usage(
            "`run`, `plan` and `reference` arrive with the experiment runner (issue 4)".into(),
        )),
        Command::Render(args) => render::run_render(args),
        Command::Bench(args) => render::run_bench(args),
        Command::Points(_) => Err(Error::Usage("`points` arrives with the report (issue 5)".into())),
    }
}

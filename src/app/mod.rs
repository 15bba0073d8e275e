//! The one orchestrator: load → validate everything → plan → render → measure → export.
//! Only this module (through `io`) touches the filesystem.

mod adaptive;
mod advise;
mod advise_json;
mod advise_page;
mod advise_report;
mod answer;
mod bench;
mod data;
mod estimate;
mod figures;
mod jobs;
mod load;
mod long_run;
mod merge;
mod page;
pub mod points;
mod reference;
pub mod render;
pub mod run;
mod shard;
mod timed;
mod verdicts;

pub use render::load_scene;

use crate::cli::{Cli, Command};
use crate::error::Result;

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run(args) => run::run_run(args),
        Command::Plan(args) => estimate::run_plan(args),
        Command::Reference(args) => run::run_reference(args),
        Command::Merge(args) => merge::run_merge(args),
        Command::Render(args) => render::run_render(args),
        Command::Bench(args) => bench::run_bench(args),
        Command::Points(args) => points::run(&args),
        Command::Advise(args) => advise::run_advise(args),
    }
}

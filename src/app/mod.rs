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

use crate::cli::{Cli, Command, FrameArgs, ModeArg, SequenceArg};
use crate::error::{Error, Result};
use crate::sampling::{Distribution, SamplerConfig};
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

/// The sampler of a command line's `--distribution/--sequence/--seed-mode/--seed/--frame/--schedule`
/// with `count` points a pixel (`flag` names the count): the names resolved (a point file or
/// texture read), the row refused as `check_row` refuses it. `render` and `points` build theirs
/// here, and so does the Python module (`python/`), so that its settings mean what the flags mean.
pub fn sampler(
    distribution: Distribution,
    sequence: &SequenceArg,
    seed_mode: &ModeArg,
    seed: u64,
    frames: &FrameArgs,
    count: u32,
    flag: &str,
) -> Result<(Row, SamplerConfig)> {
    let (sequence, seed_mode) = (sequence.resolve()?, seed_mode.resolve()?);
    let row = Row::new(distribution, sequence, seed_mode);
    check_row(&row, count, flag)?;
    let config = SamplerConfig::new(row.sequence, row.seed_mode, count, seed)
        .map_err(|e| Error::Usage(format!("{flag}: {e}")))?
        .with_frame(frames.frame)
        .with_schedule(frames.schedule);
    Ok((row, config))
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

//! `hemilab points`: one point-set panel (a cell of the paper's Table 1 / Figures 2-4) on its own.
//! Also the one place that turns sampling settings into directions for the report's point figures.

use crate::cli::PointsArgs;
use crate::error::{Error, Result};
use crate::io;
use crate::report::directions_of;
use crate::report::{self, Format, PointSet};

pub fn run(args: &PointsArgs) -> Result<()> {
    let path = &args.output;
    let format =
        path.extension().and_then(|e| e.to_str()).and_then(Format::from_extension).ok_or_else(|| {
            Error::Usage(format!("{}: the output must end in .png or .svg", path.display()))
        })?;
    let (row, config) = crate::app::sampler(
        args.distribution,
        &args.sequence,
        &args.seed_mode,
        args.seed,
        &args.frames,
        args.count,
        "--count",
    )?;
    config.prepare();
    let dirs = directions_of(args.distribution, config);
    let frame = match (args.frames.frame, args.frames.schedule) {
        (0, crate::sampling::Schedule::Independent) => String::new(),
        (f, s) => format!(", frame {f} ({s})"),
    };
    let title = format!("{} (run seed {}{frame})", row.name(), args.seed);
    let set = PointSet { title: format!("{} points", args.count), dirs };
    // As `render`'s --output: made where the path says (no `a/..` left behind), checked first.
    let target = io::absolute(path);
    io::ensure_writable_dir(target.parent().unwrap_or(&target))?;
    let bytes = report::point_panels(&title, &[(String::new(), vec![set])], true, format)
        .map_err(|e| Error::Refused(format!("{}: cannot draw the points: {e}", path.display())))?;
    io::write_atomic(&target, &bytes)?;
    // As `render` does: what was drawn, and where.
    println!(
        "{} points, {}, run seed {}{frame} (pixel 0) -> {}",
        args.count,
        row.name(),
        args.seed,
        path.display()
    );
    Ok(())
}

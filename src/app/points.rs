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
    // A static seed is the same set in every pixel and frame: one panel with its side view. A
    // per-pixel seed mode is a grid of pixels × frames, the spread one pixel's panel cannot show.
    let per_pixel = row.seed_mode != crate::sampling::SeedMode::Static;
    let (rows, which) = if per_pixel {
        let rows = report::pixel_frame_rows(args.distribution, config);
        let (f0, n) = (args.frames.frame, report::GRID_FRAMES);
        (rows, format!("pixels (0..1, 0..1) x frames {f0}..{}", f0 + n - 1))
    } else {
        let set = PointSet { title: format!("{} points", args.count), dirs };
        (vec![(String::new(), vec![set])], "pixel 0".to_string())
    };
    let title = if per_pixel { format!("{title}, {} points per pixel", args.count) } else { title };
    // As `render`'s --output: made where the path says (no `a/..` left behind), checked first.
    let target = io::absolute(path);
    io::ensure_writable_dir(target.parent().unwrap_or(&target))?;
    let bytes = report::point_panels(&title, &rows, !per_pixel, format)
        .map_err(|e| Error::Refused(format!("{}: cannot draw the points: {e}", path.display())))?;
    io::write_atomic(&target, &bytes)?;
    // As `render` does: what was drawn, and where.
    println!(
        "{} points, {}, run seed {}{frame} ({which}) -> {}",
        args.count,
        row.name(),
        args.seed,
        path.display()
    );
    Ok(())
}

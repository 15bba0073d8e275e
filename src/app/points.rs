//! `hemilab points`: one point-set panel (a cell of the paper's Table 1 / Figures 2-4) on its own.
//! Also the one place that turns sampling settings into directions for the report's point figures.

use crate::cli::PointsArgs;
use crate::error::{Error, Result};
use crate::io;
use crate::report::{self, Format, PointSet};
use crate::sampling::{Distribution, SamplerConfig, SeedMode, Sequence};
use crate::spec::Row;
use glam::{Vec2, Vec3};

pub fn run(args: &PointsArgs) -> Result<()> {
    let path = &args.output;
    let format =
        path.extension().and_then(|e| e.to_str()).and_then(Format::from_extension).ok_or_else(|| {
            Error::Usage(format!("{}: the output must end in .png or .svg", path.display()))
        })?;
    let dirs = directions(args.distribution, args.sequence, args.seed_mode, args.count, args.seed)?;
    let row = Row::new(args.distribution, args.sequence, args.seed_mode);
    let title = format!("{} (run seed {})", row.name(), args.seed);
    let set = PointSet { title: format!("{} points", args.count), dirs };
    let bytes = report::point_panels(&title, &[(String::new(), vec![set])], true, format)
        .map_err(|e| Error::Refused(format!("{}: cannot draw the points: {e}", path.display())))?;
    io::write_atomic(path, &bytes)?;
    // As `render` does: what was drawn, and where.
    println!("{} points, {}, run seed {} (pixel 0) -> {}", args.count, row.name(), args.seed, path.display());
    Ok(())
}

/// The `count` directions (local frame, z = normal) of pixel 0 of an image sampled with these
/// settings: exactly the set the renderer would use there.
pub fn directions(
    distribution: Distribution,
    sequence: Sequence,
    seed_mode: SeedMode,
    count: u32,
    seed: u64,
) -> Result<Vec<Vec3>> {
    let config =
        SamplerConfig::new(sequence, seed_mode, count, seed).map_err(|e| Error::Usage(e.to_string()))?;
    let mut pts = vec![Vec2::ZERO; count as usize];
    config.fill_pixel(0, 0, 0, &mut pts);
    Ok(pts.into_iter().map(|u| distribution.sample(u).dir).collect())
}

/// Rows of a point figure: one row per distribution, one panel per point count ("500 points"), all
/// from pixel 0 of `sequence` with `seed`. Table 1 is the Fibonacci lattice through the three
/// distributions; Figures 2-4 are one pseudo-random row each.
pub fn figure_rows(
    distributions: &[Distribution],
    sequence: Sequence,
    seed_mode: SeedMode,
    counts: &[u32],
    seed: u64,
) -> Result<Vec<(String, Vec<PointSet>)>> {
    distributions
        .iter()
        .map(|&d| {
            let sets = counts
                .iter()
                .map(|&n| {
                    Ok(PointSet {
                        title: format!("{n} points"),
                        dirs: directions(d, sequence, seed_mode, n, seed)?,
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            Ok((d.name().to_string(), sets))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figure_rows_have_one_panel_per_count_on_the_hemisphere() {
        let ds = [Distribution::Uniform, Distribution::Sine, Distribution::SineCosine];
        let rows = figure_rows(&ds, Sequence::Fibonacci, SeedMode::Static, &[5, 50], 1).unwrap();
        assert_eq!(rows.iter().map(|r| r.0.as_str()).collect::<Vec<_>>(), ["uniform", "sine", "sine-cosine"]);
        for (_, sets) in &rows {
            assert_eq!(sets.iter().map(|s| s.dirs.len()).collect::<Vec<_>>(), [5, 50]);
            assert!(sets.iter().flat_map(|s| &s.dirs).all(|d| d.z >= 0.0 && (d.length() - 1.0).abs() < 1e-4));
        }
        assert!(figure_rows(&ds, Sequence::Random, SeedMode::Static, &[0], 1).is_err());
    }
}

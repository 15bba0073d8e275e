//! `[tiles]` of a spec (`plan::tiles`): checked with the rest of the spec, each problem naming its
//! line and key.

use super::raw::{RawTiles, S};
use super::validate::Problems;

/// `[tiles]`: count 1..=`MAX_COUNT` (default 4), size `MIN_SIZE..=MAX_SIZE` px (default 128), and
/// with a `resolution`, a size that fits it and tiles that do not already cover the whole image.
pub(super) fn tiles(
    table: &S<RawTiles>,
    resolution: Option<[u32; 2]>,
    p: &mut Problems,
) -> Option<crate::plan::tiles::TileSpec> {
    use crate::plan::tiles::{DEFAULT, MAX_COUNT, MAX_SIZE, MIN_SIZE, TileSpec};
    let raw = table.get_ref();
    let count =
        raw.count.as_ref().map_or(Some(DEFAULT.count), |c| p.int(c, "tiles.count", 1, MAX_COUNT as i64));
    let size = raw
        .size
        .as_ref()
        .map_or(Some(DEFAULT.size), |s| p.int(s, "tiles.size", MIN_SIZE as i64, MAX_SIZE as i64));
    let t = TileSpec { count: count?, size: size? };
    if let (Some([w, h]), Some(s)) = (resolution, raw.size.as_ref())
        && t.size > w.min(h)
    {
        p.add(
            s.span(),
            "tiles.size",
            format!("{} px does not fit the {w}x{h} image; allowed {MIN_SIZE}..={}", t.size, w.min(h)),
        );
        return None;
    }
    if let Some([w, h]) = resolution
        && t.count as u64 * (t.size as u64).pow(2) >= w as u64 * h as u64
    {
        let at = raw.count.as_ref().or(raw.size.as_ref()).map_or_else(|| table.span(), |c| c.span());
        let why = format!(
            "{} tiles of {} px cover the whole {w}x{h} image; measure it whole (drop [tiles]) or ask for fewer              or smaller tiles",
            t.count, t.size
        );
        p.add(at, "tiles", why);
        return None;
    }
    Some(t)
}

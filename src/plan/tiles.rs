//! Where to measure a big image when the whole frame costs too much: a few square tiles chosen
//! where the scene's content is, each rendered with an apron around it (`jobs::tiles`).
//!
//! **The choice** reads a cheap, low-resolution probe of the frame's G-buffer (`Probe`, one primary
//! ray per probe pixel, `PROBE_SIDE` pixels across) and scores every candidate tile on a grid of a
//! quarter tile's step by what an error measurement needs there (`score`):
//!
//! * **coverage**: background pixels cast no AO rays and are left out of every metric, so a tile
//!   of sky measures nothing; the score is proportional to the covered share;
//! * **depth and normal edges**: where an edge-stopping filter's weights act, where reprojection
//!   disoccludes and where contact shadows are, i.e. where pipelines differ most;
//! * **thin geometry**: a covered probe pixel whose two neighbours on one axis are both farther
//!   (or background): chair legs, slats, foliage, where samplers alias and masks show.
//!
//! Tiles are taken greedily, best score first (ties to the top-left), each at least half a tile
//! from every one already taken (then, if too few fit so, merely not overlapping), so N tiles show
//! N different places of the frame rather than one cabinet in four adjacent squares. Deterministic: the probe is a
//! render of fixed rays, and nothing else is read.
//!
//! **The default** `DEFAULT` is 4 tiles of 128 × 128: at 1920 × 1080 that is 65,536 interior pixels
//! (3.2 % of the frame), and with SVGF's apron (62 px either side) 4 × 252² = 254,016 rendered
//! pixels, 12 % of the frame: the cost of a 640 × 400 image for masks, kernels and G-buffer at the
//! engine's scale. 128 px is two 64² blue-noise/STBN masks across, so a tile holds whole masks, and
//! twice SVGF's 1080p footprint radius. Four tiles is the fewest that still lets a scene show
//! different content (a floor, a wall corner, a thin object, a silhouette).

use crate::render::Window;

/// How many tiles of what side: the spec's `[tiles]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TileSpec {
    pub count: u32,
    pub size: u32,
}

/// 4 tiles of 128 × 128 (module doc).
pub const DEFAULT: TileSpec = TileSpec { count: 4, size: 128 };
/// Limits a spec may ask for: 1..=64 tiles, sides 8..=2048 px.
pub const MAX_COUNT: u32 = 64;
pub const MIN_SIZE: u32 = 8;
pub const MAX_SIZE: u32 = 2048;

impl TileSpec {
    /// `4x128`: part of job keys and provenance.
    pub fn canonical(&self) -> String {
        format!("{}x{}", self.count, self.size)
    }

    /// The interior side at a `full` image: the spec's size, at most the image's smaller side.
    pub fn side(&self, full: [u32; 2]) -> u32 {
        self.size.min(full[0]).min(full[1]).max(1)
    }
}

/// The probe's longer side: 256 px (at 1920 × 1080, one probe pixel per 7.5 × 7.5 image pixels,
/// fine enough to see a chair leg, 34,560 primary rays, a few milliseconds).
pub const PROBE_SIDE: u32 = 256;

/// The probe's size for a `full` image: the image itself when it is small, else scaled so that its
/// longer side is `PROBE_SIDE` (aspect kept, sides at least 1).
pub fn probe_size(full: [u32; 2]) -> [u32; 2] {
    let long = full[0].max(full[1]);
    if long <= PROBE_SIDE {
        return full;
    }
    let s = PROBE_SIDE as f64 / long as f64;
    [((full[0] as f64 * s).round() as u32).max(1), ((full[1] as f64 * s).round() as u32).max(1)]
}

/// A low-resolution G-buffer of the frame: per probe pixel (row-major), whether the primary ray hit,
/// its depth and its unit normal.
#[derive(Debug, Clone, PartialEq)]
pub struct Probe {
    pub width: u32,
    pub height: u32,
    pub covered: Vec<bool>,
    pub depth: Vec<f32>,
    pub normal: Vec<[f32; 3]>,
}

/// Relative depth difference between neighbouring probe pixels read as an edge: 5 % (a surface
/// seen at a grazing angle differs by less between probe pixels only when it is nearly
/// fronto-parallel; a step between objects is typically tens of percent).
pub const DEPTH_EDGE: f32 = 0.05;
/// Normal dot product below which neighbours are on two sides of a crease: 0.9 (about 26°, the
/// reprojection test's `normal_cos`).
pub const NORMAL_EDGE: f32 = 0.9;

/// Per probe pixel: (covered, on an edge, thin).
fn features(p: &Probe) -> Vec<(bool, bool, bool)> {
    let (w, h) = (p.width as i64, p.height as i64);
    let at = |x: i64, y: i64| -> Option<usize> {
        (x >= 0 && y >= 0 && x < w && y < h).then(|| (y * w + x) as usize)
    };
    let edge = |i: usize, j: usize| -> bool {
        if p.covered[i] != p.covered[j] {
            return true;
        }
        if !p.covered[i] {
            return false;
        }
        let (a, b) = (p.depth[i], p.depth[j]);
        let n = |k: usize| glam::Vec3::from_array(p.normal[k]);
        (a - b).abs() > DEPTH_EDGE * a.min(b) || n(i).dot(n(j)) < NORMAL_EDGE
    };
    // Farther than the pixel by more than the edge tolerance, or background.
    let behind = |i: usize, j: Option<usize>| match j {
        Some(j) => !p.covered[j] || p.depth[j] > p.depth[i] * (1.0 + DEPTH_EDGE),
        None => false,
    };
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let i = at(x, y).expect("inside");
            let covered = p.covered[i];
            let on_edge = [at(x + 1, y), at(x, y + 1), at(x - 1, y), at(x, y - 1)]
                .into_iter()
                .flatten()
                .any(|j| edge(i, j));
            let thin = covered
                && ((behind(i, at(x - 1, y)) && behind(i, at(x + 1, y)))
                    || (behind(i, at(x, y - 1)) && behind(i, at(x, y + 1))));
            (covered, on_edge, thin)
        })
        .collect()
}

/// A candidate's score from its probe pixels' shares: coverage × (1 + edges + 2 · thin). Coverage
/// gates (a tile of background measures nothing); edges and thin geometry, where pipelines and
/// samplers differ most, raise it up to fourfold; thin geometry counts twice because it is rarer
/// and, one probe pixel wide, stands for more of the image than its pixel count.
pub fn score(covered: f64, edges: f64, thin: f64) -> f64 {
    covered * (1.0 + edges + 2.0 * thin)
}

/// The interiors of the `spec.count` tiles of a `full` image chosen from `probe` (module doc), in
/// the order they were chosen (best first). Fewer when the image holds fewer non-overlapping
/// tiles; none on a probe with nothing covered.
pub fn choose(probe: &Probe, full: [u32; 2], spec: TileSpec) -> Vec<Window> {
    let side = spec.side(full);
    let f = features(probe);
    // Summed-area tables of the three features over the probe.
    let (pw, ph) = (probe.width as usize, probe.height as usize);
    let mut sums = vec![[0u32; 3]; (pw + 1) * (ph + 1)];
    for y in 0..ph {
        for x in 0..pw {
            let (c, e, t) = f[y * pw + x];
            let above = sums[y * (pw + 1) + x + 1];
            let left = sums[(y + 1) * (pw + 1) + x];
            let diag = sums[y * (pw + 1) + x];
            let v = [c as u32, (c && e) as u32, t as u32];
            sums[(y + 1) * (pw + 1) + x + 1] = [0, 1, 2].map(|k| above[k] + left[k] - diag[k] + v[k]);
        }
    }
    let area = |x0: usize, y0: usize, x1: usize, y1: usize| -> [u32; 3] {
        let s = |x: usize, y: usize| sums[y * (pw + 1) + x];
        [0, 1, 2].map(|k| s(x1, y1)[k] + s(x0, y0)[k] - s(x0, y1)[k] - s(x1, y0)[k])
    };
    // Image pixel → probe pixel (floor), and the probe rectangle a tile covers (at least one pixel).
    let to_probe = |v: u32, full_side: u32, probe_side: usize| -> usize {
        ((v as u64 * probe_side as u64) / full_side.max(1) as u64) as usize
    };
    let step = (side / 4).max(1);
    let positions = |full_side: u32| -> Vec<u32> {
        let last = full_side - side;
        let mut v: Vec<u32> = (0..=last).step_by(step as usize).collect();
        if v.last() != Some(&last) {
            v.push(last);
        }
        v
    };
    let mut candidates: Vec<(f64, Window)> = Vec::new();
    for &y in &positions(full[1]) {
        for &x in &positions(full[0]) {
            let (x0, y0) = (to_probe(x, full[0], pw), to_probe(y, full[1], ph));
            let x1 = to_probe(x + side, full[0], pw).max(x0 + 1).min(pw);
            let y1 = to_probe(y + side, full[1], ph).max(y0 + 1).min(ph);
            let [c, e, t] = area(x0, y0, x1, y1);
            let n = ((x1 - x0) * (y1 - y0)) as f64;
            let s = score(c as f64 / n, e as f64 / n, t as f64 / n);
            if c > 0 {
                candidates.push((s, Window::new(full, x, y, side, side)));
            }
        }
    }
    // Best first; equal scores in scan order (stable sort over scan-ordered candidates).
    candidates.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut chosen: Vec<Window> = Vec::new();
    for spacing in [side / 2, 0] {
        for (_, w) in &candidates {
            if chosen.len() as u32 >= spec.count {
                break;
            }
            if chosen.iter().all(|c| !c.grown(spacing).overlaps(w)) {
                chosen.push(*w);
            }
        }
    }
    chosen
}

/// The most pixels a whole frame is measured at before `auto` measures on tiles: 320 × 180, the
/// size a full-frame real-time spec of a production interior was run at in 26.5 minutes on this
/// project's 2-core machine (issue 46); above it the cost grows with the pixels, the tiles' does not.
pub const FULL_FRAME_MAX_PIXELS: u64 = 320 * 180;

/// What `advise` measures a `resolution` image on: the whole frame up to `FULL_FRAME_MAX_PIXELS`,
/// above it `DEFAULT` tiles (at most as many as fit side by side, and sides at most the image's
/// smaller side), unless those would cover the whole image anyway.
pub fn auto(resolution: [u32; 2]) -> Option<TileSpec> {
    let [w, h] = resolution;
    let pixels = w as u64 * h as u64;
    if pixels <= FULL_FRAME_MAX_PIXELS {
        return None;
    }
    let t = TileSpec { count: DEFAULT.count, size: DEFAULT.size.min(w).min(h) };
    (t.count as u64 * (t.size as u64).pow(2) < pixels).then_some(t)
}

/// The apron around every tile: how far the pipeline reads from a pixel (`filter_reach`, half its
/// spatial footprint) plus how far the camera moves the image over the frames a history keeps
/// (`jobs::tiles`, per tile and camera), so that an interior pixel's filter taps and its reprojected
/// history are pixels that were rendered.
pub fn apron(filter_reach: u32, motion_px: f64) -> u32 {
    filter_reach.saturating_add(motion_px.max(0.0).ceil().min(u32::MAX as f64 / 2.0) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn advise_tiles_only_images_above_the_full_frame_limit() {
        assert_eq!(auto([320, 180]), None);
        assert_eq!(auto([64, 48]), None);
        assert_eq!(auto([1920, 1080]), Some(DEFAULT));
        assert_eq!(auto([2000, 100]), Some(TileSpec { count: 4, size: 100 }));
    }

    #[test]
    fn probes_of_big_images_are_small_and_keep_the_aspect() {
        assert_eq!(probe_size([1920, 1080]), [256, 144]);
        assert_eq!(probe_size([160, 120]), [160, 120]);
        assert_eq!(probe_size([100, 4000]), [6, 256]);
    }

    #[test]
    fn a_background_probe_has_no_tiles_and_a_thin_post_draws_one() {
        let (w, h) = (64u32, 32u32);
        let n = (w * h) as usize;
        let mut p = Probe {
            width: w,
            height: h,
            covered: vec![false; n],
            depth: vec![0.0; n],
            normal: vec![[0.0, 0.0, 1.0]; n],
        };
        assert!(choose(&p, [128, 64], TileSpec { count: 2, size: 32 }).is_empty());
        // A wall at depth 2 everywhere, and a post one probe pixel wide at x = 50, in front.
        p.covered.fill(true);
        p.depth.fill(2.0);
        for y in 0..h {
            p.depth[(y * w + 50) as usize] = 1.0;
        }
        let tiles = choose(&p, [128, 64], TileSpec { count: 2, size: 32 });
        assert_eq!(tiles.len(), 2);
        let post = 100; // x = 50 in the probe is x = 100 in the image
        assert!(tiles[0].x <= post && post < tiles[0].x + 32, "{tiles:?}");
        assert!(!tiles[0].overlaps(&tiles[1]));
    }
}

//! How much the BVH build spends on the tree's quality (`Effort`), by the work the tree will do:
//! the rule, apart from the build itself (`accel`), since commands decide it before they load.

/// How much the BVH build spends on the tree's quality, chosen by the work the tree will do
/// (the rule and its measured trade-offs are in docs/performance.md). The image does not
/// depend on it: AO asks whether anything is hit (any hit) and the primary rays take the least
/// (t, input index) of the hits (`closer`), whatever order a tree meets them in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Effort {
    /// obvhs's slow preset (spatial pre-splits, reinsertion): the paper runs' tree, for work that
    /// traces many rays per triangle.
    #[default]
    Full,
    /// obvhs's fastest preset (no splits, no reinsertion) over pairs of triangles (`cluster`): a
    /// fraction of the build's time and memory, for a render that traces few rays per triangle.
    Fast,
}

/// Below this many rays per triangle the full build costs more than it saves. Measured
/// (docs/performance.md, `examples/build_effort.rs`): the full build's extra time per triangle
/// equals the time its faster tree saves on about 240 rays on the kitchen and about 50 on a 1 M
/// triangle grid; the threshold sits at the low end, so a render in doubt gets a paper run's tree.
pub const FAST_BELOW_RAYS_PER_TRIANGLE: f64 = 64.0;

impl Effort {
    /// The effort for a command that will trace `rays` rays (None: unknown, as many as a paper run
    /// may) through `triangles` triangles.
    pub fn for_work(rays: Option<u64>, triangles: usize) -> Effort {
        match rays {
            Some(r) if (r as f64) < FAST_BELOW_RAYS_PER_TRIANGLE * triangles as f64 => Effort::Fast,
            _ => Effort::Full,
        }
    }
}

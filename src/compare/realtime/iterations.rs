//! Question (4): which verdicts change with SVGF's iteration count. Schied et al. 2017 run five
//! à-trous passes on 1280 × 720; the `svgf` default keeps the footprint a share of the image (two
//! passes at 320 × 180, `denoise::edges::default_iterations`). A spec that measures `svgf` beside
//! `svgf:5` (otherwise the same options) asks whether a conclusion is the reduced filter's: each
//! cell of questions (1) and (2) is paired with the same cell under the other count, and the
//! verdicts, RMSE and FLIP, are set side by side. Pipelines are compared typed
//! (`Pipeline::svgf_options`), never by their names.

use super::*;
use crate::denoise::Pipeline;

/// A verdict as it is called: a sign (+1 the first named side wins, −1 the second, 0 a tie),
/// withheld (below floor or a bias interaction), or not measured (no FLIP in the records).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Call {
    Sign(i32),
    Withheld,
    Unmeasured,
}

impl Call {
    fn rmse(v: &Versus, withheld: bool) -> Self {
        if !v.measured() {
            Call::Unmeasured
        } else if withheld {
            Call::Withheld
        } else {
            Call::Sign(v.sign)
        }
    }

    fn flip(v: &Versus) -> Self {
        if v.measured() { Call::Sign(v.sign) } else { Call::Unmeasured }
    }
}

/// Which question a pair of cells answers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Question {
    /// (1): the paper's configuration against the best other.
    Paper,
    /// (2): spatiotemporal blue noise against the 2-D mask, for this distribution/sequence.
    Stbn(String),
}

/// One cell under two SVGF iteration counts: `places[0]` the fewer (the default first), `places[1]`
/// the other; each verdict under both.
#[derive(Debug, Clone, PartialEq)]
pub struct IterationsPair {
    pub question: Question,
    pub places: [Place; 2],
    pub rmse: [Call; 2],
    pub flip: [Call; 2],
}

impl IterationsPair {
    pub fn rmse_changes(&self) -> bool {
        self.rmse[0] != self.rmse[1]
    }

    pub fn flip_changes(&self) -> bool {
        self.flip[0] != self.flip[1] && !self.flip.contains(&Call::Unmeasured)
    }
}

/// SVGF's options without the iteration count, and the count's order (the default, None, first).
fn svgf_of(pipeline: &str) -> Option<(crate::denoise::SvgfOptions, u32)> {
    let o = pipeline.parse::<Pipeline>().ok()?.svgf_options()?;
    Some((crate::denoise::SvgfOptions { iterations: None, ..o }, o.iterations.unwrap_or(0)))
}

/// Pairs of cells that differ only in SVGF's iteration count: a cell's key is its place but the
/// pipeline, and its other options.
fn pairs<C>(cells: &[C], place: impl Fn(&C) -> &Place, extra: impl Fn(&C) -> String) -> Vec<(&C, &C)> {
    let key = |c: &C| {
        let p = place(c);
        svgf_of(&p.pipeline).map(|(o, k)| {
            ((p.scene.clone(), p.rays, p.camera.clone(), p.denoiser.clone(), p.frame, extra(c), o), k)
        })
    };
    let mut out = Vec::new();
    for (i, a) in cells.iter().enumerate() {
        let Some((ka, ia)) = key(a) else { continue };
        for b in &cells[i + 1..] {
            match key(b) {
                Some((kb, ib)) if kb == ka && ib != ia => out.push(if ia < ib { (a, b) } else { (b, a) }),
                _ => {}
            }
        }
    }
    out
}

/// Every pair of question (1) and (2) cells that differ only in SVGF's iteration count.
pub fn iterations_pairs(results: &[JobResult]) -> Vec<IterationsPair> {
    let paper = paper_cells(results).unwrap_or_default();
    let stbn = stbn_cells(results);
    let mut out: Vec<IterationsPair> = pairs(&paper, |c| &c.place, |_| String::new())
        .into_iter()
        .map(|(a, b)| IterationsPair {
            question: Question::Paper,
            places: [a.place.clone(), b.place.clone()],
            rmse: [a, b].map(|c| Call::rmse(&c.rmse, c.below_floor || c.bias_interaction)),
            flip: [a, b].map(|c| Call::flip(&c.flip)),
        })
        .collect();
    out.extend(pairs(&stbn, |c| &c.place, |c| c.prefix.clone()).into_iter().map(|(a, b)| IterationsPair {
        question: Question::Stbn(a.prefix.clone()),
        places: [a.place.clone(), b.place.clone()],
        rmse: [a, b].map(|c| Call::rmse(&c.rmse, c.below_floor || c.bias_interaction)),
        flip: [a, b].map(|c| Call::flip(&c.flip)),
    }));
    out
}

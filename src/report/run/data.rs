//! What the figures and the page are drawn from, and the small questions both ask of it (a row's
//! readable name, a configuration's banding, a sweep's points and slopes). `figures` and `page`
//! depend on this module and never on each other.

use crate::compare::equal_time::{self, EqualTime, TimeView};
use crate::error::Result;
use crate::image::Image;
use crate::load::Loaded;
use crate::metrics::mean_sd;
use crate::reference::store::Reference;
use crate::results::{self, Aggregate, JobResult};
use crate::spec::{Group, GroupKind, Row};
use crate::timing::{Protocol, Summary};

/// How FLIP maps are made (`metrics::flip`): the map of a test image against its reference at
/// `ppd` pixels per degree, and its mean over a coverage. Passed in, so the report draws maps but
/// computes no metric of its own.
#[derive(Clone, Copy)]
pub struct Flip<'a> {
    pub ppd: f64,
    pub map: &'a (dyn Fn(&Image, &Image, f64) -> Image + Sync),
    pub mean: &'a (dyn Fn(&Image, &Image) -> f64 + Sync),
}

impl Flip<'_> {
    /// The map of `image` against `reference`.
    pub fn of(&self, reference: &Image, image: &Image) -> Image {
        (self.map)(reference, image, self.ppd)
    }
}

/// Everything the figures and the page are drawn from.
pub struct ReportInput<'a> {
    pub loaded: &'a Loaded,
    pub references: &'a [Reference],
    /// The camera paths' frames' references, by scene and camera (frame from 0).
    pub views: &'a crate::jobs::reference::ViewReferences,
    pub results: &'a [JobResult],
    pub aggs: Vec<Aggregate>,
    /// How the renders were timed, and each scene's no-AO-ray overhead (spec order).
    pub protocol: Protocol,
    pub overhead: Vec<Option<Summary>>,
    /// Paragraphs the page adds after its timing text (e.g. `merge`: which shard ran where).
    pub notes: Vec<String>,
    /// A record's kept image and its coverage, read by the command that owns the files
    /// (`outdir::record_image`): the image figures' only input from disk.
    pub images: &'a (dyn Fn(&JobResult) -> Result<(Image, Image)> + Sync),
    /// FLIP maps for the error figures and the viewer (`None`: those layers are left out).
    pub flip: Option<Flip<'a>>,
}

impl<'a> ReportInput<'a> {
    /// A record's kept image (what was measured) and its coverage.
    pub fn image(&self, r: &JobResult) -> Result<(Image, Image)> {
        (self.images)(r)
    }

    /// The reference frame `f` (from 1) of scene `si` seen by `camera` is measured against: the
    /// scene's for its own camera, the path's frame's otherwise (frame 0's for a still, jittered
    /// path); `None` where the run did not obtain it.
    pub fn reference_at(&self, si: usize, camera: crate::plan::CameraId, f: u32) -> Option<&'a Reference> {
        match camera.run() {
            None => self.references.get(si),
            Some(run) => {
                self.views.of(si, camera).get(&if run.path.is_static() { 0 } else { f.saturating_sub(1) })
            }
        }
    }

    /// Sweep `g` on `scene` at equal time (`compare::equal_time`), `per_doubling` budgets to each
    /// factor 2 of time: the answer's and the tables' (1), the figure's (4, a smooth line).
    pub fn equal_time(&self, g: &Group, scene: &str, view: TimeView, per_doubling: usize) -> EqualTime {
        equal_time::equal_time(self.results, scene, &g.rows, &g.rays, view, per_doubling)
    }

    /// The spec's `[[convergence]]` groups, with each scene they cover (index, name).
    pub fn sweeps(&self) -> Vec<(&'a Group, usize, &'a str)> {
        let spec = &self.loaded.spec;
        spec.groups
            .iter()
            .filter(|g| g.kind == GroupKind::Convergence)
            .flat_map(|g| g.scenes.iter().map(move |&si| (g, si, spec.scenes[si].name.as_str())))
            .collect()
    }
}

/// Whether a group has paper-table images (`Group::has_single_frames`): a real-time group without
/// one raw frame of the scene's camera has none, only its own figures.
pub fn has_single_frames(g: &Group) -> bool {
    g.has_single_frames()
}

/// A readable name of a row, as the paper says it (`Row::name`: one vocabulary everywhere).
pub fn row_label(row: Row) -> String {
    row.name()
}

/// The readable name of an aggregate's row (its raw names if they no longer parse).
pub fn agg_label(a: &Aggregate) -> String {
    crate::compare::row_of(a)
        .map(row_label)
        .unwrap_or_else(|| format!("{}, {}, {}", a.distribution, a.sequence, a.seed_mode))
}

/// The banding metric of one image: mean of the horizontal and vertical lag-1 error autocorrelation.
fn banding(r: &JobResult) -> f64 {
    0.5 * (r.autocorr_x + r.autocorr_y)
}

/// Mean ± sd of the banding metric over the replicates of a configuration.
pub fn banding_stat(results: &[JobResult], scene: &str, row: Row, rays: u32) -> Option<(f64, f64)> {
    let v: Vec<f64> =
        results.iter().filter(|r| r.is(scene, row, rays)).map(banding).filter(|b| b.is_finite()).collect();
    (!v.is_empty()).then(|| mean_sd(&v))
}

/// Mean ± sd of the low-frequency ratio (the structure verdict's measure) over the replicates of a
/// configuration.
pub fn lowfreq_stat(results: &[JobResult], scene: &str, row: Row, rays: u32) -> Option<(f64, f64)> {
    let v: Vec<f64> = results
        .iter()
        .filter(|r| r.is(scene, row, rays))
        .map(|r| r.lowfreq_ratio)
        .filter(|z| z.is_finite())
        .collect();
    (!v.is_empty()).then(|| mean_sd(&v))
}

/// The aggregates of one sweep row, in ray order.
pub fn sweep_points<'a>(data: &'a ReportInput, g: &Group, scene: &str, row: Row) -> Vec<&'a Aggregate> {
    g.rays.iter().filter_map(|&rays| results::lookup(&data.aggs, scene, row, rays)).collect()
}

/// The fitted slopes of one sweep row, over the sweep's own ray counts.
pub fn sweep_slope(data: &ReportInput, g: &Group, scene: &str, row: Row) -> Option<results::Slope> {
    let pts: Vec<Aggregate> = sweep_points(data, g, scene, row).into_iter().cloned().collect();
    results::convergence_slopes(&pts, &g.rays).into_iter().next()
}

/// Every (scene, row, rays) of the spec's tables, in file order, without duplicates.
pub fn table_configs(data: &ReportInput) -> Vec<(String, Row, u32)> {
    let spec = &data.loaded.spec;
    let mut out: Vec<(String, Row, u32)> = Vec::new();
    for g in spec.groups.iter().filter(|g| g.kind == GroupKind::Table) {
        for &si in &g.scenes {
            for &row in &g.rows {
                for &rays in &g.rays {
                    let c = (spec.scenes[si].name.clone(), row.canonical(), rays);
                    if !out.contains(&c) {
                        out.push(c);
                    }
                }
            }
        }
    }
    out
}

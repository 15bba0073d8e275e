//! What determines a reference image (its manifest), when a stored one may be reused, and the noise
//! floor helpers. Pure: the app reads and writes the files.
//!
//! A reference is the mean of several independent high-ray renders; their spread gives a per-pixel
//! standard error, whose RMS over covered pixels is the *noise floor*: no RMSE measured against this
//! reference means anything below it.

mod camera;
mod pixels;
pub mod store;

pub use camera::{CameraJson, CameraRecord};
pub use pixels::{first_non_finite, pixel_hash};

use crate::image::Image;
use crate::metrics::covered;
use crate::spec::{AoDistance, Row, SceneRef};
use serde::{Deserialize, Serialize};

/// Default target: the floor at most a tenth of the smallest RMSE the spec measures.
pub const FLOOR_RATIO: f64 = 0.1;

/// Everything that determines a reference image, plus what was measured when it was made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    pub hemilab_version: String,
    /// The scene as the spec names it (`SceneRef::id`).
    pub scene: String,
    /// Hash of the scene file and mesh bytes, as the scene loader reports it.
    pub scene_hash: String,
    /// The camera as the scene file places it (`CameraRecord`: JSON, or the older debug string).
    pub camera: CameraRecord,
    pub resolution: [u32; 2],
    /// `AoDistance::canonical()` of the distance actually used.
    pub ao_distance: String,
    pub distribution: String,
    pub sequence: String,
    pub seed_mode: String,
    /// Rays per pixel of each replicate.
    pub rays: u32,
    pub replicates: u32,
    pub seed: u64,
    /// RMS of the per-pixel standard error over covered pixels (measured, not compared).
    #[serde(default)]
    pub noise_floor: Option<f64>,
    /// Render time of all replicates (measured, not compared).
    #[serde(default)]
    pub time_s: Option<f64>,
    /// Set for an adaptive reference (`allocation = "adaptive"`): its rays per pixel follow a pilot
    /// pass, and `rays` is then the pilot's count.
    #[serde(default)]
    pub adaptive: Option<Adaptive>,
    /// What the reference integrates (`sampling::Integrand`'s name). Left out of the file for
    /// `ao`, so that every AO manifest is the text it was before integrands existed.
    #[serde(default = "ao", skip_serializing_if = "is_ao")]
    pub integrand: String,
    /// The reference of a jittered camera (TAA's sub-pixel jitter): each replicate is the mean of
    /// renders at every jitter offset of the cycle (`scene::camera_path::halton_jitter`), what the
    /// jittered frames of a static view converge to, and a pixel counts as covered only where every
    /// offset's primary ray hits. Left out of the file when false, so every other manifest is the
    /// text it was.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub jitter_average: bool,
    /// The reference of a rectangle of the `resolution` image alone (a tile's interior,
    /// `render::Window`), as [x, y, width, height]: its pixels are those of the whole image's
    /// reference in that rectangle, and its image is the rectangle's size. Left out of the file for
    /// a whole image, so every other manifest is the text it was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window: Option<[u32; 4]>,
    /// The content address of the reference's pixels (`pixel_hash` of its mean, standard error and
    /// coverage), checked whenever the reference is read: an image edited after it was made (a
    /// pixel nudged, a NaN) is refused naming the file instead of being measured against. Not part
    /// of what determines the image (`matches`, run keys), only of what the file must hold.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pixels: Option<String>,
}

fn ao() -> String {
    "ao".into()
}

fn is_ao(s: &str) -> bool {
    s == "ao"
}

/// What determines an adaptive reference's allocation, and what it came to. The pilot is rendered
/// with the manifest's estimator and `pilot_rays` rays, seeds from their own stream; the rule turns
/// its per-pixel spread into rays per pixel, deterministically, so these settings and the seed
/// determine the image exactly.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Adaptive {
    /// The allocation rule and its version (`ADAPTIVE_RULE`).
    pub rule: String,
    /// The fewest rays any covered pixel gets.
    pub min_rays: u32,
    /// `Some(n)`: a fixed budget, n rays per covered pixel on average (`rays = n` in the spec);
    /// `None`: as many as the target floor needs (`rays = "auto"`).
    pub budget: Option<u32>,
    /// Rays per replicate actually cast over the covered pixels (measured, not compared).
    #[serde(default)]
    pub total_rays: Option<u64>,
    /// The most rays any pixel got (measured, not compared).
    #[serde(default)]
    pub max_rays: Option<u32>,
}

/// Version of the allocation rule: bump it when `allocate` changes, so stored references are redone.
pub const ADAPTIVE_RULE: &str = "sd-proportional-v1";

/// The numbers `allocate` works from (see there).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Allocation {
    /// K, the reference's replicates.
    pub replicates: u32,
    /// R0, the pilot's rays per pixel.
    pub pilot_rays: u32,
    /// Mean rays per covered pixel, or `None` to meet `target_floor`.
    pub budget: Option<u32>,
    pub target_floor: f64,
    pub min_rays: u32,
    pub max_rays: u32,
}

/// Rays per pixel of an adaptive reference. Replicate k renders pixel i with n_i rays of an unbiased
/// estimator; the n_i depend only on a pilot pass rendered with *other* seeds, so each replicate's
/// estimate is unbiased given the n_i, and so is their mean, and the spread of the replicates still
/// gives an honest standard error.
///
/// With the pilot's per-pixel sd s_i at `pilot_rays` R0 rays, a pixel's variance at n rays is at most
/// s_i² R0 / n (variance falls at least as 1/n for an unbiased estimator of independent or
/// better-than-independent rays), so the squared noise floor of K replicates is at most
/// (R0 / (P K)) Σ s_i² / n_i over the P covered pixels. For a fixed total Σ n_i this is least for
/// n_i ∝ s_i (Neyman allocation; Lagrange multipliers), giving (R0 / (P K)) (Σ s_i)² / Σ n_i — never
/// more than even allocation's (R0 / (P K)) P Σ s_i² / Σ n_i, by Cauchy–Schwarz, and much less when
/// the spread sits in a few pixels (occlusion edges) and most pixels are exact (open sky, full
/// occlusion). With no budget, the total is the least that brings that bound to `target_floor`;
/// with a budget of n, the total is n per covered pixel.
/// Every covered pixel gets at least `min_rays` (a pilot can miss a rare occluder) and at most
/// `max_rays`; background pixels get 0.
pub fn allocate(sd: &Image, mask: &Image, a: &Allocation) -> Vec<u32> {
    let Allocation { replicates, pilot_rays, budget, target_floor, min_rays, max_rays } = *a;
    let idx: Vec<usize> = (0..sd.len().min(mask.len())).filter(|&i| covered(mask, i)).collect();
    let sum_s: f64 = idx.iter().map(|&i| (sd.data[i] as f64).max(0.0)).sum();
    let mut n = vec![0u32; sd.len()];
    let p = idx.len() as f64;
    // n_i = λ s_i: either Σ n_i = budget, or (R0 / (P K)) Σ s_i / λ = target².
    let lambda = match budget {
        Some(b) if sum_s > 0.0 => b as f64 * p / sum_s,
        None if sum_s > 0.0 && target_floor > 0.0 => {
            pilot_rays as f64 * sum_s / (p * replicates.max(1) as f64 * target_floor * target_floor)
        }
        _ => 0.0,
    };
    for &i in &idx {
        let want = (lambda * (sd.data[i] as f64).max(0.0)).ceil();
        n[i] = if want.is_finite() { want.clamp(min_rays as f64, max_rays as f64) as u32 } else { max_rays };
    }
    n
}

impl Manifest {
    /// The manifest a run wants; `scene_hash`, `camera`, and the resolution and distance actually
    /// used (the spec's override or the scene's own) come from the scene loader.
    #[allow(clippy::too_many_arguments)]
    pub fn wanted(
        scene: &SceneRef,
        scene_hash: &str,
        camera: CameraRecord,
        resolution: [u32; 2],
        ao_distance: AoDistance,
        estimator: Row,
        rays: u32,
        replicates: u32,
        seed: u64,
    ) -> Self {
        Self {
            hemilab_version: env!("CARGO_PKG_VERSION").into(),
            scene: scene.id.clone(),
            scene_hash: scene_hash.into(),
            camera,
            resolution,
            ao_distance: ao_distance.canonical(),
            distribution: estimator.distribution.name().into(),
            sequence: estimator.sequence.name().into(),
            seed_mode: estimator.seed_mode.name().into(),
            rays,
            replicates,
            seed,
            noise_floor: None,
            time_s: None,
            adaptive: None,
            integrand: scene.integrand.to_string(),
            jitter_average: false,
            window: None,
            pixels: None,
        }
    }

    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a manifest always serializes");
        s.push('\n');
        s
    }

    pub fn from_json(text: &str) -> Result<Self, String> {
        serde_json::from_str(text).map_err(|e| e.to_string())
    }

    /// Differences in what determines the images, `have` → `want`, ignoring rays and replicates
    /// (the two `matches*` rules decide about those).
    fn differences(&self, wanted: &Manifest) -> Vec<String> {
        let mut d = Vec::new();
        let mut cmp = |name: &str, have: String, want: String| {
            if have != want {
                d.push(format!("{name}: stored {have}, wanted {want}"));
            }
        };
        cmp("hemilab_version", self.hemilab_version.clone(), wanted.hemilab_version.clone());
        cmp("scene", self.scene.clone(), wanted.scene.clone());
        cmp("scene_hash", self.scene_hash.clone(), wanted.scene_hash.clone());
        cmp("camera", self.camera.legacy(), wanted.camera.legacy());
        cmp("resolution", format!("{:?}", self.resolution), format!("{:?}", wanted.resolution));
        cmp("ao_distance", self.ao_distance.clone(), wanted.ao_distance.clone());
        cmp("distribution", self.distribution.clone(), wanted.distribution.clone());
        cmp("sequence", self.sequence.clone(), wanted.sequence.clone());
        cmp("seed_mode", self.seed_mode.clone(), wanted.seed_mode.clone());
        cmp("seed", self.seed.to_string(), wanted.seed.to_string());
        cmp("integrand", self.integrand.clone(), wanted.integrand.clone());
        cmp("jitter_average", self.jitter_average.to_string(), wanted.jitter_average.to_string());
        cmp("window", format!("{:?}", self.window), format!("{:?}", wanted.window));
        // An adaptive reference's settings, not what they came to.
        let settings = |a: &Option<Adaptive>| match a {
            Some(a) => format!("adaptive ({}, min {} rays, budget {:?})", a.rule, a.min_rays, a.budget),
            None => "even".to_string(),
        };
        cmp("allocation", settings(&self.adaptive), settings(&wanted.adaptive));
        d
    }

    /// A stored reference may be reused only if everything that determines it is the same.
    pub fn matches(&self, wanted: &Manifest) -> Result<(), Vec<String>> {
        let mut d = self.differences(wanted);
        if self.rays != wanted.rays {
            d.push(format!("rays: stored {}, wanted {}", self.rays, wanted.rays));
        }
        if self.replicates != wanted.replicates {
            d.push(format!("replicates: stored {}, wanted {}", self.replicates, wanted.replicates));
        }
        if d.is_empty() { Ok(()) } else { Err(d) }
    }

    /// For `rays = "auto"`: any ray count and replicate count will do if the stored noise floor is
    /// at most `max_floor`.
    pub fn matches_auto(&self, wanted: &Manifest, max_floor: f64) -> Result<(), Vec<String>> {
        let mut d = self.differences(wanted);
        match self.noise_floor {
            Some(f) if f <= max_floor => {}
            Some(f) => d.push(format!("noise_floor: stored {f:.3e}, wanted at most {max_floor:.3e}")),
            None => d.push("noise_floor: not recorded".into()),
        }
        if d.is_empty() { Ok(()) } else { Err(d) }
    }

    /// What determines the image, as text: the manifest without what was measured (noise floor,
    /// time, pixel hash, an adaptive reference's totals) and with the camera in its older form.
    fn settings(&self) -> String {
        let adaptive = self.adaptive.clone().map(|a| Adaptive { total_rays: None, max_rays: None, ..a });
        let m = Manifest {
            noise_floor: None,
            time_s: None,
            pixels: None,
            adaptive,
            camera: CameraRecord::Legacy(self.camera.legacy()),
            ..self.clone()
        };
        m.to_json()
    }

    /// The size of the reference's image: its window's, or the resolution.
    pub fn image_size(&self) -> [u32; 2] {
        self.window.map_or(self.resolution, |[_, _, w, h]| [w, h])
    }

    /// File stem of a reference whose view has a reference of other settings already
    /// (`file_stem` taken): the view's stem and a hash of everything that determines the image,
    /// so another estimator, ray count or allocation gets a name of its own and never overwrites
    /// the one there (a 20-ray adaptive reference once replaced a committed one of the same view).
    pub fn settings_stem(&self) -> String {
        format!("{}-{:08x}", self.file_stem(), crate::plan::fnv1a64(self.settings().as_bytes()) as u32)
    }

    /// File stem under `reference/`: readable, and the same for every ray count and estimator: the
    /// first reference of a view takes it; one of other settings takes `settings_stem`.
    pub fn file_stem(&self) -> String {
        let name = std::path::Path::new(&self.scene)
            .file_stem()
            .map_or("scene".to_string(), |s| s.to_string_lossy().into_owned());
        let mut what =
            format!("{};{};{:?};{}", self.scene, self.camera.legacy(), self.resolution, self.ao_distance);
        if self.jitter_average {
            what.push_str(";jitter-average");
        }
        if let Some([x, y, w, h]) = self.window {
            what.push_str(&format!(";window={x},{y}+{w}x{h}"));
        }
        let h = crate::plan::fnv1a64(what.as_bytes());
        // Another integrand's reference sits beside the AO one of the same view.
        let of = if is_ao(&self.integrand) { String::new() } else { format!("-{}", self.integrand) };
        // A window's reference says so in its name: it is never taken for a whole frame's.
        let tile = if self.window.is_some() { "-tile" } else { "" };
        format!("{name}{of}-{}x{}{tile}-{:08x}", self.resolution[0], self.resolution[1], h as u32)
    }
}

/// Per-pixel mean and standard error of the mean (sample sd / √n) of independent renders.
pub fn mean_and_stderr(replicates: &[Image]) -> Result<(Image, Image), String> {
    let first = replicates.first().ok_or("no reference replicates")?;
    if replicates.len() < 2 {
        return Err("a standard error needs at least 2 reference replicates".into());
    }
    if replicates.iter().any(|r| !r.same_size(first)) {
        return Err("reference replicates differ in size".into());
    }
    let n = replicates.len() as f64;
    let mut mean = Image::new(first.width, first.height);
    let mut se = Image::new(first.width, first.height);
    for i in 0..first.len() {
        let m = replicates.iter().map(|r| r.data[i] as f64).sum::<f64>() / n;
        let var = replicates.iter().map(|r| (r.data[i] as f64 - m).powi(2)).sum::<f64>() / (n - 1.0);
        mean.data[i] = m as f32;
        se.data[i] = (var / n).sqrt() as f32;
    }
    Ok((mean, se))
}

/// RMS of the per-pixel standard error over covered pixels (0 when nothing is covered).
pub fn noise_floor(stderr: &Image, mask: &Image) -> f64 {
    let (mut n, mut sq) = (0usize, 0.0f64);
    for i in (0..stderr.len().min(mask.len())).filter(|&i| covered(mask, i)) {
        sq += (stderr.data[i] as f64).powi(2);
        n += 1;
    }
    if n == 0 { 0.0 } else { (sq / n as f64).sqrt() }
}

/// The largest value over each covered pixel's 3 x 3 covered neighbourhood. A spread measured from a
/// few pilot replicates can read 0 or near 0 by chance (all replicates hit the same count of a small
/// occluder); its neighbours, seeing the same occluder, guard against starving such a pixel.
pub fn neighbourhood_max(img: &Image, mask: &Image) -> Image {
    let (w, h) = (img.width as i64, img.height as i64);
    let mut out = Image::new(img.width, img.height);
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            if !covered(mask, i) {
                continue;
            }
            let mut m = img.data[i];
            for (dx, dy) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                let (nx, ny) = (x + dx, y + dy);
                if nx >= 0 && ny >= 0 && nx < w && ny < h {
                    let j = (ny * w + nx) as usize;
                    if covered(mask, j) {
                        m = m.max(img.data[j]);
                    }
                }
            }
            out.data[i] = m;
        }
    }
    out
}

/// Covered pixels of a coverage mask.
pub fn noise_floor_pixels(mask: &Image) -> usize {
    (0..mask.len()).filter(|&i| covered(mask, i)).count()
}

/// The floor a reference should reach for a spec whose smallest measured RMSE is `smallest_rmse`.
pub fn target_floor(smallest_rmse: f64) -> f64 {
    smallest_rmse * FLOOR_RATIO
}

/// Rays per replicate needed to bring `floor` (measured with `rays` per replicate, same replicate
/// count) down to `target`, since the floor falls as 1/√rays. Never less than `rays`.
pub fn rays_needed(floor: f64, rays: u32, target: f64) -> u64 {
    if target.is_nan() || target <= 0.0 || !floor.is_finite() || floor <= target {
        return rays as u64;
    }
    let r = (rays as f64 * (floor / target).powi(2)).ceil();
    if r >= u64::MAX as f64 { u64::MAX } else { r as u64 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn allocation_follows_the_spread_and_meets_the_target_bound() {
        // Four covered pixels: exact (sd 0), small, large spread; one background pixel.
        let sd = Image::from_vec(5, 1, vec![0.0, 0.01, 0.04, 0.04, 0.5]);
        let mask = Image::from_vec(5, 1, vec![1.0, 1.0, 1.0, 1.0, 0.0]);
        let (k, r0, target) = (4u32, 64u32, 0.002);
        let at = |budget: Option<u32>, min_rays: u32, max_rays: u32| Allocation {
            replicates: k,
            pilot_rays: r0,
            budget,
            target_floor: target,
            min_rays,
            max_rays,
        };
        let n = allocate(&sd, &mask, &at(None, 8, 1 << 22));
        assert_eq!((n[0], n[4]), (8, 0), "exact pixel gets the minimum, background nothing: {n:?}");
        assert_eq!(n[2], n[3]);
        assert!((n[2] as f64 / n[1] as f64 - 4.0).abs() < 0.01, "rays ∝ sd: {n:?}");
        // The bound (R0 / (P K)) Σ s_i² / n_i at the allocation is the target (up to rounding up).
        let bound = (0..4).map(|i| (sd.data[i] as f64).powi(2) / n[i] as f64).sum::<f64>() * r0 as f64
            / (4.0 * k as f64);
        assert!(bound.sqrt() <= target && bound.sqrt() > 0.99 * target, "{} vs {target}", bound.sqrt());
        // Even allocation needs more rays for the same bound: P Σ s² / (Σ s)² times as many.
        let total: u64 = n[1..4].iter().map(|&x| x as u64).sum();
        let even_each = r0 as f64 * (0..4).map(|i| (sd.data[i] as f64).powi(2)).sum::<f64>()
            / (4.0 * k as f64 * target * target);
        assert!((total as f64) < 0.8 * 4.0 * even_each, "{total} vs {}", 4.0 * even_each);
        // A fixed budget is split in proportion, and an all-exact image gets the minimum everywhere.
        let b = allocate(&sd, &mask, &at(Some(225), 1, 1 << 22));
        assert_eq!(&b[1..4], &[100, 400, 400]);
        let flat = Image::from_vec(5, 1, vec![0.0; 5]);
        assert_eq!(allocate(&flat, &mask, &at(None, 3, 99)), vec![3, 3, 3, 3, 0]);
        assert_eq!(allocate(&sd, &mask, &at(Some(1 << 30), 1, 500))[2], 500, "capped");
    }

    #[test]
    fn neighbourhood_max_stays_on_covered_pixels() {
        let img = Image::from_vec(3, 2, vec![0.0, 0.0, 0.5, 0.0, 0.1, 9.0]);
        let mask = Image::from_vec(3, 2, vec![1.0, 1.0, 1.0, 1.0, 1.0, 0.0]);
        let m = neighbourhood_max(&img, &mask);
        assert_eq!(m.data, vec![0.1, 0.5, 0.5, 0.1, 0.5, 0.0]);
    }

    #[test]
    fn rays_needed_scales_with_square() {
        assert_eq!(rays_needed(0.02, 1000, 0.01), 4000);
        assert_eq!(rays_needed(0.005, 1000, 0.01), 1000);
        assert_eq!(rays_needed(0.03, 100, 0.01), 900);
    }

    #[test]
    fn stderr_of_two_images() {
        let a = Image::from_vec(2, 1, vec![0.0, 1.0]);
        let b = Image::from_vec(2, 1, vec![1.0, 1.0]);
        let (m, se) = mean_and_stderr(&[a, b]).unwrap();
        assert_eq!(m.data, vec![0.5, 1.0]);
        // sd = sqrt(0.5), se = sd / sqrt(2) = 0.5
        assert!((se.data[0] - 0.5).abs() < 1e-6 && se.data[1] == 0.0);
        let mask = Image::from_vec(2, 1, vec![1.0, 0.0]);
        assert!((noise_floor(&se, &mask) - 0.5).abs() < 1e-6);
        assert!(mean_and_stderr(&[m]).is_err());
    }
}

#[cfg(test)]
mod manifest_tests;

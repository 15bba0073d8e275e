//! A job's image size and AO distance: the spec's overrides where it has them, else the scene's own.

use crate::scene::Scene;
use crate::spec::AoDistance;

/// Image size and AO distance of a job: the spec's override, else the scene's own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geometry {
    pub width: u32,
    pub height: u32,
    pub distance: AoDistance,
}

impl Geometry {
    pub fn of(resolution: Option<[u32; 2]>, distance: Option<AoDistance>, scene: &Scene) -> Self {
        let [width, height] = resolution.unwrap_or([scene.resolution.0, scene.resolution.1]);
        let distance = distance.unwrap_or(if scene.ao_distance.is_finite() {
            AoDistance::Finite(scene.ao_distance as f64)
        } else {
            AoDistance::Infinite
        });
        Self { width, height, distance }
    }

    pub fn pixels(&self) -> u64 {
        self.width as u64 * self.height as u64
    }
}

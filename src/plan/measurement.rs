//! What is measured of a job's images besides the configuration that renders them: what the rays
//! integrate, how the frames are randomized over time, what is done to them before the error is
//! taken, and at which frame. One typed value, carried by every `Job` and `JobResult`, so that a
//! new axis of measurement (a camera path, say) is one more field here and not one more special
//! case in each stage.
//!
//! The paper's measurement — one raw AO frame — is `Measurement::PAPER`; it adds nothing to a job's
//! key, so every key of a spec without the newer axes is what it was before they existed.

use crate::denoise::Pipeline;
use crate::sampling::{Integrand, Schedule};
use std::fmt::Write as _;

/// What one job's image measures (see the module's doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measurement {
    /// What the rays integrate (`sampling::Integrand`).
    pub integrand: Integrand,
    /// The frame whose image is measured, counted from 1: frames 0..frame-1 of a static camera
    /// are rendered (with `SamplerConfig::with_frame`) when the pipeline accumulates, only the
    /// last one when it does not.
    pub frame: u32,
    /// How the per-pixel randomization changes from frame to frame.
    pub schedule: Schedule,
    /// What is done to the frames before the image is measured (`denoise::Pipeline`).
    pub pipeline: Pipeline,
}

impl Default for Measurement {
    fn default() -> Self {
        Self::PAPER
    }
}

impl Measurement {
    /// One raw AO frame: the paper's tables.
    pub const PAPER: Measurement = Measurement {
        integrand: Integrand::Ao,
        frame: 1,
        schedule: Schedule::Independent,
        pipeline: Pipeline::RAW,
    };

    /// The same measurement of another integrand.
    pub fn of(integrand: Integrand) -> Self {
        Self { integrand, ..Self::PAPER }
    }

    /// Whether one raw frame is measured (frame 1, independent schedule, raw), of any integrand:
    /// the images the paper's tables, aggregates and equal-time comparisons read.
    pub fn is_single_frame(&self) -> bool {
        self.frame == 1 && self.schedule == Schedule::Independent && self.pipeline == Pipeline::RAW
    }

    /// The frame indices (from 0) a job renders: all `frame` frames when the pipeline
    /// accumulates, the one last frame when it does not.
    pub fn frames_rendered(&self) -> Vec<u32> {
        if self.pipeline.is_temporal() { (0..self.frame).collect() } else { vec![self.frame - 1] }
    }

    /// Whether the timing protocol's second round (more renders for cheap configurations) applies:
    /// a multi-frame measurement is run for its errors, its many cheap units would each be
    /// re-rendered up to `max_repeats` times, and its times are those of the first round.
    pub fn tops_up(&self) -> bool {
        self.is_single_frame()
    }

    /// `;frame=..;schedule=..;pipeline=..` for a multi-frame measurement, empty for a single frame;
    /// part of the job's key and of its timing unit.
    pub fn frames_key(&self) -> String {
        if self.is_single_frame() {
            String::new()
        } else {
            format!(";frame={};schedule={};pipeline={}", self.frame, self.schedule, self.pipeline)
        }
    }

    /// What the jobs of one series of frames share (`plan::series`): for a pipeline that
    /// accumulates, the frames part without the frame, so that every reported frame of one
    /// sequence is read from one render of it; otherwise `frames_key`. Part of the timing unit.
    pub fn series_key(&self) -> String {
        if self.pipeline.is_temporal() {
            format!(";schedule={};pipeline={}", self.schedule, self.pipeline)
        } else {
            self.frames_key()
        }
    }

    /// Everything this measurement adds to a job's canonical text: the frames part, then
    /// `;integrand=..` unless it is AO.
    pub fn key_suffix(&self) -> String {
        let mut s = self.frames_key();
        if self.integrand != Integrand::Ao {
            let _ = write!(s, ";integrand={}", self.integrand);
        }
        s
    }

    /// `-<schedule>-<pipeline>-f<frame>` for a multi-frame measurement's file names, empty for one frame.
    pub fn file_part(&self) -> String {
        if self.is_single_frame() {
            String::new()
        } else {
            format!("-{}-{}-f{}", self.schedule, self.pipeline, self.frame)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_measurement_adds_nothing_to_a_key() {
        assert_eq!(Measurement::PAPER.key_suffix(), "");
        assert_eq!(Measurement::PAPER.file_part(), "");
        assert!(Measurement::PAPER.is_single_frame() && Measurement::PAPER.tops_up());
        assert_eq!(Measurement::PAPER.frames_rendered(), vec![0]);
        let v = Measurement::of(Integrand::Visibility);
        assert!(v.is_single_frame());
        assert_eq!(v.key_suffix(), ";integrand=visibility");
    }

    #[test]
    fn a_temporal_pipeline_renders_every_frame_a_spatial_one_the_last() {
        let m = |p: &str, frame| Measurement { frame, pipeline: p.parse().unwrap(), ..Measurement::PAPER };
        assert_eq!(m("ema0.1+atrous", 4).frames_rendered(), vec![0, 1, 2, 3]);
        assert_eq!(m("atrous", 4).frames_rendered(), vec![3]);
        assert_eq!(m("atrous", 1).frames_key(), ";frame=1;schedule=independent;pipeline=atrous");
        assert!(!m("atrous", 1).tops_up());
    }
}

//! `timing.json`, typed: how a run was timed (the clock, what a time includes, the protocol), each
//! scene's per-image overhead, and what the session cost. One type writes the file and every
//! reader (a resumed run, `merge`, the report's cost quote, advise's JSON) reads it back, so a key
//! is spelt in one place. Fields are in alphabetical order, the order the file has always had.

use super::{Protocol, Summary};
use serde::{Deserialize, Serialize};

/// What a session of renders cost.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct SessionRecord {
    /// Thread CPU seconds of its timed renders, summed.
    pub timed_cpu_s: f64,
    /// Timed renders it ran.
    pub timed_renders: usize,
    /// Its wall seconds.
    pub wall_s: f64,
}

/// One scene's no-AO-ray render times (`None` if the scene had no job).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneOverhead {
    pub overhead_s: Option<Summary>,
    pub scene: String,
}

/// A run's (or a shard's) `timing.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunTiming {
    pub clock: String,
    pub overhead: Vec<SceneOverhead>,
    pub protocol: Protocol,
    pub session: SessionRecord,
    pub time_includes: String,
}

impl RunTiming {
    pub fn new(protocol: Protocol, overhead: Vec<SceneOverhead>, session: SessionRecord) -> Self {
        Self {
            clock: super::clock::NAME.into(),
            overhead,
            protocol,
            session,
            time_includes: super::TIME_INCLUDES.into(),
        }
    }

    /// The overhead recorded for scene `name`.
    pub fn overhead_of(&self, name: &str) -> Option<Summary> {
        self.overhead.iter().find(|o| o.scene == name).and_then(|o| o.overhead_s)
    }

    /// Pretty JSON with every object's keys in alphabetical order.
    pub fn to_json(&self) -> String {
        let v = serde_json::to_value(self).unwrap_or_default();
        serde_json::to_string_pretty(&v).unwrap_or_default()
    }

    pub fn from_json(text: &str) -> Result<Self, String> {
        serde_json::from_str(text).map_err(|e| e.to_string())
    }
}

//! What the finished renders of a run have produced so far: the records by plan position, the
//! timing-only renders that finished before their job's record, the overhead renders' times and
//! the session's totals. Every new record is written out at once, so a killed run keeps it.

use crate::error::Result;
use crate::interrupt;
use crate::results::JobResult;
use crate::timing::{Slot, Time};
use std::collections::HashMap;

/// Whatever a worker hands back for one slot: the render's time, and per job the render produced
/// (a series' members: `plan::series`) that job's time and, when the slot records, its record.
pub(super) struct Done {
    pub time: Time,
    pub parts: Vec<(usize, Time, Option<JobResult>)>,
}

pub(super) struct State {
    /// By plan position: resumed, or filled as jobs finish.
    pub records: Vec<Option<JobResult>>,
    /// Timing-only renders that finished before their job's first render did.
    pub pending: HashMap<usize, Vec<Time>>,
    /// Per scene: the no-AO-ray renders' times.
    pub overhead_samples: Vec<Vec<f64>>,
    pub renders: usize,
    pub cpu_s: f64,
}

impl State {
    pub fn new(records: Vec<Option<JobResult>>, scenes: usize) -> Self {
        Self {
            records,
            pending: HashMap::new(),
            overhead_samples: vec![Vec::new(); scenes],
            renders: 0,
            cpu_s: 0.0,
        }
    }

    /// Files one finished render (`n`: the plan's job count; ids from `n` on are overhead renders).
    /// New records are written out at once, so a killed run keeps them.
    pub fn done(&mut self, n: usize, slot: &Slot, d: Done, write: &super::Write) -> Result<()> {
        self.renders += 1;
        self.cpu_s += d.time.cpu_s;
        if slot.job >= n {
            self.overhead_samples[slot.job - n].push(d.time.cpu_s);
            return Ok(());
        }
        let mut new = Vec::new();
        for (job, time, record) in d.parts {
            match (record, &mut self.records[job]) {
                (Some(mut rec), r) => {
                    rec.add_time(time.cpu_s, time.wall_s);
                    for t in self.pending.remove(&job).unwrap_or_default() {
                        rec.add_time(t.cpu_s, t.wall_s);
                    }
                    new.push(rec.clone());
                    *r = Some(rec);
                }
                (None, Some(rec)) => rec.add_time(time.cpu_s, time.wall_s),
                (None, None) => self.pending.entry(job).or_default().push(time),
            }
        }
        if !new.is_empty() {
            write(&super::Saved { new: &new, so_far: &self.records })?;
            interrupt::jobs_done(self.records.iter().flatten().count());
        }
        Ok(())
    }

    /// Every timed render of job `i` so far.
    pub fn samples(&self, i: usize) -> Vec<f64> {
        let mut v: Vec<f64> = self.records[i].as_ref().map(|r| r.times.clone()).unwrap_or_default();
        v.extend(self.pending.get(&i).into_iter().flatten().map(|t| t.cpu_s));
        v
    }
}

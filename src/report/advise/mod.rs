//! `hemilab advise`'s outputs: its page, `advice.json`, and its figures (error against time, winner
//! maps).

pub mod figures;
pub mod json;
pub mod page;

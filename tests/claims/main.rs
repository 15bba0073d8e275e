//! The paper's claims, asserted on real renders of the shipped claims specs against the committed
//! references: on the kitchen (`paper`) and on every shipped scene (`scenes`).

#[path = "../support/mod.rs"]
mod support;

mod engine_noise;
mod integrands;
mod lowfreq;
mod paper;
mod readme;
mod realtime;
mod realtime_split;
mod scenes;

//! Helpers shared by the three test binaries (`cli`, `stages`, `claims`). Each includes this module
//! with `#[path = "../support/mod.rs"] mod support;` and uses only part of it.
#![allow(dead_code)]

pub mod common;
pub mod examples;
pub mod gltf_ext;
pub mod images;
pub mod jobs;
pub mod lambert;
pub mod mutate;
pub mod parallax;
pub mod room;
pub mod stats;

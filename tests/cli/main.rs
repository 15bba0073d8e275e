//! The command-line contract: every test here runs the real `hemilab` binary (`CARGO_BIN_EXE_hemilab`),
//! mostly in a temporary directory of its own, and checks its exit status, messages and files.

#[path = "../support/mod.rs"]
mod support;

mod advise;
mod advise_pipeline;
mod advise_runs;
mod bad_inputs;
mod bench_dump;
mod external_sampler;
mod first_hour;
mod help_readme;
mod interrupt;
mod no_surprises;
mod plan_estimate;
mod points;
mod reference_adaptive;
mod reference_content;
mod reference_dir;
mod render;
mod render_gltf;
mod render_integrand;
mod report_page;
mod report_viewer;
mod run_answer;
mod run_errors;
mod run_realtime;
mod run_results;
mod run_tiles;
mod shard_merge;
mod textures;

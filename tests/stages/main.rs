//! The stages' properties, through the library: warps and sequences (χ², exact structure), estimators
//! against closed forms, the BVH against brute force, rendering (exact scenes, determinism, extreme
//! coordinates), metrics, the plan and its shards, spec and scene files.

#[path = "../support/mod.rs"]
mod support;

mod compare_equal_time;
mod denoise_bias;
mod denoise_command;
mod denoise_filters;
mod denoise_gbuffer;
mod denoise_joint;
mod denoise_kept_taps;
mod denoise_svgf;
mod denoise_temporal;
mod fuzz_files;
mod fuzz_inputs;
mod load_bounds;
mod metrics_flicker;
mod metrics_flip;
mod metrics_known;
mod plan_integrands;
mod plan_order;
mod plan_shard;
mod plan_tiles;
mod reference_hashes;
mod render_closed_form;
mod render_closed_room;
mod render_determinism;
mod render_exact;
mod render_integrands;
mod render_kept_primaries;
mod render_reproject;
mod render_robust;
mod render_stiff;
mod render_window;
mod sampling_blue_noise;
mod sampling_engine_noise;
mod sampling_estimators;
mod sampling_frame;
mod sampling_point_files;
mod sampling_registry;
mod sampling_samplers;
mod sampling_schedule;
mod sampling_sequences;
mod sampling_stbn;
mod sampling_textures;
mod sampling_warps;
mod scene_alpha;
mod scene_build_order;
mod scene_bvh;
mod scene_camera_path;
mod scene_files;
mod scene_gltf;
mod scene_gltf_ext;
mod scene_gltf_wall;
mod scene_obj_alpha;
mod scene_primary_packets;
mod scene_repeats;
mod spec_errors;
mod spec_files;
mod stats;

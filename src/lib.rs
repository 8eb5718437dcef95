//! argil: a real-time renderer of physically based clay on explicit Vulkan.
//!
//! - [`vk`]: the explicit Vulkan pieces, one concept a file.
//! - [`render`]: passes built from them, and the renderer that owns device and pipelines.
//! - [`scene`]: scene files, meshes, materials, lights, camera.
//! - [`brdf`]: f64 reference models, twins of the GLSL in `shaders/lib`.
//! - [`viewer`]: the interactive window.
//! - [`verify`]: `argil verify`, the GPU and f64 checks of every BRDF.
//! - [`reference`]: `argil reference`, the Monte Carlo ground truth of a scene, in f64.
//! - [`compare`]: `argil compare`, error figures and ꟻLIP of one EXR against a reference.
//! - [`bench`]: `argil bench`, run time against error, and the trivial-shader floor.
//! - [`cache`]: what every start computes alike, kept on disk for the next.
//! - [`error`]: error types the command line maps to exit codes; [`atomic`]: output files
//!   written whole or not at all.
//! - [`fault`]: `ARGIL_FAULT`, failures injected for tests; [`scratch`]: folders removed
//!   when done; [`interrupt`]: Ctrl-C for the commands with work to keep.
//! - [`fuzz`]: the loaders' fuzz targets and mutations (`argil-fuzz`, `tests/fuzz.rs`).

pub mod atomic;
pub mod bench;
pub mod brdf;
pub mod cache;
pub mod compare;
pub mod error;
pub mod fault;
pub mod fuzz;
pub mod interrupt;
pub mod priority;
pub mod reference;
pub mod render;
pub mod rng;
pub mod scene;
pub mod scratch;
pub mod verify;
pub mod viewer;
pub mod vk;

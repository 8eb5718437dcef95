//! Passes built from the Vulkan pieces, and the renderer that owns them.

pub mod accumulate;
pub mod debug_view;
pub mod deferred;
pub mod environment;
pub mod exposure;
pub mod forward;
pub mod fullscreen;
pub mod gpu_scene;
pub mod ground_maps;
pub mod material_data;
pub mod msaa;
pub mod occlusion;
pub mod output;
pub mod renderer;
pub mod shaders;
pub mod shadow;
pub mod split;
pub mod subsurface;
pub mod target;
pub mod textures;
pub mod tonemap;
pub mod vertex_light;
pub mod warm_up;

pub use debug_view::DebugView;
pub use gpu_scene::GpuScene;
pub use output::{count_non_finite, write_frame};
pub use renderer::{DisplayOutput, Frames, OffscreenFrame, OffscreenTarget, Renderer, PASS_NAMES};
pub use split::Split;
pub use target::RenderTarget;

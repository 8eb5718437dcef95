//! Debug views of the forward pass: geometry shown as colours, or one term of the shading
//! alone. The value travels in `FrameData.counts.y` to shaders/lib/debug_views.glsl,
//! whose `DEBUG_VIEW_*` constants are the `as u32` values here.

/// What the forward pass writes into the HDR target. Every view goes through the same
/// display transform as the shaded image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum DebugView {
    /// The normal image.
    #[default]
    Shaded = 0,
    /// World-space shading normal, n·0.5 + 0.5.
    Normals = 1,
    /// World-space tangent, t·0.5 + 0.5.
    Tangents = 2,
    /// World-space bitangent (n × t, times the tangent's handedness), ·0.5 + 0.5.
    Bitangents = 3,
    /// Texture coordinates, fract(u) in red and fract(v) in green.
    Uvs = 4,
    /// Σ max(n·l, 0) over the point lights, grey.
    NDotL = 5,
    /// The diffuse lobe alone under the point lights.
    Diffuse = 6,
    /// The specular lobe alone under the point lights.
    Specular = 7,
    /// The subsurface term alone under the point lights: the report's wrap, or what a
    /// redistributing model adds to the diffuse lobe (negative, so black, where it takes).
    Subsurface = 8,
    /// The uniform environment's contribution alone.
    Environment = 9,
    /// The shaded image with NaN/Inf pixels in magenta.
    NanHighlight = 10,
    /// The mesh's mean curvature (1/world length): red where convex, blue where concave,
    /// brightness 1 - exp(-|κ|/2), so a sphere of radius 1 shows at 0.39 and a plane black.
    Curvature = 11,
    /// The ambient visibility the environment's light is scaled by (GTAO), grey; white
    /// where nothing occludes and everywhere when the occlusion pass is off.
    Occlusion = 12,
}

impl DebugView {
    pub const ALL: [DebugView; 13] = [
        DebugView::Shaded,
        DebugView::Normals,
        DebugView::Tangents,
        DebugView::Bitangents,
        DebugView::Uvs,
        DebugView::NDotL,
        DebugView::Diffuse,
        DebugView::Specular,
        DebugView::Subsurface,
        DebugView::Environment,
        DebugView::NanHighlight,
        DebugView::Curvature,
        DebugView::Occlusion,
    ];

    pub fn label(self) -> &'static str {
        match self {
            DebugView::Shaded => "shaded",
            DebugView::Normals => "normals",
            DebugView::Tangents => "tangents",
            DebugView::Bitangents => "bitangents",
            DebugView::Uvs => "UVs",
            DebugView::NDotL => "n·l",
            DebugView::Diffuse => "diffuse lobe",
            DebugView::Specular => "specular lobe",
            DebugView::Subsurface => "subsurface term",
            DebugView::Environment => "environment",
            DebugView::NanHighlight => "NaN/Inf highlight",
            DebugView::Curvature => "curvature",
            DebugView::Occlusion => "ambient occlusion",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_lists_every_view_once_in_shader_order() {
        for (i, view) in DebugView::ALL.iter().enumerate() {
            assert_eq!(*view as u32, i as u32);
        }
        let shader = include_str!("../../shaders/lib/debug_views.glsl");
        for view in DebugView::ALL {
            let name = format!("= {}u;", view as u32);
            assert!(shader.contains(&name), "debug_views.glsl has no constant {name}");
        }
    }
}

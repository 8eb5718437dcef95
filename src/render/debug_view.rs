//! Debug views of the forward pass: geometry shown as colours, or one term of the shading
//! alone. The value travels in `FrameData.counts.y` to shaders/lib/debug_views.glsl,
//! whose `DEBUG_VIEW_*` constants are the `as u32` values here.

/// `CURVATURE_VIEW_SCALE` in debug_views.glsl: the curvature view's brightness is
/// 1 − exp(−|κ| · CURVATURE_VIEW_SCALE).
pub const CURVATURE_VIEW_SCALE: f64 = 0.5;

/// The curvature view's colour at mean curvature `kappa` (1/world length): red where
/// convex, blue where concave (debug_views.glsl's `DEBUG_VIEW_CURVATURE` branch).
pub fn curvature_color(kappa: f64) -> [f64; 3] {
    let strength = 1.0 - (-kappa.abs() * CURVATURE_VIEW_SCALE).exp();
    if kappa > 0.0 {
        [strength, 0.0, 0.0]
    } else {
        [0.0, 0.0, strength]
    }
}

/// The |κ| the curvature view shows at `brightness` in [0, 1): the inverse of its map.
pub fn curvature_at_brightness(brightness: f64) -> f64 {
    -(1.0 - brightness).ln() / CURVATURE_VIEW_SCALE
}

/// `SHADOW_MAP_VIEW_CHECKER` in debug_views.glsl: the shadow-map view multiplies every
/// other texel of the map by it.
pub const SHADOW_MAP_VIEW_CHECKER: f64 = 0.8;

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
    /// brightness 1 − exp(−|κ| · [`CURVATURE_VIEW_SCALE`]) ([`curvature_color`]), so a
    /// sphere of radius 1 shows at 0.39 and a plane black.
    Curvature = 11,
    /// The ambient visibility the environment's light is scaled by (GTAO), grey; white
    /// where nothing occludes and everywhere when the occlusion pass is off.
    Occlusion = 12,
    /// The point lights' shadow factors, weighted by the luminance of their irradiance, grey:
    /// white where every light is unshadowed, black inside every umbra.
    Shadows = 13,
    /// The light bounced off the ground alone (`[shadows] bounce`); red by the luminance it
    /// takes where the ground is darker than the sky; black with bounce off.
    Bounce = 14,
    /// The first shadow-casting light's cube shadow map projected onto the scene, grey: at
    /// the map's texel nearest to the point's direction, the distance it stores over the
    /// point's, 1 (white) where the shadow test passes; every other texel times
    /// [`SHADOW_MAP_VIEW_CHECKER`], so that the map's resolution shows.
    ShadowMap = 15,
}

impl DebugView {
    pub const ALL: [DebugView; 16] = [
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
        DebugView::Shadows,
        DebugView::Bounce,
        DebugView::ShadowMap,
    ];

    /// Whether the view's values are radiance (one term of the shading alone), so that an
    /// exposure chosen from them reads it at a glance.
    pub fn is_radiance(self) -> bool {
        matches!(
            self,
            DebugView::Diffuse
                | DebugView::Specular
                | DebugView::Subsurface
                | DebugView::Environment
                | DebugView::Bounce
        )
    }

    /// Whether the view shows the environment's light, so that the `sampled` reflection's
    /// noise is in it.
    pub fn shows_environment(self) -> bool {
        matches!(
            self,
            DebugView::Shaded | DebugView::Environment | DebugView::NanHighlight
        )
    }

    /// The view's name on the command line (`argil view --debug-view NAME`).
    pub fn name(self) -> &'static str {
        match self {
            DebugView::Shaded => "shaded",
            DebugView::Normals => "normals",
            DebugView::Tangents => "tangents",
            DebugView::Bitangents => "bitangents",
            DebugView::Uvs => "uvs",
            DebugView::NDotL => "n-dot-l",
            DebugView::Diffuse => "diffuse",
            DebugView::Specular => "specular",
            DebugView::Subsurface => "subsurface",
            DebugView::Environment => "environment",
            DebugView::NanHighlight => "nan",
            DebugView::Curvature => "curvature",
            DebugView::Occlusion => "occlusion",
            DebugView::Shadows => "shadows",
            DebugView::Bounce => "bounce",
            DebugView::ShadowMap => "shadow-map",
        }
    }

    /// The view named `name` (see [`Self::name`]).
    pub fn from_name(name: &str) -> Result<Self, String> {
        Self::ALL.into_iter().find(|v| v.name() == name).ok_or_else(|| {
            let names: Vec<&str> = Self::ALL.iter().map(|v| v.name()).collect();
            format!("{name:?} is not a debug view: one of {}", names.join(", "))
        })
    }

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
            DebugView::Shadows => "shadow factor",
            DebugView::Bounce => "bounced light",
            DebugView::ShadowMap => "shadow map",
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

    #[test]
    fn names_round_trip() {
        for view in DebugView::ALL {
            assert_eq!(DebugView::from_name(view.name()), Ok(view));
        }
        assert!(DebugView::from_name("specular lobe").is_err_and(|e| e.contains("specular, subsurface")));
    }

    #[test]
    fn the_shadow_map_views_checker_is_the_shaders() {
        let shader = include_str!("../../shaders/lib/debug_views.glsl");
        let declared = format!("const float SHADOW_MAP_VIEW_CHECKER = {SHADOW_MAP_VIEW_CHECKER:?};");
        assert!(shader.contains(&declared), "debug_views.glsl does not declare {declared}");
    }

    #[test]
    fn curvature_colours_follow_the_shaders_map() {
        let shader = include_str!("../../shaders/lib/debug_views.glsl");
        let declared = format!("const float CURVATURE_VIEW_SCALE = {CURVATURE_VIEW_SCALE:?};");
        assert!(
            shader.contains(&declared),
            "debug_views.glsl does not declare {declared}"
        );
        assert!(shader.contains("float strength = 1.0 - exp(-abs(curvature) * CURVATURE_VIEW_SCALE);"));
        // The GLSL comment's figures: radius 1 at 0.39, 0.35 at 0.76, 0.1 at 0.99.
        for (radius, shown) in [(1.0, 0.39), (0.35, 0.76), (0.1, 0.99)] {
            let [r, g, b] = curvature_color(1.0 / radius);
            assert!(
                (r - shown).abs() < 0.005 && g == 0.0 && b == 0.0,
                "radius {radius}: {r}"
            );
        }
        assert_eq!(curvature_color(-2.0), [0.0, 0.0, curvature_color(2.0)[0]]);
        assert_eq!(curvature_color(0.0), [0.0; 3]);
        for kappa in [0.1, 1.0, 4.0] {
            let back = curvature_at_brightness(curvature_color(kappa)[0]);
            assert!((back - kappa).abs() < 1e-12, "{kappa} → {back}");
        }
    }
}

// The ground's shadows ([shadows] ground_map): each point light's visibility on the
// ground, as point_light_shadow finds it (shadows.glsl), computed by
// shaders/ground_shadow.comp at the texel centres of a map over the ground's rectangle
// that objects can shadow (shadow_data.ground, src/scene/ground_shadow.rs) once per change
// of the lights, the objects or the shadow maps, and read bilinearly at the ground's pixels
// rather than searched and filtered at every one of them: on a flat ground the receiver's
// plane, all that the shadow depends on besides the point, is the same at every pixel.
// Outside the rectangle every light is seen whole: 1.
#ifndef ARGIL_GROUND_SHADOW_GLSL
#define ARGIL_GROUND_SHADOW_GLSL
#include "ground_light.glsl"

// Whether the draw reads its shadows from the map (src/render/forward.rs): the ground's.
layout(constant_id = 19) const bool GROUND_SHADOWS = false;
// Whether a draw that reads the soft lights' shadows from this map or from its vertices
// (vertex_light.glsl) has hard lights beside them (src/render/forward.rs): their shadow is
// one lookup at each pixel, whose edge the map or the vertices would blur.
layout(constant_id = 21) const bool HARD_SHADOWS_AT_PIXELS = false;

// The ground point at the centre of texel `texel` of the map, `size` texels on a side.
vec3 ground_shadow_point(uvec2 texel, uint size) {
    return ground_texel_point(texel, size, shadow_data.ground.xy, shadow_data.ground.zw);
}

#ifndef GROUND_SHADOW_MAP_WRITER
// Lights 4k to 4k + 3 in the channels of layer k.
layout(set = 5, binding = 2) uniform sampler2DArray ground_shadow_map;

// The fraction of point light i that reaches ground point p.
float ground_map_shadow(uint i, vec3 p) {
    vec2 centre = shadow_data.ground.xy;
    vec2 half_extent = shadow_data.ground.zw;
    vec2 st = ground_texel_uv(p, centre, max(half_extent, vec2(1e-30)));
    float shadow = textureLod(ground_shadow_map, vec3(st, float(i / 4u)), 0.0)[i % 4u];
    return all(lessThan(abs(p.xz - centre), half_extent)) ? shadow : 1.0;
}
#endif

#endif

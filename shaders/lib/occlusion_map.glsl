// The forward pass's view of the ambient occlusion (set 4; src/render/occlusion.rs): the
// visibility GTAO computed at this pixel, or 1 when the frame does not run the pass.
#ifndef ARGIL_OCCLUSION_MAP_GLSL
#define ARGIL_OCCLUSION_MAP_GLSL
#include "occlusion.glsl"

layout(set = 4, binding = 0) uniform sampler2D occlusion_map;
// OcclusionMode of src/render/occlusion.rs; always specialised.
layout(constant_id = 12) const uint OCCLUSION = 0;
const uint OCCLUSION_OFF = 0u;
const uint OCCLUSION_MULTI_BOUNCE = 1u;
const uint OCCLUSION_PLAIN = 2u;

float ambient_visibility(vec2 frag_coord) {
    if (OCCLUSION == OCCLUSION_OFF) return 1.0;
    return texelFetch(occlusion_map, ivec2(frag_coord), 0).r;
}

// What environment_light (environment.glsl) scales the environment's light by at
// visibility x: rgb the diffuse light (x raised by the multi-bounce fit of the albedo, or
// x itself), a the visibility the specular occlusion derives from (1: nothing occluded).
vec4 environment_occlusion(float x, vec3 albedo) {
    if (x >= 1.0) return vec4(1.0);
    return vec4(OCCLUSION == OCCLUSION_MULTI_BOUNCE ? gtao_multi_bounce(x, albedo) : vec3(x), x);
}

#endif

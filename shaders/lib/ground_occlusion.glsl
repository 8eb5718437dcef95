// The objects' occlusion of the environment's light on the ground ([occlusion] objects,
// object_occlusion.glsl) read from the ground's occlusion map, which
// shaders/ground_occlusion.comp computes at the texel centres of the ground's square
// (src/render/ground_maps.rs) once per change of the objects, the ground or the
// environment, rather than from every sphere at every pixel of the ground.
#ifndef ARGIL_GROUND_OCCLUSION_GLSL
#define ARGIL_GROUND_OCCLUSION_GLSL
#include "ground_light.glsl"

layout(set = 5, binding = 1) uniform sampler2D ground_occlusion_map;

// What the occluders make of the environment's diffuse light at ground point p.
vec3 ground_map_occlusion(vec3 p) {
    return textureLod(ground_occlusion_map, ground_light_uv(p), 0.0).rgb;
}

#endif

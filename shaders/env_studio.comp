#version 460
// Level 0 of the studio cube map: studio_radiance at each texel's centre.
#include "env_math.glsl"
#include "env_studio.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform writeonly image2DArray cube;

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    ivec2 size = imageSize(cube).xy;
    if (any(greaterThanEqual(texel.xy, size))) return;
    vec2 ab = (vec2(texel.xy) + 0.5) / vec2(size) * 2.0 - 1.0;
    imageStore(cube, texel, vec4(studio_radiance(cube_direction(uint(texel.z), ab)), 1.0));
}

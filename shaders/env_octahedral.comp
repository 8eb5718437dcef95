#version 460
// One prefiltered level's cube resampled into its layer of the octahedral maps split sum
// reads (env_math.glsl's octahedral_uv): each texel the cube read bilinearly at the texel's
// direction. Layers of one size, a lookup blends two of them at the same lod for every
// pixel, where mips would be read at a lod per pixel, which lavapipe samples at about four
// times the cost.
#include "env_math.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform samplerCube prefiltered;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D target;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    int side = imageSize(target).x;
    if (any(greaterThanEqual(texel, ivec2(side)))) return;
    vec2 p = octahedral_texel_point(vec2(texel), float(side));
    vec3 radiance = textureLod(prefiltered, octahedral_direction(p), 0.0).rgb;
    imageStore(target, texel, vec4(radiance, 1.0));
}

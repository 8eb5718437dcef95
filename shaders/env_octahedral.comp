#version 460
// One prefiltered level's cube resampled into its layer of the octahedral maps split sum
// reads (env_math.glsl's octahedral_uv): each texel the cube read bilinearly at the texel's
// direction. Layers of one size, a lookup blends two of them at the same lod for every
// pixel, where mips would be read at a lod per pixel, which lavapipe samples at about four
// times the cost.
#include "env_math.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform samplerCube prefiltered;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2DArray target;
layout(push_constant) uniform OctahedralPush {
    uint layer;
} push;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    int side = imageSize(target).x;
    if (any(greaterThanEqual(texel, ivec2(side)))) return;
    // Texel 0 and side − 1 are the border, half a texel past the square's edges.
    vec2 p = (vec2(texel) - 0.5) * (2.0 / float(side - 2)) - 1.0;
    vec3 radiance = textureLod(prefiltered, octahedral_direction(p), 0.0).rgb;
    imageStore(target, ivec3(texel, push.layer), vec4(radiance, 1.0));
}

#version 460
// One mip level of a cube map from the level above: each 2×2 block's mean weighted by its
// texels' solid angles, so every level holds the same ∫ L dω (a plain mean would weight
// a face's corners, whose texels subtend down to 1/(3√3) of its centre's, as much).
#include "env_math.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2DArray source;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2DArray target;

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(texel.xy, imageSize(target).xy))) return;
    uint size = uint(imageSize(source).x);
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int i = 0; i < 4; ++i) {
        ivec2 s = texel.xy * 2 + ivec2(i & 1, i >> 1);
        float omega = cube_texel_solid_angle(uvec2(s), size);
        sum += omega * imageLoad(source, ivec3(s, texel.z));
        weight += omega;
    }
    imageStore(target, texel, sum / weight);
}

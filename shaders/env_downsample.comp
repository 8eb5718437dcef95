#version 460
// One mip level of a cube map from the level above: the mean of each 2×2 block.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2DArray source;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2DArray target;

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(texel.xy, imageSize(target).xy))) return;
    ivec3 s = ivec3(texel.xy * 2, texel.z);
    vec4 sum = imageLoad(source, s) + imageLoad(source, s + ivec3(1, 0, 0))
             + imageLoad(source, s + ivec3(0, 1, 0)) + imageLoad(source, s + ivec3(1, 1, 0));
    imageStore(target, texel, 0.25 * sum);
}

#version 460
// Level 0 of a map's cube: the equirectangular image (a storage buffer of RGBA texels,
// rows from the top) read bilinearly at each texel's direction, wrapping around in u.
// Radiance beyond fp16 is clamped to its largest value rather than becoming infinite.
#include "env_math.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform writeonly image2DArray cube;
layout(set = 0, binding = 1, std430) readonly buffer Equirect {
    vec4 texels[];
};
layout(push_constant) uniform EquirectPush {
    ivec2 size;
} map;

vec3 equirect_texel(ivec2 p) {
    int x = ((p.x % map.size.x) + map.size.x) % map.size.x;
    int y = clamp(p.y, 0, map.size.y - 1);
    return texels[y * map.size.x + x].rgb;
}

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    ivec2 size = imageSize(cube).xy;
    if (any(greaterThanEqual(texel.xy, size))) return;
    vec2 ab = (vec2(texel.xy) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec2 p = equirect_uv(cube_direction(uint(texel.z), ab)) * vec2(map.size) - 0.5;
    ivec2 p0 = ivec2(floor(p));
    vec2 f = p - vec2(p0);
    vec3 top = mix(equirect_texel(p0), equirect_texel(p0 + ivec2(1, 0)), f.x);
    vec3 bottom = mix(equirect_texel(p0 + ivec2(0, 1)), equirect_texel(p0 + ivec2(1, 1)), f.x);
    imageStore(cube, texel, vec4(min(mix(top, bottom, f.y), vec3(FP16_MAX)), 1.0));
}

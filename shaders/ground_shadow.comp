#version 460
// The ground's shadow map (ground_shadow.glsl): per texel, each point light's visibility
// at its centre on the ground, whose triangles' normal is +y, with the texel in place of
// the pixel that turns the soft shadow's taps. Set 0 is the forward pass's (FrameData),
// set 3 its shadows' (src/render/ground_maps.rs).
#define GROUND_SHADOW_MAP_WRITER
#include "ground_shadow.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 1, binding = 0, rgba16f) uniform writeonly image2DArray ground_shadow_out;

void main() {
    uvec2 texel = gl_GlobalInvocationID.xy;
    uint size = uint(imageSize(ground_shadow_out).x);
    if (any(greaterThanEqual(texel, uvec2(size)))) return;
    vec3 p = ground_shadow_point(texel, size);
    for (uint layer = 0u; 4u * layer < frame.counts.x; ++layer) {
        vec4 visibility = vec4(1.0);
        for (uint c = 0u; c < 4u && 4u * layer + c < frame.counts.x; ++c) {
            // A hard light's shadow the ground looks up at its pixels (lights.glsl): its
            // channel is left lit, unread.
            uint i = 4u * layer + c;
            bool soft = shadow_data.lights[i].map.y > 0.0;
            visibility[c] = point_light_shadow(i, p, vec3(0.0, 1.0, 0.0), frame.camera_position.xyz - p, vec2(texel),
                                               soft);
        }
        imageStore(ground_shadow_out, ivec3(texel, layer), visibility);
    }
}

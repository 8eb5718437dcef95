#version 460
// The ground's light map (ground_light.glsl): per texel, the point lights' irradiance at
// its centre on the ground. Set 0 is the forward pass's (FrameData), set 3 its shadows'
// (src/render/ground_light.rs).
#include "ground_light.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 1, binding = 0, rgba16f) uniform writeonly image2D ground_light_out;

void main() {
    uvec2 texel = gl_GlobalInvocationID.xy;
    uint size = uint(imageSize(ground_light_out).x);
    if (any(greaterThanEqual(texel, uvec2(size)))) return;
    imageStore(ground_light_out, ivec2(texel), vec4(ground_lights_irradiance(ground_light_point(texel, size)), 1.0));
}

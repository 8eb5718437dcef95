#version 460
// The ground's occlusion map (ground_occlusion.glsl): per texel, what the objects' spheres
// make of the environment's diffuse light at its centre on the ground, whose normal is +y.
// Set 0 is the forward pass's (FrameData), set 2 the environment's
// (src/render/ground_maps.rs).
#include "ground_light.glsl"
#include "object_occlusion.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 1, binding = 0, rgba16f) uniform writeonly image2D ground_occlusion_out;

void main() {
    uvec2 texel = gl_GlobalInvocationID.xy;
    uint size = uint(imageSize(ground_occlusion_out).x);
    if (any(greaterThanEqual(texel, uvec2(size)))) return;
    // No sphere is the ground's own.
    vec3 factor = object_occlusion(ground_light_point(texel, size), vec3(0.0, 1.0, 0.0), uvec2(0u));
    imageStore(ground_occlusion_out, ivec2(texel), vec4(factor, 1.0));
}

#version 460
// The environment behind the objects: the radiance along each pixel's view ray, at full
// resolution (mip 0). Alpha is coverage, so 0.
#define ENV_SET 0
#include "environment.glsl"

layout(push_constant) uniform SkyboxPush {
    mat4 inverse_view_proj;
    vec4 camera_position;
} sky;

layout(location = 0) in vec2 in_ndc;
layout(location = 0) out vec4 out_radiance;

void main() {
    vec4 far = sky.inverse_view_proj * vec4(in_ndc, 1.0, 1.0);
    vec3 d = normalize(far.xyz / far.w - sky.camera_position.xyz);
    out_radiance = vec4(env_radiance(d, 0.0), 0.0);
}

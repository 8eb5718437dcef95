#version 460
// Display transform of the HDR frame: exposure, tone mapping, then sRGB encoding (by the
// hardware for *_SRGB targets, here otherwise).
#extension GL_EXT_samplerless_texture_functions : require
#include "tonemap.glsl"

layout(constant_id = 0) const bool ENCODE_SRGB = false;

layout(set = 0, binding = 0) uniform texture2D hdr_frame;
layout(push_constant) uniform Push {
    // Where the frame starts in the output (the viewer draws it beside its panel).
    ivec2 offset;
    float exposure;
    // Output pixels per HDR texel along each axis: the viewer's reduced resolution while
    // the UI is in use, 1 otherwise.
    int scale;
} push;

layout(location = 0) out vec4 out_color;

void main() {
    ivec2 texel = min((ivec2(gl_FragCoord.xy) - push.offset) / push.scale, textureSize(hdr_frame, 0) - 1);
    vec3 hdr = texelFetch(hdr_frame, texel, 0).rgb * push.exposure;
    vec3 display = tonemap_pbr_neutral(max(hdr, vec3(0.0)));
    out_color = vec4(ENCODE_SRGB ? srgb_oetf(display) : display, 1.0);
}

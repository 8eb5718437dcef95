#version 460
// Which solid each pixel shows, as the depth its shading draw is made at
// (src/render/deferred.rs): the G-buffer image's alpha that forward.frag's GBUFFER build
// wrote, 0 where no solid was drawn.
layout(set = 0, binding = 0) uniform sampler2D objects;

void main() {
    gl_FragDepth = texelFetch(objects, ivec2(gl_FragCoord.xy), 0).a;
}

#version 460
// The bench's floor: the forward pass's geometry, targets and vertex shader with no shading,
// so that a configuration's time divided by this one's is what its shading costs. Writes the
// interpolated normal (not normalised: the cheapest output that still reads an input).
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec4 out_radiance;

void main() {
    out_radiance = vec4(in_normal * 0.5 + 0.5, 1.0);
}

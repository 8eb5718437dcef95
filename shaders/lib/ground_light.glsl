// The point lights' irradiance on the ground that bounces their light ([shadows] bounce;
// bounce.glsl): each light's through its shadow map, E_lights(x). shaders/ground_light.comp
// computes it once per change of the lights, the ground or the shadow maps at the texel
// centres of a map over the ground's square (src/render/ground_light.rs), which the
// gather reads bilinearly where its taps meet the ground. The f64 twins are in
// src/brdf/bounce.rs.
#ifndef ARGIL_GROUND_LIGHT_GLSL
#define ARGIL_GROUND_LIGHT_GLSL
#include "scene_data.glsl"
#include "shading.glsl"
#include "shadows.glsl"

// The fraction of point light i reaching ground point x: one bilinear lookup of its map
// against the ground's own plane (the bounce's source needs no penumbra).
float ground_light_visibility(uint i, vec3 x) {
    ShadowLight s = shadow_data.lights[i];
    if (s.map.x < 0.0) return 1.0;
    vec3 q = x - frame.lights[i].position.xyz;
    vec3 m = abs(q);
    float q_major = max(max(m.x, m.y), m.z);
    if (q_major <= s.map.z || q_major >= s.map.w) return 1.0;
    float d = length(q);
    ShadowReceiver r = ShadowReceiver(int(s.map.x), s.map.z, s.map.w, vec3(0.0, 1.0, 0.0), q.y, d);
    return shadow_bilinear(r, q / d);
}

// E_lights(x): the point lights' irradiance at ground point x, each through its shadow map.
vec3 ground_lights_irradiance(vec3 x) {
    vec3 lights = vec3(0.0);
    for (uint i = 0u; i < frame.counts.x; ++i) {
        vec3 to_light = frame.lights[i].position.xyz - x;
        float e = plane_point_irradiance(to_light.y, max(dot(to_light, to_light), MIN_LIGHT_DISTANCE2));
        if (e > 0.0) lights += frame.lights[i].intensity.rgb * (e * ground_light_visibility(i, x));
    }
    return lights;
}

// The ground point at the centre of texel `texel` of a map `size` texels on a side over
// the ground's rectangle centre ± half_extent (x and z), which grow with the texel's column
// and row.
vec3 ground_texel_point(uvec2 texel, uint size, vec2 centre, vec2 half_extent) {
    vec2 st = (vec2(texel) + 0.5) / float(size) * 2.0 - 1.0;
    vec2 xz = centre + st * half_extent;
    return vec3(xz.x, frame.ground.y, xz.y);
}

// Where ground point x falls on such a map, the inverse of ground_texel_point: (0, 0) to
// (1, 1) over the rectangle.
vec2 ground_texel_uv(vec3 x, vec2 centre, vec2 half_extent) {
    return (x.xz - centre) / (2.0 * half_extent) + 0.5;
}

// ground_texel_point over the ground's square frame.ground.xz ± frame.ground.w.
vec3 ground_light_point(uvec2 texel, uint size) {
    return ground_texel_point(texel, size, frame.ground.xz, vec2(frame.ground.w));
}

// ground_texel_uv over the ground's square.
vec2 ground_light_uv(vec3 x) {
    return ground_texel_uv(x, frame.ground.xz, vec2(frame.ground.w));
}

#endif

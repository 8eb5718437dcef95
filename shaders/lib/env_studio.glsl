// The procedural studio environment (`kind = "studio"`): a grey cyclorama — darker floor,
// bright horizon, cooler ceiling — lit by three rectangular soft boxes: a warm key above
// left front, a cool fill strip on the right and a rim light behind. Large soft sources
// suit clay: broad highlights, gentle terminators. Linear RGB radiance; the f64 twin is
// studio_radiance in src/brdf/environment.rs.
#ifndef ARGIL_ENV_STUDIO_GLSL
#define ARGIL_ENV_STUDIO_GLSL

const vec3 STUDIO_FLOOR = vec3(0.09, 0.085, 0.08);
const vec3 STUDIO_HORIZON = vec3(0.34, 0.33, 0.32);
const vec3 STUDIO_CEILING = vec3(0.15, 0.16, 0.19);
// Elevations (sin) over which the horizon fades into the floor and into the ceiling.
const float STUDIO_FLOOR_FADE = 0.3;
const float STUDIO_CEILING_FADE = 0.6;

// How much of a soft box direction d sees: the box is a rectangle on the plane at unit
// distance along `centre` (not vertical), with half-extents `half_size` along the plane's
// horizontal and vertical axes and edges blurred over ±`softness` (plane units).
float soft_box(vec3 d, vec3 centre, vec2 half_size, float softness) {
    float q = dot(d, centre);
    if (q <= 0.0) return 0.0;
    vec3 t = normalize(cross(centre, vec3(0.0, 1.0, 0.0)));
    vec3 b = cross(t, centre);
    vec2 p = abs(vec2(dot(d, t), dot(d, b))) / q;
    vec2 inside = vec2(1.0) - smoothstep(half_size - softness, half_size + softness, p);
    return inside.x * inside.y;
}

vec3 studio_radiance(vec3 d) {
    vec3 background = d.y < 0.0
        ? mix(STUDIO_HORIZON, STUDIO_FLOOR, smoothstep(0.0, STUDIO_FLOOR_FADE, -d.y))
        : mix(STUDIO_HORIZON, STUDIO_CEILING, smoothstep(0.0, STUDIO_CEILING_FADE, d.y));
    return background
        + vec3(6.0, 5.75, 5.3) * soft_box(d, normalize(vec3(-0.55, 0.55, 0.63)), vec2(0.45, 0.3), 0.06)
        + vec3(1.5, 1.65, 1.9) * soft_box(d, normalize(vec3(0.85, 0.2, 0.35)), vec2(0.1, 0.55), 0.04)
        + vec3(4.0, 3.9, 3.7) * soft_box(d, normalize(vec3(0.25, 0.6, -0.75)), vec2(0.35, 0.2), 0.05);
}

#endif

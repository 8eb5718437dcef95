// Subsurface scattering of the diffuse lobe: the models' constants and the pre-integrated
// diffusion table (Penner & Borshukov 2011, "Pre-Integrated Skin Shading"), which
// src/brdf/subsurface.rs computes in f64 and twins.
#ifndef ARGIL_SUBSURFACE_GLSL
#define ARGIL_SUBSURFACE_GLSL
#include "brdf.glsl"

// `as u32` of Subsurface in src/brdf/subsurface.rs.
const uint SUBSURFACE_NONE = 0u;
const uint SUBSURFACE_SEED = 1u;
const uint SUBSURFACE_ENERGY_CONSERVING_WRAP = 2u;
const uint SUBSURFACE_PRE_INTEGRATED = 3u;

// Per texel: r = D(n·l, t), Penner's ring integral of a Gaussian profile, t = σκ; gba = the
// Funk–Hecke coefficients of D at the row's t. Columns n·l ∈ [−1, 1], rows t/(1 + t) ∈
// [0, 1]. Set 0, binding 2 in both the forward pass and the verify harness.
layout(set = 0, binding = 2) uniform sampler2D preintegrated_table;
const int PREINTEGRATED_WIDTH = 129;
const int PREINTEGRATED_HEIGHT = 65;
// Largest t looked up: t/(1 + t) is 1 long before it, and ∞/∞ would be NaN.
const float MAX_PREINTEGRATED_T = 1e30;

// The cell of texels around (n·l, t/(1 + t)): its texel below and left, and the fractions
// of the way to the next ones. The column is found from n·l·64 (exact) rather than
// (n·l + 1)·64, whose rounding would cost n·l its last digits right where D is small, at
// the terminator.
ivec2 preintegrated_cell(float n_dot_l, float t, out vec2 f) {
    const int half_width = (PREINTEGRATED_WIDTH - 1) / 2;
    float s = clamp(n_dot_l, -1.0, 1.0) * float(half_width);
    float column = min(floor(s), float(half_width - 1));
    float tc = clamp(t, 0.0, MAX_PREINTEGRATED_T);
    float y = tc / (1.0 + tc) * float(PREINTEGRATED_HEIGHT - 1);
    float row = min(floor(y), float(PREINTEGRATED_HEIGHT - 2));
    f = vec2(s - column, y - row);
    return ivec2(int(column) + half_width, int(row));
}

// D(n·l, t) bilinear between the cell's four texels (their r), with fp32 weights: not the
// sampler's filtering, which may keep only a few bits of them. One gather reads the four,
// at the corner they share (the clamp-to-edge sampler cannot move it to other texels):
// lavapipe runs every texel read as a call over the batch, and four fetches cost it
// 19% of the subsurface ball's shading.
float preintegrated_d(float n_dot_l, float t) {
    vec2 f;
    ivec2 i = preintegrated_cell(n_dot_l, t, f);
    vec2 corner = vec2(i + 1) / vec2(PREINTEGRATED_WIDTH, PREINTEGRATED_HEIGHT);
    // Gather order is (0, 1), (1, 1), (1, 0), (0, 0) from i.
    vec4 d = textureGather(preintegrated_table, corner, 0);
    float below = d.w + (d.z - d.w) * f.x;
    float above = d.x + (d.y - d.x) * f.x;
    return below + (above - below) * f.y;
}

// The Funk–Hecke coefficients (gba) of the row at t, between the cell's texels at n·l = 0:
// there the next column's weight is 0, and the finite texels make its share exactly 0, so
// only the cell's own column is read.
vec3 preintegrated_kernel(float t) {
    vec2 f;
    ivec2 i = preintegrated_cell(0.0, t, f);
    vec3 below = texelFetch(preintegrated_table, i, 0).gba;
    vec3 above = texelFetch(preintegrated_table, i + ivec2(0, 1), 0).gba;
    return below + (above - below) * f.y;
}

// The transfer K(n·l) per channel that replaces max(0, n·l) for the models that move
// diffuse light across the terminator; `reach` is w (energy-conserving wrap) or t = σκ
// (pre-integrated) per channel.
vec3 subsurface_transfer(uint model, float n_dot_l, vec3 reach) {
    if (model == SUBSURFACE_ENERGY_CONSERVING_WRAP) {
        return vec3(wrap_energy_conserving(n_dot_l, reach.r), wrap_energy_conserving(n_dot_l, reach.g),
                    wrap_energy_conserving(n_dot_l, reach.b));
    }
    if (model == SUBSURFACE_PRE_INTEGRATED) {
        return vec3(preintegrated_d(n_dot_l, reach.r), preintegrated_d(n_dot_l, reach.g),
                    preintegrated_d(n_dot_l, reach.b));
    }
    return vec3(0.0);
}

// Funk–Hecke coefficients of `wrap_energy_conserving` (seed eq. 18's replacement):
// (π, 2π(1/3 + w/2 − w³/6)/(1 + w)², π(1 − w)²/4), Lambert's at w = 0.
vec3 wrap_energy_conserving_sh_kernel(float w) {
    float wc = clamp(w, 0.0, 1.0);
    float square = (1.0 + wc) * (1.0 + wc);
    return vec3(PI, 2.0 * PI * (1.0 / 3.0 + wc * 0.5 - wc * wc * wc / 6.0) / square,
                PI * (1.0 - wc) * (1.0 - wc) * 0.25);
}

// The Funk–Hecke coefficients of one channel's transfer, for environment lighting.
vec3 subsurface_sh_kernel(uint model, float reach) {
    if (model == SUBSURFACE_ENERGY_CONSERVING_WRAP) return wrap_energy_conserving_sh_kernel(reach);
    return preintegrated_kernel(reach);
}

#endif

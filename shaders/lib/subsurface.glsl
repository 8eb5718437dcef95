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

// Bilinear between the four texels around (n·l, t/(1 + t)), with fp32 weights: texels are
// fetched because a sampler's filtering may keep only a few bits of the weights. The column
// is found from n·l·64 (exact) rather than (n·l + 1)·64, whose rounding would cost n·l its
// last digits right where D is small, at the terminator.
vec4 preintegrated_lookup(float n_dot_l, float t) {
    const int half_width = (PREINTEGRATED_WIDTH - 1) / 2;
    float s = clamp(n_dot_l, -1.0, 1.0) * float(half_width);
    float column = min(floor(s), float(half_width - 1));
    float tc = clamp(t, 0.0, MAX_PREINTEGRATED_T);
    float y = tc / (1.0 + tc) * float(PREINTEGRATED_HEIGHT - 1);
    float row = min(floor(y), float(PREINTEGRATED_HEIGHT - 2));
    ivec2 i = ivec2(int(column) + half_width, int(row));
    vec2 f = vec2(s - column, y - row);
    vec4 t00 = texelFetch(preintegrated_table, i, 0);
    vec4 t10 = texelFetch(preintegrated_table, i + ivec2(1, 0), 0);
    vec4 t01 = texelFetch(preintegrated_table, i + ivec2(0, 1), 0);
    vec4 t11 = texelFetch(preintegrated_table, i + ivec2(1, 1), 0);
    vec4 below = t00 + (t10 - t00) * f.x;
    vec4 above = t01 + (t11 - t01) * f.x;
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
        return vec3(preintegrated_lookup(n_dot_l, reach.r).r, preintegrated_lookup(n_dot_l, reach.g).r,
                    preintegrated_lookup(n_dot_l, reach.b).r);
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
    return preintegrated_lookup(0.0, reach).gba;
}

#endif

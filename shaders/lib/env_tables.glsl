// The BRDF tables' layers: which table a material's lobes read (environment.glsl) and
// which lobes a layer integrates (env_brdf_lut.comp). Twins in src/brdf/environment.rs.
#ifndef ARGIL_ENV_TABLES_GLSL
#define ARGIL_ENV_TABLES_GLSL
#include "shading.glsl"

// Layers 0–3: Cook-Torrance (distribution × 2 + geometry); 4: Torrance-Sparrow;
// 5: Blinn-Phong. RG = (A, B) with ∫ f_s cos = F0 A + B (Karis 2013); BA = (θ_A, θ_B), the
// angles from n towards the mirror direction of each part's mean direction ∫ l f_s cos.
const uint LUT_LAYER_TORRANCE_SPARROW = 4u;
const uint LUT_LAYER_BLINN_PHONG = 5u;
// R = the directional albedo of Oren-Nayar per unit albedo, against σ instead of roughness.
const uint LUT_LAYER_OREN_NAYAR = 6u;
const uint LUT_LAYERS = 7u;

// The tables' x is √(1 − n·v), not n·v: Oren-Nayar's albedo grows with sin θv, which has
// an infinite slope in n·v at normal incidence but is smooth in √(1 − n·v).
float lut_x(float n_dot_v) {
    return sqrt(max(1.0 - n_dot_v, 0.0));
}

// The n·v of table x, down to MIN_N_DOT_V at x = 1: the least n·v the shading uses (at 0
// itself the lobes are a degenerate limit).
float lut_n_dot_v(float x) {
    return max(1.0 - x * x, MIN_N_DOT_V);
}

// Texel i of a table of `size` holds parameter i/(size − 1), so both ends of [0, 1] are
// texels; parameter x is read at the texel-centre coordinate (x (size − 1) + ½)/size,
// where linear filtering reproduces the texels exactly at the ends.
float lut_parameter(uint texel, uint size) {
    return float(texel) / float(size - 1u);
}

float lut_coordinate(float x, uint size) {
    return (x * float(size - 1u) + 0.5) / float(size);
}

uint lut_layer(ShadingModels models) {
    if (models.specular == SPECULAR_COOK_TORRANCE) return models.distribution * 2u + models.geometry;
    if (models.specular == SPECULAR_TORRANCE_SPARROW) return LUT_LAYER_TORRANCE_SPARROW;
    return LUT_LAYER_BLINN_PHONG;
}

// The specular models of a specular layer (diffuse none).
ShadingModels lut_layer_models(uint layer) {
    if (layer < LUT_LAYER_TORRANCE_SPARROW)
        return ShadingModels(DIFFUSE_NONE, SPECULAR_COOK_TORRANCE, layer / 2u, layer % 2u, SUBSURFACE_NONE);
    uint specular = layer == LUT_LAYER_TORRANCE_SPARROW ? SPECULAR_TORRANCE_SPARROW : SPECULAR_BLINN_PHONG;
    return ShadingModels(DIFFUSE_NONE, specular, 0u, 0u, SUBSURFACE_NONE);
}

#endif

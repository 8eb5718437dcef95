// Environment lighting (set 2 of the forward pass; built by src/render/environment.rs):
// the material's own BRDF (shading.glsl) integrated against the environment's radiance,
// by the scene's reflection mode. For a uniform environment every lookup is the radiance
// itself, so Lambert reflects exactly ρL.
#ifndef ARGIL_ENVIRONMENT_GLSL
#define ARGIL_ENVIRONMENT_GLSL
#extension GL_EXT_control_flow_attributes : require
#include "env_math.glsl"
#include "specialization.glsl"
#include "env_tables.glsl"
#include "occlusion.glsl"

// The forward pass binds the environment as set 2; the skybox, which has no other set, as 0.
#ifndef ENV_SET
#define ENV_SET 2
#endif

// EnvironmentData.mode.x, and ENVIRONMENT_KIND
const uint ENV_NONE = 0u;
const uint ENV_UNIFORM = 1u;
const uint ENV_CUBE = 2u;
// EnvironmentData.mode.y, and REFLECTION_MODE
const uint REFLECTION_SPLIT_SUM = 0u;
const uint REFLECTION_SEED = 1u;
const uint REFLECTION_SAMPLED = 2u;

// Mirrored by EnvironmentData in src/render/environment.rs (std140).
layout(set = ENV_SET, binding = 0, std140) uniform EnvironmentData {
    uvec4 mode;     // x: kind, y: reflection mode, z: lookups per pixel (sampled)
    vec4 radiance;  // rgb: the uniform radiance, or the cube maps' intensity multiplier
    vec4 params;    // xy: (cos, sin) of the world-to-map rotation about +y; z: seed_strength;
                    // w: the prefiltered map's last mip, where roughness = 1
    vec4 texel;     // x: solid angle of a level-0 texel of radiance_map
    uvec4 grid;     // xy: columns and rows of luminance_cdf's distribution, 0 without one
    vec4 sun;       // the map's sun, lifted out of prefiltered_map: xyz its world direction,
                    // w its angular radius, 0 without one
    vec4 sun_irradiance; // rgb: its irradiance E⊥, before intensity
    vec4 sh[9];     // the map's radiance in SH (rgb), before rotation and intensity
} env;
// The forward pass specialises the kind and reflection mode; FROM_UNIFORM (the skybox, the
// generic pipeline) reads them from env.mode.
layout(constant_id = 9) const uint ENVIRONMENT_KIND = FROM_UNIFORM;
layout(constant_id = 10) const uint REFLECTION_MODE = FROM_UNIFORM;
// Whether the pipeline holds a map's sun (env.sun, split-sum reflection): set where the
// map has one (src/render/environment/sun.rs) and in the generic pipeline, which reads
// env.sun.w. Off, a sunless frame holds none of its lobe, which lavapipe would otherwise
// run behind the uniform for every pixel.
layout(constant_id = 16) const bool ENV_SUN = false;

uint env_kind() {
    return ENVIRONMENT_KIND == FROM_UNIFORM ? env.mode.x : ENVIRONMENT_KIND;
}

uint reflection_mode() {
    return REFLECTION_MODE == FROM_UNIFORM ? env.mode.y : REFLECTION_MODE;
}

// The environment with a mip chain of solid-angle-weighted means.
layout(set = ENV_SET, binding = 1) uniform samplerCube radiance_map;
// Radiance prefiltered by GGX lobes (Karis 2013), octahedral maps (octahedral_uv): layer k
// the prefiltered level k, α = 2^(k − params.w) above layer 0 (prefiltered_lod).
layout(set = ENV_SET, binding = 2) uniform sampler2DArray prefiltered_map;
// BRDF tables: x = lut_x(n·v), y = roughness (σ for Oren-Nayar), layer = lut_layer().
layout(set = ENV_SET, binding = 3) uniform sampler2DArray brdf_lut;
// Irradiance over π (f64 twin: irradiance_over_pi_cube in src/brdf/environment.rs).
layout(set = ENV_SET, binding = 4) uniform samplerCube irradiance_map;

// The cube map's luminance as a piecewise-constant density over its (u, v), when sampled
// reflection reads a cube map (f64 twin: LuminanceDistribution in
// src/brdf/luminance_distribution.rs): the running sums of the rows' weights (rows + 1,
// from 0), then each row's of its cells' (columns + 1 each).
layout(set = ENV_SET, binding = 5, std430) readonly buffer LuminanceCdf {
    float luminance_cdf[];
};

vec3 env_map_direction(vec3 d) {
    return rotate_y(d, env.params.xy);
}

// The cell i of the running sums luminance_cdf[first .. first + n] with cdf[i] ≤ x cdf[n] <
// cdf[i + 1], and where x falls inside it (pbrt-v4's PiecewiseConstant1D::Sample).
uint invert_luminance_cdf(uint first, uint n, float x, out float t) {
    float target = x * luminance_cdf[first + n];
    uint lo = 0u;
    uint hi = n;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (luminance_cdf[first + mid] <= target) lo = mid; else hi = mid;
    }
    float below = luminance_cdf[first + lo];
    float width = luminance_cdf[first + lo + 1u] - below;
    t = width > 0.0 ? clamp((target - below) / width, 0.0, 1.0) : 0.5;
    return lo;
}

// The density on [0, 1]² of a cell: its probability, from the differences sampling
// inverts, times the cells' count.
float luminance_cell_density(uvec2 cell) {
    uint columns = env.grid.x;
    uint rows = env.grid.y;
    uint row = rows + 1u + cell.y * (columns + 1u);
    float p_row = (luminance_cdf[cell.y + 1u] - luminance_cdf[cell.y]) / luminance_cdf[rows];
    float p_column = (luminance_cdf[row + cell.x + 1u] - luminance_cdf[row + cell.x]) / luminance_cdf[row + columns];
    return p_row * p_column * float(columns * rows);
}

// A world direction drawn in proportion to the cube map's luminance bound.
vec3 sample_env_luminance(vec2 u) {
    uint columns = env.grid.x;
    uint rows = env.grid.y;
    vec2 t;
    uint row = invert_luminance_cdf(0u, rows, u.y, t.y);
    uint column = invert_luminance_cdf(rows + 1u + row * (columns + 1u), columns, u.x, t.x);
    vec2 uv = (vec2(column, row) + t) / vec2(columns, rows);
    return rotate_y(equirect_direction(uv), vec2(env.params.x, -env.params.y));
}

// The pdf per steradian of sample_env_luminance drawing unit l: dω = 2π² sin θ du dv.
float pdf_env_luminance(vec3 l) {
    vec3 m = env_map_direction(l);
    float sin_theta = sqrt(max(1.0 - m.y * m.y, 0.0));
    if (sin_theta <= 0.0) return 0.0;
    vec2 uv = equirect_uv(m);
    uvec2 cell = min(uvec2(vec2(fract(uv.x), uv.y) * vec2(env.grid.xy)), env.grid.xy - 1u);
    return luminance_cell_density(cell) / (2.0 * PI * PI * sin_theta);
}

// Radiance arriving from direction d, read from mip `lod` of the cube map.
vec3 env_radiance(vec3 d, float lod) {
    if (env_kind() == ENV_UNIFORM) return env.radiance.rgb;
    return env.radiance.rgb * textureLod(radiance_map, env_map_direction(d), lod).rgb;
}

// Radiance around d prefiltered by GGX lobes, at level `lod` (prefiltered_lod): the two
// layers about it blended, as a trilinear lookup blends two mips.
vec3 env_prefiltered(vec3 d, float lod) {
    if (env_kind() == ENV_UNIFORM) return env.radiance.rgb;
    vec2 uv = octahedral_uv(env_map_direction(d), float(textureSize(prefiltered_map, 0).x));
    float below = floor(lod);
    vec3 lower = textureLod(prefiltered_map, vec3(uv, below), 0.0).rgb;
    vec3 upper = textureLod(prefiltered_map, vec3(uv, below + 1.0), 0.0).rgb;
    return env.radiance.rgb * mix(lower, upper, lod - below);
}

// ∫ L(l) k(d·l) dl for a zonal kernel k given by its Funk–Hecke coefficients: from the
// SH of the map (bands 0–2), exactly kernel.x L for a uniform L.
vec3 env_convolve(vec3 d, vec3 kernel) {
    if (env_kind() == ENV_UNIFORM) return kernel.x * env.radiance.rgb;
    return env.radiance.rgb * max(sh_convolve(env.sh, env_map_direction(d), kernel), vec3(0.0));
}

// Irradiance over π on a surface facing d, E(d)/π = (1/π) ∫ L(l) max(d·l, 0) dl: exactly
// L for a uniform L.
vec3 env_irradiance_over_pi(vec3 d) {
    if (env_kind() == ENV_UNIFORM) return env.radiance.rgb;
    return env.radiance.rgb * textureLod(irradiance_map, env_map_direction(d), 0.0).rgb;
}

vec4 brdf_table(uint layer, float n_dot_v, float y) {
    uvec2 size = uvec2(textureSize(brdf_lut, 0).xy);
    vec2 xy = vec2(lut_coordinate(lut_x(n_dot_v), size.x), lut_coordinate(y, size.y));
    return textureLod(brdf_lut, vec3(xy, float(layer)), 0.0);
}

// Whether the pipeline holds energy compensation: set for a material that asks and in the
// generic pipeline, which reads the material's flag; off, a material that does not ask
// reads no table, which lavapipe would otherwise do behind the flag for every pixel.
layout(constant_id = 17) const bool ENERGY_COMPENSATION = false;

// The material's specular tint with the lobe's multiple scattering compensated where the
// material asks for it (energy_compensation): E = A + B, the lobe's albedo at F0 = 1, is
// the split sum's own table (twin: SpecularAlbedoTable in src/brdf/energy.rs), so point
// lights and the environment, which both read the tint, are compensated alike.
vec3 compensated_specular_color(ShadingModels models, Material m, float n_dot_v) {
    if (!ENERGY_COMPENSATION || m.energy_compensation == 0.0 || models.specular == SPECULAR_NONE)
        return m.specular_color.rgb;
    vec4 lobe = brdf_table(lut_layer(models), n_dot_v, m.roughness);
    return m.specular_color.rgb * specular_energy_compensation(lobe.x + lobe.y, specular_f0(m));
}

// The directional albedo of the diffuse lobe: what it reflects of a unit uniform light.
vec3 diffuse_albedo(uint model, Material m, float n_dot_v) {
    if (model == DIFFUSE_LAMBERT) return diffuse_color(m);
    if (model == DIFFUSE_OREN_NAYAR)
        return diffuse_color(m) * brdf_table(LUT_LAYER_OREN_NAYAR, n_dot_v, m.diffuse_roughness).r;
    if (model == DIFFUSE_EON) return diffuse_eon_albedo(diffuse_color(m), m.diffuse_roughness, n_dot_v);
    return vec3(0.0);
}

// The split sum's diffuse and subsurface light, before occlusion; n_dot_v clamped.
vec3 split_sum_diffuse(ShadingModels models, Material m, vec3 n, float n_dot_v, float curvature) {
    vec3 radiance = diffuse_albedo(models.diffuse, m, n_dot_v) * env_irradiance_over_pi(n);
    if (subsurface_lights(models, m)) {
        if (models.subsurface == SUBSURFACE_SEED) {
            vec3 kernel = wrap_sh_kernel(m.wrap, m.wrap_width);
            radiance += m.wrap_color.rgb * (m.wrap_color.a / PI) * env_convolve(n, kernel);
        } else {
            // ρ/π (∫ L K − ∫ L max(0, n·l)), a kernel per channel.
            vec3 reach = subsurface_reach(models.subsurface, m, curvature);
            vec3 transferred = vec3(env_convolve(n, subsurface_sh_kernel(models.subsurface, reach.r)).r,
                                    env_convolve(n, subsurface_sh_kernel(models.subsurface, reach.g)).g,
                                    env_convolve(n, subsurface_sh_kernel(models.subsurface, reach.b)).b);
            radiance += diffuse_color(m) * (transferred / PI - env_convolve(n, SH_IRRADIANCE_OVER_PI));
        }
    }
    return radiance;
}

// The split sum's specular light, before occlusion, of a material with a specular lobe;
// n_dot_v clamped, alpha the widened lobe's.
vec3 split_sum_specular(ShadingModels models, Material m, float microsurface_roughness, vec3 n, vec3 v,
                        float n_dot_v, float alpha) {
    vec4 lobe = brdf_table(lut_layer(models), n_dot_v, microsurface_roughness);
    vec3 f0_a = clamp(specular_f0(m), 0.0, 1.0) * lobe.x;
    vec3 prefiltered = env.radiance.rgb;
    vec3 sunlight = vec3(0.0);
    if (env_kind() != ENV_UNIFORM) {
        // One direction for the three channels: their mean F0 weighs the parts.
        float theta = lobe_mean_angle(dot(f0_a, vec3(1.0 / 3.0)), lobe.y, lobe.z, lobe.w);
        vec3 mean = lobe_direction(n, v, theta);
        // Along the plane of incidence, across the mean direction; none seen head-on.
        vec3 across_plane = cross(n, v);
        float sin_v = length(across_plane);
        vec3 along = sin_v > 1e-4 ? cross(across_plane / sin_v, mean) : vec3(0.0);
        vec3 taps = prefiltered_taps(n_dot_v);
        float lod = prefiltered_lod(alpha * taps.y, env.params.w);
        prefiltered = vec3(0.0);
        // The count varies by pixel. Unrolled, lavapipe would run all eight lookups for
        // every pixel; as a loop it stops once no pixel of its batch has one left.
        [[dont_unroll]]
        for (float i = 0.0; i < taps.x; ++i) {
            float offset = alpha * taps.z * (i - 0.5 * (taps.x - 1.0));
            prefiltered += env_prefiltered(normalize(mean + offset * along), lod);
        }
        prefiltered /= taps.x;
#if SUN_LOBE
        // A map's sun lights as one direction (sun_alpha widens the lobe by its disc).
        float n_dot_sun = dot(n, env.sun.xyz);
        if (ENV_SUN && env.sun.w > 0.0 && n_dot_sun > 0.0) {
            Material sunlit = m;
            sunlit.roughness = sqrt(sun_alpha(alpha, env.sun.w));
            sunlight = env.radiance.rgb * env.sun_irradiance.rgb * n_dot_sun
                     * specular_lobe(models, sunlit, n, v, env.sun.xyz, n_dot_v, n_dot_sun);
        }
#endif
    }
    return prefiltered * m.specular_color.rgb * (f0_a + lobe.y) + sunlight;
}

// Split sum (Karis 2013, "Real Shading in Unreal Engine 4"): the diffuse lobe's albedo
// times irradiance/π (exact for Lambert), the subsurface term through its own SH kernels
// (less the SH irradiance, so that both sides of the difference are band-limited alike),
// and the specular lobe as prefiltered radiance around its mean direction (lookups along
// the plane of incidence, prefiltered_taps) times ∫ f_s cos = F0 A + B, plus a map's sun,
// which the prefiltered cube leaves out, through the lobe itself. In seed mode the
// specular lobe is replaced by the report's eq. 17: one lookup along the mirror direction
// × seed_strength × noise. `noise` modulates the seed mode's lookup: the material's noise
// map, or 1. `occlusion` (occlusion_map.glsl, times object_occlusion.glsl's factor in rgb;
// all 1: none) scales the diffuse and subsurface terms by its rgb, and the specular one by
// the specular occlusion of its visibility a (none at a = 1). `microsurface_roughness` is
// the material's roughness before specular anti-aliasing widened m.roughness: the
// prefiltered lookups read the widened lobe, which filters the light over the pixel's
// normals, but the lobe's albedo (the table's F0 A + B) and its mean direction are the
// microsurface's, which the pixel's many normals neither shadow nor tilt more.
vec3 environment_split_sum(ShadingModels models, Material m, float microsurface_roughness, vec3 n, vec3 v,
                           float curvature, float noise, vec4 occlusion) {
    float n_dot_v = max(dot(n, v), MIN_N_DOT_V);
    vec3 radiance = split_sum_diffuse(models, m, n, n_dot_v, curvature);
    float alpha = clamp_alpha(m.roughness * m.roughness);
    float specular_visibility = 1.0;
    radiance *= occlusion.rgb;
    if (occlusion.a < 1.0) specular_visibility = specular_occlusion(n_dot_v, occlusion.a, alpha);
    if (models.specular == SPECULAR_NONE) return radiance;
    if (reflection_mode() == REFLECTION_SEED) {
        return radiance + specular_visibility * env.params.z * noise * env_radiance(seed_reflection(n, v), 0.0);
    }
    return radiance + specular_visibility * split_sum_specular(models, m, microsurface_roughness, n, v, n_dot_v, alpha);
}

#if SAMPLED_REFLECTION
// PCG hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering").
uint pcg_hash(uint x) {
    uint state = x * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// A pixel's offset in [0, 1)² that rotates its sample sets (Cranley–Patterson), so the
// error of neighbouring pixels is noise rather than a shared pattern.
vec2 pixel_offset(vec2 pixel) {
    uvec2 p = uvec2(pixel);
    uint h = pcg_hash(p.x + pcg_hash(p.y));
    return vec2(float(h), float(pcg_hash(h))) * RADICAL_INVERSE_SCALE;
}

// env.mode.z lookups of L(l) brdf_cos(l): cosine samples for the diffuse lobe, GGX
// visible normals for the specular lobe, uniform ones for the wrap term, and a cube map's
// luminance (when its distribution is built, with sampled reflection), combined by the
// multi-sample balance heuristic (Veach 1997, §9.2.2): Σ f(l) L(l) / Σ_k N_k p_k(l). Every
// lookup reads level 0. Filtered importance sampling (a mip per sample's pdf) blurred a
// sun over a lobe's footprint; beside luminance samples, whose small footprints do not
// spread it, that blur counts its light twice: sampled N = 64 read ꟻLIP 0.36 on the bench's
// `sphere-sky` with it, 0.033 without, where the filtered lobe samples alone read 0.16.
// `sample_set` k (0 for a single frame) rotates every set by point k of R2, so the frames
// a still view accumulates (src/render/accumulate.rs) use different, evenly spread samples
// and the running mean converges to the integral.
vec3 environment_sampled(ShadingModels models, Material m, vec3 n, vec3 n_geometric, vec3 v, float curvature,
                         vec2 pixel, uint sample_set) {
    bool by_luminance = env_kind() == ENV_CUBE && env.grid.x > 0u;
    uvec4 counts = strategy_counts(env.mode.z, models.diffuse != DIFFUSE_NONE,
                                   models.specular != SPECULAR_NONE, subsurface_lights(models, m), by_luminance);
    mat3 frame = tangent_frame(n);
    vec3 v_local = v * frame;
    float n_dot_v = max(v_local.z, MIN_N_DOT_V);
    float alpha = clamp_alpha(m.roughness * m.roughness);
    vec2 offset = fract(pixel_offset(pixel) + r2(sample_set));
    uint lobes = counts.x + counts.y;
    uint total = lobes + counts.z + counts.w;
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < total; ++i) {
        vec3 l;
        if (i < counts.x) {
            l = frame * sample_cosine(fract(hammersley(i, counts.x) + offset));
        } else if (i < lobes) {
            vec3 h = sample_ggx_vndf(v_local, alpha, fract(hammersley(i - counts.x, counts.y) + offset));
            l = frame * reflect(-v_local, h);
        } else if (i < lobes + counts.z) {
            l = sample_uniform_sphere(fract(hammersley(i - lobes, counts.z) + offset));
        } else {
            l = sample_env_luminance(fract(hammersley(i - lobes - counts.z, counts.w) + offset));
        }
        vec3 h = safe_half_vector(v, l, n);
        vec3 n_cross_h = cross(n, h);
        float n_pdf = float(counts.x) * pdf_cosine(dot(n, l))
                    + float(counts.y) * pdf_ggx_vndf(alpha, n_dot_v, max(dot(n, h), 0.0), dot(n_cross_h, n_cross_h))
                    + float(counts.z) * PDF_UNIFORM_SPHERE
                    + (counts.w > 0u ? float(counts.w) * pdf_env_luminance(l) : 0.0);
        if (n_pdf <= 0.0) continue;
        vec3 f = brdf_cos(models, m, n, n_geometric, v, l, curvature);
        sum += f * env_radiance(l, 0.0) / n_pdf;
    }
    return sum;
}
#endif

// The light the environment reflects towards v: replaces the report's constant ambient.
// `occlusion` is applied as environment_split_sum applies it; the sampled mode then
// estimates the diffuse (with subsurface) and specular lobes apart, to scale each, with
// the widened lobe alone (it estimates the whole BRDF, not a lookup times an albedo).
vec3 environment_light(ShadingModels models, Material m, float microsurface_roughness, vec3 n, vec3 n_geometric,
                       vec3 v, float curvature, float noise, vec2 pixel, uint sample_set, vec4 occlusion) {
    if (env_kind() == ENV_NONE) return vec3(0.0);
    if (!bool(SAMPLED_REFLECTION) || reflection_mode() != REFLECTION_SAMPLED) {
        return environment_split_sum(models, m, microsurface_roughness, n, v, curvature, noise, occlusion);
    }
#if SAMPLED_REFLECTION
    if (occlusion == vec4(1.0)) return environment_sampled(models, m, n, n_geometric, v, curvature, pixel, sample_set);
    ShadingModels diffuse_only = models;
    diffuse_only.specular = SPECULAR_NONE;
    ShadingModels specular_only = models;
    specular_only.diffuse = DIFFUSE_NONE;
    specular_only.subsurface = SUBSURFACE_NONE;
    float n_dot_v = max(dot(n, v), MIN_N_DOT_V);
    float alpha = clamp_alpha(m.roughness * m.roughness);
    return occlusion.rgb * environment_sampled(diffuse_only, m, n, n_geometric, v, curvature, pixel, sample_set)
         + specular_occlusion(n_dot_v, occlusion.a, alpha)
             * environment_sampled(specular_only, m, n, n_geometric, v, curvature, pixel, sample_set);
#endif
}

#endif

// BRDF models of the clay material (GLSL 4.60).
//
// #include from a shader that declares #version 460 and GL_GOOGLE_include_directive: the
// forward fragment shader, or a compute harness that feeds the scalar arguments directly.
// Every function returns a BRDF value f without the cosine (multiply by n·l), is finite and
// non-negative for any finite input, and has an f64 twin of the same name in src/brdf/.
// Dot products are passed as scalars; n_cross_h_len2 is |n×h|² = dot(cross(n, h), cross(n, h)).
// Microfacet roughness α = perceptual roughness²; every function clamps it to
// [MIN_ALPHA, MAX_ALPHA]. The forward shader passes `distribution` and `geometry` from
// specialization constants, so the branches on them fold away.

#ifndef ARGIL_BRDF_GLSL
#define ARGIL_BRDF_GLSL

const float PI = 3.14159265358979;

// Smallest α. Measured: fp32 d_ggx through |n×h|² stays within 3.4e-7 of f64 down to
// α = 1e-9, so precision does not bound α; the fp16 target does: the normal-incidence
// Cook-Torrance peak 1/(4πα²) reaches FP16_MAX at α = 1.10e-3, 0.002025 (0.045², Filament's)
// keeps it at 1.94e4, 3.4x below.
const float MIN_ALPHA = 0.002025;
// Largest α: roughness = √α ≤ 1, and Blinn-Phong's exponent 2/α² − 2 is negative above it.
const float MAX_ALPHA = 1.0;
// Cosines are clamped up to this where they divide (Smith Λ, 1/(4 n·v n·l), tan θ): a
// normal-mapped n·v ≤ 0 still shades, and 1/cos stays ≤ 1e4 (Filament's value).
const float MIN_N_DOT_V = 1e-4;
// Largest finite fp16: D·G/(4 n·v n·l) is clamped to it, so with F ≤ 1 a specular lobe
// never puts Inf in an RGBA16F target.
const float FP16_MAX = 65504.0;
// |v+l|² below which v+l is fp32 rounding noise (direction error > 0.6%): h falls back to n.
const float MIN_HALF_LEN2 = 1e-10;
// Smallest normal fp32: log() of a denormal flushed to 0 is −Inf, and 0·(−Inf) is NaN.
const float FLT_MIN_NORMAL = 1.17549435e-38;
// log_near_one's series holds from here to 1; below, log() errs little relative to the result.
const float LOG_SERIES_MIN = 0.7;
// log_n_dot_h sums ½ ln(1 − |n×h|²) by series below this |n×h|² (n·h > 0.866 for unit n, h).
const float SIN2_SERIES_MAX = 0.25;
// exp(−x) is treated as 0 beyond this: Beckmann D is then below 1e-31 of its peak.
const float BECKMANN_MAX_EXPONENT = 80.0;
// Walter et al. 2007's Beckmann fit sets G1 = 1 from a = 1/(α tan θ) ≥ 1.6.
const float BECKMANN_FIT_MAX_A = 1.6;
// |v_t|²|l_t|² below which φ is undefined (one direction along n, where sin a tan b is 0).
const float MIN_TANGENT_LEN2 = 1e-12;
// EON's 1/2 − 2/(3π) (Portsmouth, Kutz & Hill 2025): FON's A = 1/(1 + c₁ r).
const float EON_CONSTANT_1 = 0.5 - 2.0 / (3.0 * PI);
// EON's 2/3 − 28/(15π): FON's average albedo is A (1 + c₂ r).
const float EON_CONSTANT_2 = 2.0 / 3.0 - 28.0 / (15.0 * PI);
// EON's ε: keeps 1 − E > 0 where E_FON = 1 (r = 0), where the multiple-scattering lobe vanishes.
const float EON_EPSILON = 1e-7;
// Smallest wrap width w₂: keeps eq. 18's smoothstep edges apart.
const float MIN_WRAP_WIDTH = 1e-4;
// Smallest single-scattering albedo E specular_energy_compensation divides by: the BRDF
// tables' least specular E is above it; it bounds the factor by 1/E = 20.
const float MIN_SPECULAR_ALBEDO = 0.05;

// Values of spec_cook_torrance's `distribution` and `geometry`.
const int DISTRIBUTION_GGX = 0;
const int DISTRIBUTION_BECKMANN = 1;
const int GEOMETRY_SMITH_CORRELATED = 0;
const int GEOMETRY_SMITH_SEPARABLE = 1;

// Clamps a microfacet roughness to [MIN_ALPHA, MAX_ALPHA].
float clamp_alpha(float alpha) {
    return clamp(alpha, MIN_ALPHA, MAX_ALPHA);
}

// Normalised v + l (seed eq. 5), or n when v ≈ −l leaves no meaningful half vector.
vec3 safe_half_vector(vec3 v, vec3 l, vec3 n) {
    vec3 h = v + l;
    float len2 = dot(h, h);
    return len2 < MIN_HALF_LEN2 ? n : h * inversesqrt(len2);
}

// ---- Distributions: ∫ D (n·h) dω = 1 ----

// GGX / Trowbridge-Reitz, seed eq. 7 rewritten as α²/(π((n·h)²α² + |n×h|²)²) so the
// highlight keeps its precision (1 − (n·h)² cancels near n·h = 1).
float d_ggx(float alpha, float n_dot_h, float n_cross_h_len2) {
    if (n_dot_h <= 0.0) {
        return 0.0;
    }
    float a = clamp_alpha(alpha);
    float a2 = a * a;
    float c = min(n_dot_h, 1.0);
    // For unit n, h the denominator is ≥ α²; the max only tames inconsistent inputs.
    float d = max(c * c * a2 + max(n_cross_h_len2, 0.0), a2);
    float k = a / d;
    return k * k / PI;
}

// Beckmann, seed eq. 6 corrected to tan²θh = |n×h|²/(n·h)²:
// exp(−tan²θh/α²)/(πα² cos⁴θh), with 1/cos⁴θh = (1 + tan²θh)².
float d_beckmann(float alpha, float n_dot_h, float n_cross_h_len2) {
    float a = clamp_alpha(alpha);
    float a2 = a * a;
    float c = clamp(n_dot_h, 0.0, 1.0);
    float c2 = c * c;
    float s2 = max(n_cross_h_len2, 0.0);
    // Also catches n·h ≤ 0 (c2 = 0) without dividing.
    if (s2 >= BECKMANN_MAX_EXPONENT * a2 * c2) {
        return 0.0;
    }
    float tan2 = s2 / c2;
    float sec2 = 1.0 + tan2;
    return exp(-tan2 / a2) * sec2 * sec2 / (PI * a2);
}

// ---- Masking-shadowing ----

// Smith Λ of GGX (Heitz 2014): (√(1 + α² tan²θ) − 1)/2, written x/(2(1 + √(1+x))) so it
// does not cancel for small α tan θ. Below-horizon cosines are masked by G, not here.
float lambda_ggx(float alpha, float n_dot_x) {
    float a = clamp_alpha(alpha);
    float mu = clamp(n_dot_x, MIN_N_DOT_V, 1.0);
    float mu2 = mu * mu;
    float x = a * a * (1.0 - mu2) / mu2;
    return x / (2.0 * (1.0 + sqrt(1.0 + x)));
}

// Smith Λ of Beckmann by Walter et al. 2007's rational fit of G1, a = 1/(α tan θ) (GLSL
// has no erf). The fit exceeds G1 = 1 by 6e-5 just below a = 1.6, so Λ is clamped at 0.
float lambda_beckmann(float alpha, float n_dot_x) {
    float al = clamp_alpha(alpha);
    float mu = clamp(n_dot_x, MIN_N_DOT_V, 1.0);
    float s = sqrt(1.0 - mu * mu);
    if (mu >= BECKMANN_FIT_MAX_A * al * s) {
        return 0.0;
    }
    float a = mu / (al * s);
    return max((1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a), 0.0);
}

// Smith G1 of GGX, seed eq. 8: 2(n·x)/(n·x + √(α² + (1 − α²)(n·x)²)); 0 below the horizon.
float g1_smith_ggx(float alpha, float n_dot_x) {
    float a = clamp_alpha(alpha);
    float a2 = a * a;
    float mu = clamp(n_dot_x, 0.0, 1.0);
    return 2.0 * mu / (mu + sqrt(a2 + (1.0 - a2) * mu * mu));
}

// Separable Smith G2 = G1(v) G1(l) (seed's G, eq. 8), GGX.
float g2_smith_separable_ggx(float alpha, float n_dot_v, float n_dot_l) {
    return g1_smith_ggx(alpha, n_dot_v) * g1_smith_ggx(alpha, n_dot_l);
}

// Height-correlated Smith G2 = 1/(1 + Λ(v) + Λ(l)) (Heitz 2014), GGX.
float g2_smith_correlated_ggx(float alpha, float n_dot_v, float n_dot_l) {
    if (n_dot_v <= 0.0 || n_dot_l <= 0.0) {
        return 0.0;
    }
    return 1.0 / (1.0 + lambda_ggx(alpha, n_dot_v) + lambda_ggx(alpha, n_dot_l));
}

// Separable Smith G2 = 1/((1 + Λ(v))(1 + Λ(l))) (Heitz 2014), Beckmann (Walter fit).
float g2_smith_separable_beckmann(float alpha, float n_dot_v, float n_dot_l) {
    if (n_dot_v <= 0.0 || n_dot_l <= 0.0) {
        return 0.0;
    }
    return 1.0 / ((1.0 + lambda_beckmann(alpha, n_dot_v)) * (1.0 + lambda_beckmann(alpha, n_dot_l)));
}

// Height-correlated Smith G2 = 1/(1 + Λ(v) + Λ(l)) (Heitz 2014), Beckmann (Walter fit).
float g2_smith_correlated_beckmann(float alpha, float n_dot_v, float n_dot_l) {
    if (n_dot_v <= 0.0 || n_dot_l <= 0.0) {
        return 0.0;
    }
    return 1.0 / (1.0 + lambda_beckmann(alpha, n_dot_v) + lambda_beckmann(alpha, n_dot_l));
}

// V-cavity G of Torrance & Sparrow 1967 / Cook & Torrance 1982:
// min(1, 2(n·h)(n·v)/(v·h), 2(n·h)(n·l)/(v·h)), written without dividing by a tiny v·h.
float g2_v_cavity(float n_dot_h, float n_dot_v, float n_dot_l, float v_dot_h) {
    float g = 2.0 * clamp(n_dot_h, 0.0, 1.0) * clamp(min(n_dot_v, n_dot_l), 0.0, 1.0);
    float vh = clamp(v_dot_h, 0.0, 1.0);
    return vh > g ? g / vh : 1.0;
}

// ---- Fresnel ----

// Schlick 1994, seed eq. 9: F0 + (1 − F0)(1 − v·h)⁵, with F0 and v·h clamped to [0, 1].
float f_schlick_scalar(float f0, float v_dot_h) {
    float x = 1.0 - clamp(v_dot_h, 0.0, 1.0);
    float x2 = x * x;
    float f = clamp(f0, 0.0, 1.0);
    return f + (1.0 - f) * (x2 * x2 * x);
}

// Schlick 1994, seed eq. 9, per channel.
vec3 f_schlick(vec3 f0, float v_dot_h) {
    float x = 1.0 - clamp(v_dot_h, 0.0, 1.0);
    float x2 = x * x;
    vec3 f = clamp(f0, 0.0, 1.0);
    return f + (1.0 - f) * (x2 * x2 * x);
}

// ---- Specular lobes ----

// Cook & Torrance 1982, seed eq. 11 without F: D·G/(4 n·v n·l), G the Smith G2 matching D,
// clamped to FP16_MAX; for callers that apply Fresnel themselves (F ≤ 1 keeps the cap).
float spec_cook_torrance_df(float alpha, float n_dot_v, float n_dot_l, float n_dot_h,
                            float n_cross_h_len2, int distribution, int geometry) {
    float nv = clamp(n_dot_v, MIN_N_DOT_V, 1.0);
    float nl = clamp(n_dot_l, MIN_N_DOT_V, 1.0);
    float d_g;
    if (distribution == DISTRIBUTION_BECKMANN) {
        d_g = d_beckmann(alpha, n_dot_h, n_cross_h_len2)
            * (geometry == GEOMETRY_SMITH_SEPARABLE ? g2_smith_separable_beckmann(alpha, nv, nl)
                                                    : g2_smith_correlated_beckmann(alpha, nv, nl));
    } else {
        d_g = d_ggx(alpha, n_dot_h, n_cross_h_len2)
            * (geometry == GEOMETRY_SMITH_SEPARABLE ? g2_smith_separable_ggx(alpha, nv, nl)
                                                    : g2_smith_correlated_ggx(alpha, nv, nl));
    }
    return min(d_g / (4.0 * nv * nl), FP16_MAX);
}

// Cook & Torrance 1982, seed eq. 11: D·G·F/(4 n·v n·l), G the Smith G2 matching D;
// F times spec_cook_torrance_df.
vec3 spec_cook_torrance(float alpha, float n_dot_v, float n_dot_l, float n_dot_h,
                        float n_cross_h_len2, vec3 f0, float v_dot_h, int distribution,
                        int geometry) {
    return f_schlick(f0, v_dot_h)
         * spec_cook_torrance_df(alpha, n_dot_v, n_dot_l, n_dot_h, n_cross_h_len2, distribution, geometry);
}

// Torrance & Sparrow 1967 (seed eq. 10 corrected): Beckmann D, V-cavity G, F over
// 4 n·v n·l, because eq. 10's 4π(n·ωr) does not integrate D's projected area to 1.
// D·G/(4 n·v n·l) is clamped to FP16_MAX before F.
vec3 spec_torrance_sparrow(float alpha, float n_dot_v, float n_dot_l, float n_dot_h,
                           float n_cross_h_len2, vec3 f0, float v_dot_h) {
    float nv = clamp(n_dot_v, MIN_N_DOT_V, 1.0);
    float nl = clamp(n_dot_l, MIN_N_DOT_V, 1.0);
    float d_g = d_beckmann(alpha, n_dot_h, n_cross_h_len2) * g2_v_cavity(n_dot_h, nv, nl, v_dot_h);
    return f_schlick(f0, v_dot_h) * min(d_g / (4.0 * nv * nl), FP16_MAX);
}

// 2 atanh(u) = ln((1 + u)/(1 − u)), by its series to u⁹.
float two_atanh(float u) {
    float u2 = u * u;
    return 2.0 * u * (1.0 + u2 * (1.0 / 3.0 + u2 * (1.0 / 5.0 + u2 * (1.0 / 7.0 + u2 / 9.0))));
}

// ln x for x clamped to [FLT_MIN_NORMAL, 1], relatively precise near 1. log2 on GPUs (and
// lavapipe) errs by about 2⁻²² absolutely near 1, and (n·h)ⁿ = exp(n ln(n·h)) multiplies that
// by n ≤ 4.9e5: pow() was 9% off at MIN_ALPHA. From LOG_SERIES_MIN up, ln x = 2 atanh(u),
// u = (x − 1)/(x + 1) with x − 1 exact in fp32, by its series to u⁹ (|u| ≤ 0.18: truncation
// 3e-9 relative).
float log_near_one(float x) {
    float c = clamp(x, FLT_MIN_NORMAL, 1.0);
    if (c < LOG_SERIES_MIN) {
        return log(c);
    }
    return two_atanh((c - 1.0) / (c + 1.0));
}

// ln(n·h) = ½ ln(1 − s²), s² = |n×h|², for (n·h)ⁿ: fp32 n·h is rounded to 2⁻²⁴ near 1 before
// any log, an error (n·h)ⁿ multiplies by n ≤ 4.9e5, while s² is relatively precise. Below
// SIN2_SERIES_MAX, ln(1 − s²) = 2 atanh(u), u = −s²/(2 − s²), by its series to u⁹: five
// terms, |u| ≤ 1/7, truncation < u¹⁰/(11(1 − u²)) < 4e-10 relative. From there (also s² ≥ 1
// of non-unit inputs), log_near_one(n·h). Both are ln n·h for unit n, h: the switch is
// continuous to rounding.
float log_n_dot_h(float n_dot_h, float n_cross_h_len2) {
    float s2 = max(n_cross_h_len2, 0.0);
    if (s2 < SIN2_SERIES_MAX) {
        return 0.5 * two_atanh(-s2 / (2.0 - s2));
    }
    return log_near_one(n_dot_h);
}

// Blinn 1977 (seed eq. 5) normalised: (n+8)/(8π) (n·h)ⁿ F(v·h), n = 2/α² − 2, (n·h)ⁿ via |n×h|².
// Peaks at 1.94e4 for MIN_ALPHA, so it needs no cap.
vec3 spec_blinn_phong(float alpha, float n_dot_h, float n_cross_h_len2, vec3 f0, float v_dot_h) {
    if (n_dot_h <= 0.0) {
        return vec3(0.0);
    }
    float a = clamp_alpha(alpha);
    float n = 2.0 / (a * a) - 2.0;
    float lobe = (n + 8.0) / (8.0 * PI) * exp(n * log_n_dot_h(n_dot_h, n_cross_h_len2));
    return f_schlick(f0, v_dot_h) * lobe;
}

// ---- Diffuse lobes: Lambert and Oren-Nayar per unit albedo, EON takes the albedo ρ ----

// Lambert, seed eq. 4: 1/π per unit albedo.
float diffuse_lambert() {
    return 1.0 / PI;
}

// Qualitative Oren-Nayar, seed eq. 12 with a = max(θi, θr), b = min(θi, θr) as angles:
// (A + B max(0, cos(φi − φr)) sin a tan b)/π per unit albedo, σ in radians. sin a and tan b
// come from the tangent-plane projections (|v_t| = sin θr) rather than acos/tan, which lose
// precision near the normal in fp32.
float diffuse_oren_nayar(float sigma, vec3 n, vec3 v, vec3 l) {
    float s2 = sigma * sigma;
    float a_coef = 1.0 - 0.5 * s2 / (s2 + 0.33);
    float b_coef = 0.45 * s2 / (s2 + 0.09);
    float n_dot_v = dot(n, v);
    float n_dot_l = dot(n, l);
    vec3 v_t = v - n * n_dot_v;
    vec3 l_t = l - n * n_dot_l;
    float v_t2 = dot(v_t, v_t);
    float l_t2 = dot(l_t, l_t);
    float len2 = v_t2 * l_t2;
    float cos_phi = len2 > MIN_TANGENT_LEN2 ? clamp(dot(v_t, l_t) * inversesqrt(len2), 0.0, 1.0) : 0.0;
    float sin_r = min(sqrt(v_t2), 1.0);
    float sin_i = min(sqrt(l_t2), 1.0);
    float cos_r = clamp(n_dot_v, MIN_N_DOT_V, 1.0);
    float cos_i = clamp(n_dot_l, MIN_N_DOT_V, 1.0);
    // The larger angle has the larger sine, the smaller angle the larger cosine.
    float sin_a = max(sin_r, sin_i);
    float tan_b = min(sin_r, sin_i) / max(cos_r, cos_i);
    return (a_coef + b_coef * cos_phi * sin_a * tan_b) / PI;
}

// EON's polynomial fit of the FON directional albedo E_FON(μ) (Portsmouth et al. 2025).
float e_fon_approx(float mu, float r) {
    float m = 1.0 - clamp(mu, 0.0, 1.0);
    float rr = clamp(r, 0.0, 1.0);
    float g_over_pi = m * (0.0571085289 + m * (0.491881867 + m * (-0.332181442 + m * 0.0714429953)));
    return (1.0 + rr * g_over_pi) / (1.0 + EON_CONSTANT_1 * rr);
}

// EON's average FON albedo Ē = A (1 + c₂ r), r in [0, 1].
float eon_average_albedo(float r) {
    float rr = clamp(r, 0.0, 1.0);
    float a = 1.0 / (1.0 + EON_CONSTANT_1 * rr);
    return a * (1.0 + EON_CONSTANT_2 * rr);
}

// EON's multiple-scattering albedo ρ_ms = ρ² Ē/(1 − ρ(1 − Ē)), ρ clamped to [0, 1].
vec3 eon_multiple_albedo(vec3 rho, float e_avg) {
    vec3 c = clamp(rho, 0.0, 1.0);
    return c * c * e_avg / (1.0 - c * (1.0 - e_avg));
}

// Energy-preserving Oren-Nayar (EON, Portsmouth, Kutz & Hill 2025, as in OpenPBR), with the
// E_FON fit: FON single scattering ρ/π A (1 + r s/t) plus the multiple-scattering lobe
// ρ_ms/π (1 − E(μo))(1 − E(μi))/(1 − Ē). r is the roughness in [0, 1].
vec3 diffuse_eon(vec3 rho, float r, float n_dot_v, float n_dot_l, float v_dot_l) {
    float rr = clamp(r, 0.0, 1.0);
    float mu_o = clamp(n_dot_v, MIN_N_DOT_V, 1.0);
    float mu_i = clamp(n_dot_l, MIN_N_DOT_V, 1.0);
    // FON's s = cos φ sin θi sin θo and t = max(μi, μo) where s > 0.
    float s = v_dot_l - mu_i * mu_o;
    float s_over_t = s > 0.0 ? s / max(mu_i, mu_o) : s;
    float a = 1.0 / (1.0 + EON_CONSTANT_1 * rr);
    float single = a * (1.0 + rr * s_over_t) / PI;
    float e_avg = eon_average_albedo(rr);
    float multi = max(1.0 - e_fon_approx(mu_o, rr), EON_EPSILON)
                * max(1.0 - e_fon_approx(mu_i, rr), EON_EPSILON)
                / (PI * max(1.0 - e_avg, EON_EPSILON));
    vec3 c = clamp(rho, 0.0, 1.0);
    return max(c * single + eon_multiple_albedo(c, e_avg) * multi, vec3(0.0));
}

// The directional albedo of diffuse_eon, ρ E(μ) + ρ_ms (1 − E(μ)) with the E_FON fit
// (Portsmouth et al. 2025: single scattering reflects E, the multiple-scattering lobe
// 1 − E of ρ_ms): the radiance it reflects of a unit uniform environment.
vec3 diffuse_eon_albedo(vec3 rho, float r, float n_dot_v) {
    float e = e_fon_approx(n_dot_v, r);
    vec3 c = clamp(rho, 0.0, 1.0);
    return c * e + eon_multiple_albedo(c, eon_average_albedo(r)) * (1.0 - e);
}

// ---- Wrap lighting (seed's subsurface approximation) ----

// Hermite smoothstep that, like HLSL's and unlike GLSL's, accepts edge0 > edge1 (eq. 18
// relies on it); the edges must differ.
float hermite_step(float edge0, float edge1, float x) {
    float t = clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

// Seed eq. 18 (Fernando 2004): x = max(0, (n·l + w₁)/(1 + w₁)),
// s = smoothstep(0, w₂, x) smoothstep(2w₂, w₂, x); w₁ in [0, 1], w₂ ≥ MIN_WRAP_WIDTH.
float wrap_seed(float n_dot_l, float w1, float w2) {
    float wa = clamp(w1, 0.0, 1.0);
    float wb = max(w2, MIN_WRAP_WIDTH);
    float x = max((n_dot_l + wa) / (1.0 + wa), 0.0);
    return hermite_step(0.0, wb, x) * hermite_step(2.0 * wb, wb, x);
}

// Energy-conserving wrap, a replacement for max(0, n·l): saturate((n·l + w)/(1 + w)²),
// whose integral over the sphere is π (Lambert's) for every w in [0, 1].
float wrap_energy_conserving(float n_dot_l, float w) {
    float ww = clamp(w, 0.0, 1.0);
    return clamp((n_dot_l + ww) / ((1.0 + ww) * (1.0 + ww)), 0.0, 1.0);
}

// ---- Multiple-scattering energy compensation ----

// Fdez-Agüera 2019 (Kulla & Conty 2017 simplified, as Filament has it): the factor
// 1 + F0 (1/E − 1) on a single-scattering lobe whose albedo at F0 = 1 is E, so a white
// conductor reflects all it receives. E is clamped to [MIN_SPECULAR_ALBEDO, 1] (never
// darkening), F0 to [0, 1].
vec3 specular_energy_compensation(float e, vec3 f0) {
    float ee = clamp(e, MIN_SPECULAR_ALBEDO, 1.0);
    return 1.0 + clamp(f0, 0.0, 1.0) * (1.0 / ee - 1.0);
}

#endif // ARGIL_BRDF_GLSL

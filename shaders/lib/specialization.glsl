// A specialization constant's value that defers the choice to the uniform beside it
// (FROM_UNIFORM in src/render/forward.rs): the skybox and the bench's generic pipelines.
#ifndef ARGIL_SPECIALIZATION_GLSL
#define ARGIL_SPECIALIZATION_GLSL

const uint FROM_UNIFORM = 0xFFFFFFFFu;

// What a build of forward.frag leaves out, each at 0 (build.rs; `FragmentBuild` in
// src/render/forward.rs picks a pipeline's build from its constants): code that none of
// its pipelines runs, but which lavapipe would translate at every pipeline's creation.
// The sampled reflection (REFLECTION_SAMPLED).
#ifndef SAMPLED_REFLECTION
#define SAMPLED_REFLECTION 1
#endif
// The report's composition of the BRDFs (HORIZON_SEED's brdf_cos_seed).
#ifndef SEED_COMPOSITION
#define SEED_COMPOSITION 1
#endif
// A map's sun lobe (ENV_SUN).
#ifndef SUN_LOBE
#define SUN_LOBE 1
#endif

#endif

// A specialization constant's value that defers the choice to the uniform beside it
// (FROM_UNIFORM in src/render/forward.rs): the skybox and the bench's generic pipelines.
#ifndef ARGIL_SPECIALIZATION_GLSL
#define ARGIL_SPECIALIZATION_GLSL

const uint FROM_UNIFORM = 0xFFFFFFFFu;

#endif

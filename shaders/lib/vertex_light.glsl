// What an object's draw reads at its vertices rather than at its pixels: where its mesh is
// finely tessellated, the ground's bounce (bounce.glsl) and, where `[shadows] per_vertex`
// asks for them, the soft lights' shadows; where `[occlusion] per_vertex` reads them there,
// what the other objects take of the environment's light (object_occlusion.glsl). None
// follows the camera, so each is computed once per change of what it is made of by
// shaders/vertex_light.comp (src/render/vertex_light.rs) into one buffer that forward.vert
// reads and interpolates. A soft shadow is PCSS (shadows.glsl) at the vertex, with its
// tangent plane as the receiver's and more taps than a pixel takes; its penumbra is wider
// than the mesh's triangles, so interpolating it loses little, and the pixels then run no
// search nor filter. A hard light's edge is sharper than a triangle, and the tangent plane
// of a concave mesh lies behind the triangles the map stores: its one tap stays at the
// pixels.
#ifndef ARGIL_VERTEX_LIGHT_GLSL
#define ARGIL_VERTEX_LIGHT_GLSL
#include "bounce.glsl"
#include "shadows.glsl"
#include "object_occlusion.glsl"

// Vec4s of the soft lights' visibility that the draw reads at its vertices, lights 4k to
// 4k + 3 in the kth; 0 where it searches them at its pixels (src/render/forward.rs).
layout(constant_id = 24) const uint VERTEX_SHADOW_LAYERS = 0u;
const uint MAX_VERTEX_SHADOW_LAYERS = MAX_POINT_LIGHTS / 4;

// One vertex's entry in the buffer; `objects_take.xyz` is 1 − object_occlusion, in which
// interpolated zeros stay exactly 0 where ones would round to 1 − 2⁻²⁴ here and there.
struct LightAtVertex {
    BounceAtVertex bounce;
    vec4 shadows[MAX_VERTEX_SHADOW_LAYERS];
    vec4 objects_take;
};

// The fraction of soft light i that reaches vertex `vertex` at p of unit normal n:
// point_light_shadow with the vertex's tangent plane, seen from the side its normal faces
// (the side a closed mesh shows), its taps turned by the vertex; 1 for a hard light,
// whose shadow the pixels take, or where the light may shadow nothing of the object.
float vertex_shadow(uint i, vec3 p, vec3 n, uint vertex) {
    bool soft = shadow_data.lights[i].map.y > 0.0;
    bool may_shadow = ((object.shadowing_lights >> i) & 1u) != 0u;
    return point_light_shadow(i, p, n, n, vec2(vertex % 4096u, vertex / 4096u), soft && may_shadow);
}

#endif

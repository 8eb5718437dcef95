// The deferred pass's objects (src/render/deferred.rs): the depth that stands for object
// number `object` (forward.rs's deferred_object, 0 for none) in the objects' image, which
// each object's shading draw tests for equality: exact in fp32, and within [0, 1] below
// 2^16 objects.
#ifndef ARGIL_DEFERRED_GLSL
#define ARGIL_DEFERRED_GLSL

float deferred_object_depth(uint object) {
    return float(object) / 65536.0;
}

#endif

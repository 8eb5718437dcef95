#version 460
// One face of a light's cube shadow map: positions only, projected by the face's
// matrix (src/render/shadow.rs, face_projection); no fragment shader, depth only.
layout(location = 0) in vec3 in_position;

layout(push_constant) uniform ShadowPush {
    mat4 clip_from_object;
} push;

void main() {
    gl_Position = push.clip_from_object * vec4(in_position, 1.0);
}

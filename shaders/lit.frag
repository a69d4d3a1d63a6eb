#version 330 core
#include "lighting.glsl"
#include "shadow.glsl"

in vec3 v_world;
in vec3 v_normal;
in vec3 v_color;
in vec3 v_shadow;

out vec4 frag_color;

void main() {
    vec3 n = normalize(v_normal);
#ifdef SOFT_SELF_SHADOW
    float lit = light_visibility_soft(v_shadow);  // offline: four taps, no stepped edges
#else
    float lit = light_visibility(v_shadow);  // the window: one tap (each costs there)
#endif
    vec3 face = normalize(cross(dFdx(v_world), dFdy(v_world)));
    frag_color = vec4(to_display(shade(v_color, n, face, v_world, lit)), 1.0);
}

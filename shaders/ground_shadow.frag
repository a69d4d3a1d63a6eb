#version 330 core
#include "shadow.glsl"
// The creature's shadow on the ground, drawn over the shadow's footprint with
// multiplicative blending (result = floor colour x this colour). On a flat floor the
// shadowed/lit ratio does not depend on the floor colour: it is
// mix(u_shadowed_ratio, 1, visibility) with u_shadowed_ratio = ambient / (ambient + sun),
// and the display transform is a square root, so multiplying by sqrt(ratio) gives
// exactly the shadowed floor.

in vec3 v_shadow;
uniform vec3 u_shadowed_ratio;
out vec4 frag_color;

void main() {
    float lit = light_visibility_soft(v_shadow);
    frag_color = vec4(sqrt(mix(u_shadowed_ratio, vec3(1.0), lit)), 1.0);
}

#version 330 core
#include "lighting.glsl"
#include "shadow.glsl"
// The creature's shadow on the ground, drawn over the shadow's footprint with
// multiplicative blending (result = floor colour x this colour). On a flat floor the
// shadowed/lit ratio does not depend on the floor colour, and the display transform is
// a square root, so multiplying by sqrt(ratio) gives exactly the shadowed floor.

in vec3 v_world;
out vec4 frag_color;

void main() {
    const vec3 up = vec3(0.0, 1.0, 0.0);
    float lit = light_visibility_soft(v_world, up);
    float wrapped = max((-u_light_dir.y + 0.35) * (1.0 / 1.35), 0.0);
    vec3 ambient = ambient_light(up);
    vec3 ratio = (ambient + SUN_COLOR * wrapped * lit) / (ambient + SUN_COLOR * wrapped);
    frag_color = vec4(sqrt(ratio), 1.0);
}

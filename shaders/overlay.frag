#version 330 core
#include "lighting.glsl"
in float v_focus_distance;
uniform vec3 u_color;          // linear
uniform vec3 u_horizon_color;  // linear
uniform vec2 u_fog_range;
out vec4 frag_color;
void main() {
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, v_focus_distance);
    frag_color = vec4(to_display(mix(u_color, u_horizon_color, fog)), 1.0);
}

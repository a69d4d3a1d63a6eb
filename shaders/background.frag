#version 330 core
#include "lighting.glsl"
// Sky gradient: the horizon colour at the floor's far edge (where the fogged floor ends
// in the same colour), rising to the sky colour overhead. Below the band the framebuffer
// is cleared to the horizon colour.
in float v_height;
uniform vec3 u_top_color;      // linear
uniform vec3 u_horizon_color;  // linear
out vec4 frag_color;
void main() {
    vec3 color = mix(u_horizon_color, u_top_color, smoothstep(0.0, 0.45, v_height));
    frag_color = vec4(to_display(color), 1.0);
}

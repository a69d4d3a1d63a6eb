#version 330 core
#include "lighting.glsl"
#include "grid.glsl"
// Flat ground: a matte floor with an anti-aliased grid that moves with the ground (so planted
// feet stay on one spot of it), fading into the horizon colour with distance. The floor
// is flat, so its lighting is one constant, applied to its two colours on the CPU
// (u_ground_lit, u_line_lit: the same lighting model as lighting.glsl's); the fog comes
// from the floor mesh's corners (ground.vert). A software rasteriser's floor costs per
// pixel, and the floor is most of the picture. The creature's shadow is multiplied onto it
// afterwards by ground_shadow.frag over the shadow's footprint only.

in vec2 v_grid;  // grid coordinate (grid.glsl)
in float v_fog;  // 0: clear, 1: the horizon colour

uniform vec3 u_ground_lit;     // the ground colour lit by ambient + sun (linear)
uniform vec3 u_line_lit;       // the grid lines' colour, lit likewise (linear)
uniform vec3 u_horizon_color;  // linear

out vec4 frag_color;

void main() {
    vec3 color = mix(u_ground_lit, u_line_lit, grid_line(v_grid));
    frag_color = vec4(to_display(mix(color, u_horizon_color, v_fog)), 1.0);
}

#version 330 core
#include "lighting.glsl"
#include "grid.glsl"
// Flat ground: a matte floor with an anti-aliased grid that moves with the ground (so planted
// feet stay on one spot of it), fading into the horizon colour with distance. The floor
// is flat, so its lighting is one constant, applied to its two colours on the CPU
// (u_ground_lit, u_line_lit: the same lighting model as lighting.glsl's); the fog's
// smoothstep is a ramp the CPU has set up (no division per pixel: a software rasteriser's
// floor costs per pixel, and the floor is most of the picture). The creature's shadow is
// multiplied onto it afterwards by ground_shadow.frag over the shadow's footprint only.

in vec2 v_grid;  // grid coordinate (grid.glsl)
in vec2 v_focus_offset;  // world xz - u_focus (metres)

uniform vec3 u_ground_lit;     // the ground colour lit by ambient + sun (linear)
uniform vec3 u_line_lit;       // the grid lines' colour, lit likewise (linear)
uniform vec3 u_horizon_color;  // linear
uniform vec2 u_fog_ramp;       // fog = smoothstep of clamp(distance * x + y): 0 at the fog's start, 1 at its end

out vec4 frag_color;

void main() {
    vec3 color = mix(u_ground_lit, u_line_lit, grid_line(v_grid));
    float t = clamp(length(v_focus_offset) * u_fog_ramp.x + u_fog_ramp.y, 0.0, 1.0);
    frag_color = vec4(to_display(mix(color, u_horizon_color, t * t * (3.0 - 2.0 * t))), 1.0);
}

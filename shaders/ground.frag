#version 330 core
#include "lighting.glsl"
#include "grid.glsl"
// Flat ground: a matte floor with an anti-aliased grid that moves with the ground (so planted
// feet stay on one spot of it), fading into the horizon colour with distance. The floor
// is flat, so its lighting is one constant (u_floor_light, from the same lighting model
// on the CPU); the creature's shadow is multiplied onto it afterwards by
// ground_shadow.frag over the shadow's footprint only.

in vec2 v_grid;  // grid coordinate (grid.glsl)
in vec2 v_focus_offset;  // world xz - u_focus (metres)

uniform vec3 u_ground_color;   // linear
uniform vec3 u_line_color;     // linear
uniform vec3 u_horizon_color;  // linear
uniform vec3 u_floor_light;    // ambient + sun reaching the floor (linear)
uniform vec2 u_fog_range;      // fog starts, ends (metres from u_focus)

out vec4 frag_color;

void main() {
    float line = grid_line(v_grid);
    vec3 color = mix(u_ground_color, u_line_color, line) * u_floor_light;
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, length(v_focus_offset));
    frag_color = vec4(to_display(mix(color, u_horizon_color, fog)), 1.0);
}

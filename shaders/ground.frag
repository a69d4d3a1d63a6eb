#version 330 core
#include "lighting.glsl"
// Ground: a matte floor with an anti-aliased grid that moves with the ground (so planted
// feet stay on one spot of it), fading into the horizon colour with distance. The floor
// is flat, so its lighting is one constant (u_floor_light, from the same lighting model
// on the CPU); the creature's shadow is multiplied onto it afterwards by
// ground_shadow.frag over the shadow's footprint only.

in vec3 v_world;
in float v_focus_distance;

uniform vec3 u_ground_color;   // linear
uniform vec3 u_line_color;     // linear
uniform vec3 u_horizon_color;  // linear
uniform vec3 u_floor_light;    // ambient + sun reaching the floor (linear)
uniform vec2 u_grid_offset;    // metres the ground has moved (added to world xz)
uniform float u_grid_spacing;  // metres between minor lines
uniform float u_grid_on;       // 0 or 1
uniform vec2 u_fog_range;      // fog starts, ends (metres from u_focus)

out vec4 frag_color;

void main() {
    vec2 coord = (v_world.xz + u_grid_offset) / u_grid_spacing;
    vec2 fw = max(fwidth(coord), vec2(1e-6));
    // Minor lines every unit, major lines every 5; both fade out before they would alias.
    vec2 minor_d = abs(fract(coord - 0.5) - 0.5) / fw;
    vec2 major_d = abs(fract(coord * 0.2 - 0.5) - 0.5) / (fw * 0.3);
    float spread = max(fw.x, fw.y);
    float minor = (1.0 - min(min(minor_d.x, minor_d.y), 1.0)) * (1.0 - smoothstep(0.25, 0.6, spread));
    float major = (1.0 - min(min(major_d.x, major_d.y), 1.0)) * (1.0 - smoothstep(1.25, 3.0, spread));
    float line = u_grid_on * max(minor * 0.45, major * 0.8);
    vec3 color = mix(u_ground_color, u_line_color, line) * u_floor_light;
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, v_focus_distance);
    frag_color = vec4(to_display(mix(color, u_horizon_color, fog)), 1.0);
}

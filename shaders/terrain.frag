#version 330 core
#include "lighting.glsl"
#include "shadow.glsl"
#include "grid.glsl"
// Terrain: matte ground with the world grid draped over it (lines at fixed world x and z,
// so planted feet stay on one spot), the creature's shadow and the fog towards the horizon.

in vec3 v_world;
in vec3 v_shadow;
in vec3 v_ambient;
in vec3 v_sun;

uniform vec3 u_ground_color;   // linear
uniform vec3 u_line_color;     // linear
uniform vec3 u_horizon_color;  // linear
uniform vec2 u_fog_range;
uniform vec2 u_focus;  // world xz the fog is centred on (per pixel: terrain faces can be large)

out vec4 frag_color;

void main() {
    float line = grid_line(v_world.xz);
    float lit = light_visibility_soft(v_shadow);
    vec3 color = mix(u_ground_color, u_line_color, line) * (v_ambient + v_sun * lit);
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, length(v_world.xz - u_focus));
    frag_color = vec4(to_display(mix(color, u_horizon_color, fog)), 1.0);
}

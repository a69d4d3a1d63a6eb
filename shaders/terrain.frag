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
in float v_up;  // the normal's y: steep faces (risers) are drawn darker

uniform vec3 u_ground_color;   // linear
uniform vec3 u_line_color;     // linear
uniform vec3 u_horizon_color;  // linear
uniform vec2 u_fog_range;
uniform vec2 u_focus;  // world xz the fog is centred on (per pixel: terrain faces can be large)

out vec4 frag_color;

// Contour lines every u_contour metres of height: they make hills, slopes and the risers
// of stairs readable from any side (0 turns them off).
uniform float u_contour;

float contour_line(float y) {
    if (u_contour <= 0.0) {
        return 0.0;
    }
    float c = y / u_contour + 0.5;
    float fw = max(fwidth(c), 1e-6);
    float d = abs(fract(c - 0.5) - 0.5) / fw;
    // Only where the ground slopes (level ground has no contours), and never so dense they alias.
    return (1.0 - min(d, 1.0)) * smoothstep(0.01, 0.06, fw) * (1.0 - smoothstep(0.3, 0.7, fw)) * 0.55;
}

void main() {
    float line = max(grid_line(grid_coord(v_world.xz)), contour_line(v_world.y));
    float lit = light_visibility_soft(v_shadow);
    vec3 color = mix(u_ground_color, u_line_color, line) * (v_ambient + v_sun * lit);
    color *= 1.0 - 0.35 * (1.0 - smoothstep(0.3, 0.8, v_up));
    float fog = smoothstep(u_fog_range.x, u_fog_range.y, length(v_world.xz - u_focus));
    frag_color = vec4(to_display(mix(color, u_horizon_color, fog)), 1.0);
}

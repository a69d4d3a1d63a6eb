#version 330 core
// A rectangle on the ground plane, used for the floor and for the shadow that lies on it.

in vec2 in_xz;  // unit square corner in [-1, 1]^2

uniform mat4 u_view_proj;
uniform vec2 u_center;     // world xz of the rectangle's centre
uniform vec2 u_half_size;  // half extents in x and z (metres)
uniform float u_lift;      // height above y = 0 (metres)
uniform vec2 u_focus;      // world xz the fog is centred on (the floor disc's centre)
uniform vec2 u_fog_ramp;   // fog = smoothstep of clamp(distance * x + y): 0 at the fog's start, 1 at its end
uniform vec2 u_grid_offset;    // as in grid.glsl: metres the ground has moved
uniform float u_grid_spacing;  // metres between minor grid lines

#include "shadow_vertex.glsl"

out vec2 v_grid;   // grid coordinate (grid.glsl's grid_coord), linear in the world
out vec3 v_shadow;  // light-space position (used by the shadow pass only)
out float v_fog;   // the fog at this corner (the floor's mesh has rings through it: linear enough between)

void main() {
    vec3 world = vec3(u_center.x + in_xz.x * u_half_size.x, u_lift, u_center.y + in_xz.y * u_half_size.y);
    v_grid = (world.xz + u_grid_offset) / u_grid_spacing;
    v_shadow = shadow_coord(world, vec3(0.0, 1.0, 0.0));
    float t = clamp(length(world.xz - u_focus) * u_fog_ramp.x + u_fog_ramp.y, 0.0, 1.0);
    v_fog = t * t * (3.0 - 2.0 * t);
    gl_Position = u_view_proj * vec4(world, 1.0);
}

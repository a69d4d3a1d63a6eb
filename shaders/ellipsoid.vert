#version 330 core
// Instanced ellipsoid: a unit sphere scaled by three radii along three unit axes.

in vec3 in_pos;       // unit-sphere point (also its normal)

in vec3 in_center;
in vec3 in_axis_x;
in vec3 in_axis_y;
in vec3 in_axis_z;
in vec3 in_radii;
in vec3 in_color;

uniform mat4 u_view_proj;

#include "shadow_vertex.glsl"

out vec3 v_world;
out vec3 v_normal;
out vec3 v_color;
out vec3 v_shadow;  // light-space position

void main() {
    vec3 scaled = in_pos * in_radii;
    v_world = in_center + in_axis_x * scaled.x + in_axis_y * scaled.y + in_axis_z * scaled.z;
    vec3 n = in_pos / in_radii;  // inverse-transpose of the scale
    v_normal = normalize(in_axis_x * n.x + in_axis_y * n.y + in_axis_z * n.z);
    v_color = in_color;
    v_shadow = shadow_coord(v_world, v_normal);
    gl_Position = u_view_proj * vec4(v_world, 1.0);
}

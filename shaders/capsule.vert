#version 330 core
// Instanced tapered capsule: the unit mesh's vertices belong to end 0 or end 1 and are
// placed around that end's centre at that end's radius. Per instance: both end centres,
// both radii and a colour (linear).

in vec3 in_pos;     // unit-sphere direction of the vertex, capsule axis = +Y
in float in_end;    // 0 for the cap at a, 1 for the cap at b

in vec3 in_a;
in vec3 in_b;
in vec2 in_radius;
in vec3 in_color;

uniform mat4 u_view_proj;

#include "shadow_vertex.glsl"

out vec3 v_world;
out vec3 v_normal;
out vec3 v_color;
out vec3 v_shadow;  // light-space position

void main() {
    vec3 axis = in_b - in_a;
    float len = length(axis);
    vec3 y = len > 1e-9 ? axis / len : vec3(0.0, 1.0, 0.0);
    vec3 helper = abs(y.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
    vec3 x = normalize(cross(helper, y));
    vec3 z = cross(x, y);
    vec3 dir = x * in_pos.x + y * in_pos.y + z * in_pos.z;
    float r = mix(in_radius.x, in_radius.y, in_end);
    vec3 centre = mix(in_a, in_b, in_end);
    v_world = centre + dir * r;
    // Tapered side: tilt the normal by the cone's slope.
    float slope = len > 1e-9 ? (in_radius.x - in_radius.y) / len : 0.0;
    v_normal = normalize(dir + y * slope * (1.0 - abs(in_pos.y)));
    v_color = in_color;
    v_shadow = shadow_coord(v_world, v_normal);
    gl_Position = u_view_proj * vec4(v_world, 1.0);
}

#version 330 core
// Terrain: a world-space triangle mesh (heights and normals from the terrain). Lighting
// is computed per vertex (ambient for the normal plus the wrapped key light), so the
// fragment shader only adds the grid, the shadow and the fog.
#include "lighting.glsl"

in vec3 in_position;
in vec3 in_normal;

uniform mat4 u_view_proj;

#include "shadow_vertex.glsl"

out vec3 v_world;
out vec3 v_shadow;
out vec3 v_ambient;
out vec3 v_sun;
out float v_up;

void main() {
    vec3 n = normalize(in_normal);
    v_world = in_position;
    v_shadow = shadow_coord(in_position, n);
    v_ambient = ambient_light(n);
    v_up = n.y;
    v_sun = SUN_COLOR * max((dot(n, -u_light_dir) + 0.35) * (1.0 / 1.35), 0.0);
    gl_Position = u_view_proj * vec4(in_position, 1.0);
}

#version 330 core
#include "lighting.glsl"
// Sky: the horizon colour at and below the horizon (where the fogged ground ends), rising
// to the sky colour overhead. Computed from the view ray, so it matches the ground at any
// camera angle.
in vec2 v_uv;
uniform mat4 u_inverse_view_proj;
uniform vec3 u_top_color;      // linear
uniform vec3 u_horizon_color;  // linear
out vec4 frag_color;
void main() {
    vec4 far_point = u_inverse_view_proj * vec4(v_uv * 2.0 - 1.0, 1.0, 1.0);
    vec3 ray = normalize(far_point.xyz / far_point.w - u_camera_pos);
    vec3 color = mix(u_horizon_color, u_top_color, smoothstep(0.0, 0.45, ray.y));
    frag_color = vec4(to_display(color), 1.0);
}

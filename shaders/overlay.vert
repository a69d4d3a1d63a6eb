#version 330 core
// Flat-coloured lines and ribbons drawn over the ground (the path), in world space.
in vec3 in_position;
uniform mat4 u_view_proj;
uniform vec2 u_focus;
out float v_focus_distance;
void main() {
    v_focus_distance = length(in_position.xz - u_focus);
    gl_Position = u_view_proj * vec4(in_position, 1.0);
}

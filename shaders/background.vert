#version 330 core
// Sky: a screen-space band from the far edge of the floor up to the top of the view,
// drawn on the far plane (only where nothing else was drawn). in_height is how far up
// the sky each vertex looks (ray elevation), interpolated across the band.
in vec2 in_ndc;
in float in_height;
out float v_height;
void main() {
    v_height = in_height;
    gl_Position = vec4(in_ndc, 1.0, 1.0);
}

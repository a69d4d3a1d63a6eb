#version 330 core
// Sky: a screen-space band from the far edge of the floor up to the top of the view,
// drawn on the far plane (only where nothing else was drawn), in rows whose colours
// (display values) the CPU works out from the gradient (app/render/ground.py).
in vec2 in_ndc;
in vec3 in_color;
out vec3 v_color;
void main() {
    v_color = in_color;
    gl_Position = vec4(in_ndc, 1.0, 1.0);
}

#version 330 core
// Rectangles of the image given in pixels (from the bottom left); v_uv is the texture
// coordinate of the same spot of the source image.
in vec2 in_pixel;
uniform vec2 u_texel;  // 1 / image size
out vec2 v_uv;
void main() {
    v_uv = in_pixel * u_texel;
    gl_Position = vec4(v_uv * 2.0 - 1.0, 0.0, 1.0);
}

#version 330 core
// Sky gradient: the horizon colour at the floor's far edge (where the fogged floor ends
// in the same colour), rising to the sky colour overhead; colours come per row from the
// vertices. Below the band the framebuffer is cleared to the horizon colour.
in vec3 v_color;
out vec4 frag_color;
void main() {
    frag_color = vec4(v_color, 1.0);
}

// Soft studio lighting shared by every lit surface.
// Colours are in a gamma-2.0 "linear" space: squared sRGB on the way in (see
// app/render/scene.py: srgb_to_linear) and a square root on the way out. It is within a
// few percent of true sRGB and much cheaper than pow() on a software rasteriser.
// Hemisphere ambient (sky above, warm bounce below), one wrapped key light that casts the
// shadow, a faint specular and a rim to separate the creature from the background.

uniform vec3 u_light_dir;     // direction the key light travels (unit)
uniform vec3 u_camera_pos;    // world position of the eye
uniform vec3 u_sky_color;     // linear
uniform vec3 u_bounce_color;  // linear

const vec3 SUN_COLOR = vec3(0.95, 0.90, 0.84);

vec3 ambient_light(vec3 n) {
    return mix(u_bounce_color, u_sky_color, 0.5 + 0.5 * n.y) * 0.55;
}

// n: the smooth (interpolated) normal; face: the triangle's own, from the surface's
// screen derivatives. The rim lights only where both graze the view (a silhouette): in a
// fold of skinned skin (an armpit as the arm swings back) the smooth normals turn away
// while the triangles still face the eye, and the rim had lit pale patches there.
vec3 shade(vec3 albedo, vec3 n, vec3 face, vec3 p, float lit) {
    vec3 to_light = -u_light_dir;
    vec3 to_eye = normalize(u_camera_pos - p);
    float wrapped = max((dot(n, to_light) + 0.35) * (1.0 / 1.35), 0.0);
    float h = max(dot(n, normalize(to_light + to_eye)), 0.0);
    float h2 = h * h, h4 = h2 * h2, h8 = h4 * h4, h16 = h8 * h8;
    float spec = h16 * h16 * 0.12 * lit;  // h^32
    float facing = 1.0 - max(abs(dot(n, to_eye)), abs(dot(face, to_eye)));
    float rim = facing * facing * facing * 0.18;
    return albedo * (ambient_light(n) + SUN_COLOR * wrapped * lit) + vec3(spec) + rim * u_sky_color;
}

vec3 to_display(vec3 linear_color) {
    return sqrt(clamp(linear_color, 0.0, 1.0));
}

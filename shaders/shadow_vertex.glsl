// Light-space position of a vertex, for shadow lookups in the fragment shader.

uniform mat4 u_light_view_proj;
uniform float u_shadow_texel;  // world size (m) of one shadow-map texel

vec3 shadow_coord(vec3 world, vec3 normal) {
    // Normal offset of two texels keeps lit surfaces from shadowing themselves (acne).
    vec4 lp = u_light_view_proj * vec4(world + normal * (2.0 * u_shadow_texel), 1.0);
    return lp.xyz / lp.w * 0.5 + 0.5;
}

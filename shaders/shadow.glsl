// Shadow lookups into the key light's depth map (comparison sampler, bilinear: every
// tap is already a 2x2 percentage-closer filter).

uniform sampler2DShadow u_shadow_map;
uniform mat4 u_light_view_proj;
uniform float u_shadow_strength;  // 0 = no shadow, 1 = full
uniform float u_shadow_texel;     // world size (m) of one shadow-map texel

vec3 shadow_coord(vec3 p, vec3 n) {
    // Normal offset of two texels keeps lit surfaces from shadowing themselves (acne).
    vec4 lp = u_light_view_proj * vec4(p + n * (2.0 * u_shadow_texel), 1.0);
    return lp.xyz / lp.w * 0.5 + 0.5;
}

bool outside_shadow_map(vec3 c) {
    return c.x <= 0.0 || c.x >= 1.0 || c.y <= 0.0 || c.y >= 1.0 || c.z >= 1.0;
}

// One bilinear tap: for surfaces of the creature itself (self-shadowing).
float light_visibility(vec3 p, vec3 n) {
    vec3 c = shadow_coord(p, n);
    if (outside_shadow_map(c)) {
        return 1.0;
    }
    return mix(1.0, texture(u_shadow_map, vec3(c.xy, c.z - 0.001)), u_shadow_strength);
}

// Four bilinear taps (a soft 4x4-texel footprint): for the shadow on the ground.
float light_visibility_soft(vec3 p, vec3 n) {
    vec3 c = shadow_coord(p, n);
    if (outside_shadow_map(c)) {
        return 1.0;
    }
    vec2 texel = 1.0 / vec2(textureSize(u_shadow_map, 0));
    float z = c.z - 0.001;
    float sum = texture(u_shadow_map, vec3(c.xy + vec2(-0.75, -0.75) * texel, z))
              + texture(u_shadow_map, vec3(c.xy + vec2(0.75, -0.75) * texel, z))
              + texture(u_shadow_map, vec3(c.xy + vec2(-0.75, 0.75) * texel, z))
              + texture(u_shadow_map, vec3(c.xy + vec2(0.75, 0.75) * texel, z));
    return mix(1.0, sum * 0.25, u_shadow_strength);
}

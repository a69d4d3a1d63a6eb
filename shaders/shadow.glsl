// Shadow lookups into the key light's depth map (comparison sampler, bilinear: every
// tap is already a 2x2 percentage-closer filter). The light-space coordinate comes from
// the vertex shader (shadow_vertex.glsl): the light's projection is orthographic, so it
// interpolates exactly across triangles.

uniform sampler2DShadow u_shadow_map;
uniform float u_shadow_strength;  // 0 = no shadow, 1 = full

bool outside_shadow_map(vec3 c) {
    return c.x <= 0.0 || c.x >= 1.0 || c.y <= 0.0 || c.y >= 1.0 || c.z >= 1.0;
}

// One bilinear tap: for surfaces of the creature itself (self-shadowing).
float light_visibility(vec3 c) {
    if (outside_shadow_map(c)) {
        return 1.0;
    }
    return mix(1.0, texture(u_shadow_map, vec3(c.xy, c.z - 0.001)), u_shadow_strength);
}

// Four bilinear taps (a soft 4x4-texel footprint): for the shadow on the ground.
float light_visibility_soft(vec3 c) {
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

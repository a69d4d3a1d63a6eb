#version 330 core
// Fast approximate antialiasing (after Lottes' FXAA): where the luma of the four diagonal
// neighbours says an edge passes, blend along the edge's direction. One pass over the
// finished image: far cheaper than multisampling on a software rasteriser, whose cost is
// per sample. Flat areas and smooth gradients are left untouched.

uniform sampler2D u_image;
uniform vec2 u_texel;  // 1 / image size

in vec2 v_uv;
out vec4 frag_color;

const float REDUCE_MIN = 1.0 / 128.0;
const float REDUCE_MUL = 1.0 / 8.0;
const float SPAN_MAX = 8.0;

float luma(vec3 c) {
    return dot(c, vec3(0.299, 0.587, 0.114));
}

void main() {
    // The centre and its diagonal neighbours by texelFetch: unfiltered reads are several
    // times cheaper than filtered ones on a software rasteriser, and most pixels stop here.
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 last = textureSize(u_image, 0) - 1;
    vec3 centre = texelFetch(u_image, p, 0).rgb;
    float nw = luma(texelFetch(u_image, clamp(p + ivec2(-1, -1), ivec2(0), last), 0).rgb);
    float ne = luma(texelFetch(u_image, clamp(p + ivec2(1, -1), ivec2(0), last), 0).rgb);
    float sw = luma(texelFetch(u_image, clamp(p + ivec2(-1, 1), ivec2(0), last), 0).rgb);
    float se = luma(texelFetch(u_image, clamp(p + ivec2(1, 1), ivec2(0), last), 0).rgb);
    float m = luma(centre);
    float lo = min(m, min(min(nw, ne), min(sw, se)));
    float hi = max(m, max(max(nw, ne), max(sw, se)));
    if (hi - lo < max(1.0 / 24.0, hi * 0.125)) {  // no edge here: the common case, cheap
        frag_color = vec4(centre, 1.0);
        return;
    }
    vec2 dir = vec2(-((nw + ne) - (sw + se)), (nw + sw) - (ne + se));
    float reduce = max((nw + ne + sw + se) * 0.25 * REDUCE_MUL, REDUCE_MIN);
    float scale = 1.0 / (min(abs(dir.x), abs(dir.y)) + reduce);
    dir = clamp(dir * scale, vec2(-SPAN_MAX), vec2(SPAN_MAX)) * u_texel;
    vec3 near = 0.5 * (texture(u_image, v_uv + dir * (1.0 / 3.0 - 0.5)).rgb
                     + texture(u_image, v_uv + dir * (2.0 / 3.0 - 0.5)).rgb);
    vec3 wide = 0.5 * near + 0.25 * (texture(u_image, v_uv - 0.5 * dir).rgb
                                     + texture(u_image, v_uv + 0.5 * dir).rgb);
    float wide_luma = luma(wide);
    frag_color = vec4((wide_luma < lo || wide_luma > hi) ? near : wide, 1.0);
}

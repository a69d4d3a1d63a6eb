#version 330 core
// A skinned body: each vertex moved by up to four joints (linear blend skinning). The
// joints' skinning matrices (world now x inverse bind, affine) are rows of u_bones, three
// RGBA32F texels a matrix (its top three rows): instance i of a draw (one animal of a
// herd) reads its joints from row u_bone_offset + i * u_bone_stride. The rows are blended
// first, then applied once (12 texel fetches a vertex, one transform).

in vec3 in_pos;
in vec3 in_normal;
in vec3 in_color;
in vec4 in_joints;
in vec4 in_weights;

uniform mat4 u_view_proj;
uniform sampler2D u_bones;
uniform int u_bone_offset;
uniform int u_bone_stride;

#include "shadow_vertex.glsl"

out vec3 v_world;
out vec3 v_normal;
out vec3 v_color;
out vec3 v_shadow;

int bone_row(float joint) {
    return u_bone_offset + gl_InstanceID * u_bone_stride + int(joint + 0.5);
}

void main() {
    vec4 rows[3] = vec4[3](vec4(0.0), vec4(0.0), vec4(0.0));
    for (int k = 0; k < 4; ++k) {
        float w = in_weights[k];
        int row = bone_row(in_joints[k]);
        rows[0] += w * texelFetch(u_bones, ivec2(0, row), 0);
        rows[1] += w * texelFetch(u_bones, ivec2(1, row), 0);
        rows[2] += w * texelFetch(u_bones, ivec2(2, row), 0);
    }
    vec4 p = vec4(in_pos, 1.0);
    v_world = vec3(dot(rows[0], p), dot(rows[1], p), dot(rows[2], p));
    mat3 turn = transpose(mat3(rows[0].xyz, rows[1].xyz, rows[2].xyz));
    v_normal = normalize(turn * in_normal);
    v_color = in_color;
    v_shadow = shadow_coord(v_world, v_normal);
    gl_Position = u_view_proj * vec4(v_world, 1.0);
}

#version 330 core
// A skinned body: each vertex moved by up to four joints (linear blend skinning). The
// joints' skinning matrices (world now x inverse bind) are rows of u_bones, four RGBA32F
// texels a matrix (its columns): instance i of a draw (one animal of a herd) reads its
// joints from row u_bone_offset + i * u_bone_stride.

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

mat4 bone(float joint) {
    int row = u_bone_offset + gl_InstanceID * u_bone_stride + int(joint + 0.5);
    return mat4(texelFetch(u_bones, ivec2(0, row), 0), texelFetch(u_bones, ivec2(1, row), 0),
                texelFetch(u_bones, ivec2(2, row), 0), texelFetch(u_bones, ivec2(3, row), 0));
}

void main() {
    mat4 skin = in_weights.x * bone(in_joints.x) + in_weights.y * bone(in_joints.y)
              + in_weights.z * bone(in_joints.z) + in_weights.w * bone(in_joints.w);
    v_world = (skin * vec4(in_pos, 1.0)).xyz;
    v_normal = normalize(mat3(skin) * in_normal);
    v_color = in_color;
    v_shadow = shadow_coord(v_world, v_normal);
    gl_Position = u_view_proj * vec4(v_world, 1.0);
}

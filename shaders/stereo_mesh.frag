#version 450
// shaders/stereo_mesh.frag - Blinn-Phong shading with a directional light, two-sided, per eye;
// flat colour (with alpha, for the translucent workspace box) when draw.lit == 0.
#extension GL_GOOGLE_include_directive : require

#include "stereo_interface.glsl"

layout(location = 0) in vec3 in_world_position;
layout(location = 1) in vec3 in_world_normal;
layout(location = 2) flat in uint in_eye;

layout(location = 0) out vec4 out_colour;

void main() {
    if (draw.lit == 0u) {
        out_colour = draw.colour;
        return;
    }
    vec3 n = normalize(in_world_normal);
    if (!gl_FrontFacing) n = -n;
    vec3 l = eyes.light_direction.xyz;
    vec3 v = normalize(eyes.eye_position[in_eye].xyz - in_world_position);
    vec3 h = normalize(l + v);
    float diffuse = max(dot(n, l), 0.0);
    float specular = diffuse > 0.0 ? pow(max(dot(n, h), 0.0), 48.0) : 0.0;
    vec3 rgb = draw.colour.rgb * (0.2 + 0.75 * diffuse) + vec3(0.25 * specular);
    out_colour = vec4(min(rgb, vec3(1.0)), draw.colour.a);
}

#version 450
// shaders/stereo_mesh.frag - Blinn-Phong shading with a directional key light from above plus a soft
// fill light from the eye (so faces turned from the key light keep their shape), two-sided, per eye;
// flat colour (with alpha, for the translucent workspace box and the overlay) when draw.lit == 0.
// The base colour is draw.colour, or the interpolated palette colour of the vertex materials when
// draw.palette == 1 (per-material workpiece colours).
// FLAT_NORMALS 1 (the GPU contour, which carries no normals): the facet normal from screen-space derivatives
// of the world position, turned towards the eye (flat shading; the surface is closed and back faces are culled).
#extension GL_GOOGLE_include_directive : require

#include "stereo_interface.glsl"

#ifndef FLAT_NORMALS
#define FLAT_NORMALS 0
#endif

layout(location = 0) in vec3 in_world_position;
layout(location = 1) in vec3 in_world_normal;
layout(location = 2) flat in uint in_eye;
layout(location = 3) in vec4 in_palette_colour;

layout(location = 0) out vec4 out_colour;

void main() {
    if (((draw.eye_mask >> in_eye) & 1u) == 0u) discard;  // a one-eye draw (multiview draws every view)
    vec4 base = draw.palette != 0u ? in_palette_colour : draw.colour;
    if (draw.lit == 0u) {
        out_colour = base;
        return;
    }
    vec3 v = normalize(eyes.eye_position[in_eye].xyz - in_world_position);
#if FLAT_NORMALS
    vec3 n = normalize(cross(dFdx(in_world_position), dFdy(in_world_position)));
    if (dot(n, v) < 0.0) n = -n;
#else
    vec3 n = normalize(in_world_normal);
    if (!gl_FrontFacing) n = -n;
#endif
    vec3 l = eyes.light_direction.xyz;
    vec3 h = normalize(l + v);
    float diffuse = max(dot(n, l), 0.0);
    float fill = max(dot(n, v), 0.0);
    float specular = diffuse > 0.0 ? pow(max(dot(n, h), 0.0), 48.0) : 0.0;
    vec3 rgb = base.rgb * (0.2 + 0.6 * diffuse + 0.2 * fill) + vec3(0.2 * specular);
    out_colour = vec4(min(rgb, vec3(1.0)), base.a);
}

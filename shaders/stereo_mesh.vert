#version 450
// shaders/stereo_mesh.vert - transforms a mesh vertex (model m) into one eye's clip space.
// EYE_MODE selects how the eye is chosen (renderer/stereo/eye_strategy.hpp):
//   0 = one render pass per eye: eye index from the push constant;
//   1 = multiview: eye = gl_ViewIndex (the view mask routes it to a layer);
//   2 = instanced layered draw: eye = gl_InstanceIndex & 1, written to gl_Layer.
// Screen-space draws (draw.screen_space = 1, the overlay) skip the eye's matrix: both eyes get the
// same clip position, i.e. zero disparity, as if drawn on the screen plane.
// CONTOUR_INPUT 1: the GPU contour's vertices (compute/gpu/gpu_contourer.hpp GpuContourVertex, 16 bytes: grid
// position + material, no normal; world_from_model = world_from_grid). Drawn with indirect draws whose
// instance count is 1, so the instanced-layer variant takes the eye from the push constant (one draw per eye).
#extension GL_GOOGLE_include_directive : require
#if EYE_MODE == 1
#extension GL_EXT_multiview : require
#elif EYE_MODE == 2
#extension GL_ARB_shader_viewport_layer_array : require
#endif

#include "stereo_interface.glsl"

#ifndef CONTOUR_INPUT
#define CONTOUR_INPUT 0
#endif

layout(location = 0) in vec3 in_position;  // model space, m (pixels for screen-space draws)
#if CONTOUR_INPUT
const vec3 in_normal = vec3(0.0);          // no normal: the fragment shader derives the facet normal
#else
layout(location = 1) in vec3 in_normal;    // model space, unit (ignored when unlit)
#endif
layout(location = 2) in uint in_material;  // material id, 0..MATERIAL_COUNT-1

layout(location = 0) out vec3 out_world_position;
layout(location = 1) out vec3 out_world_normal;
layout(location = 2) flat out uint out_eye;
layout(location = 3) out vec4 out_palette_colour;  // palette[in_material] (only read when draw.palette == 1)

void main() {
#if EYE_MODE == 0
    uint eye = draw.eye;
#elif EYE_MODE == 1
    uint eye = gl_ViewIndex;
#elif CONTOUR_INPUT
    uint eye = draw.eye;
    gl_Layer = int(eye);
#else
    uint eye = uint(gl_InstanceIndex) & 1u;
    gl_Layer = int(eye);
#endif
    vec4 world = draw.world_from_model * vec4(in_position, 1.0);
    out_world_position = world.xyz;
    out_world_normal = mat3(draw.world_from_model) * in_normal;
    out_eye = eye;
    out_palette_colour = eyes.palette[min(in_material, uint(MATERIAL_COUNT - 1))];
    gl_Position = draw.screen_space != 0u ? world : eyes.clip_from_world[eye] * world;
}

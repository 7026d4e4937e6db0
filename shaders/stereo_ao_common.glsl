// shaders/stereo_ao_common.glsl - resources and helpers shared by stereo_ao.comp and stereo_ao_apply.comp
// (renderer/stereo/ambient_occlusion.cpp binds them).
#define NO_DRAW_CONSTANTS 1
// Pixels per occlusion value along x and y: 2 (half resolution) or 4 (quarter resolution); set at build time.
#ifndef BLOCK
#define BLOCK 2
#endif
#include "stereo_interface.glsl"

layout(set = 0, binding = 1) uniform sampler2DArray depth_layers;       // D32, DEPTH_STENCIL_READ_ONLY_OPTIMAL
layout(set = 0, binding = 2, rgba8) uniform image2DArray colour_layers;  // GENERAL
// One value per BLOCK x BLOCK pixel block, one layer per eye (layer = eye), GENERAL: the colour scale of the block's
// nearest surface point (x) and that point's distance in front of the eye, m (y; -1 where the block shows no
// surface).
layout(set = 0, binding = 3, rgba16f) uniform image2DArray half_occlusion;

layout(push_constant, std430) uniform Pass {
    uint first_eye;    // eye (0 left, 1 right) of invocation z = 0
    uint first_texel;  // its layer in the bound depth and colour views (0 when they hold that one layer only)
    ivec2 origin;      // block (half_occlusion texel) of invocation (0, 0): the dispatch covers a region
} pass;

// Distance in front of the eye (m) of the surface with depth-buffer value `depth` in eye `layer`. The inverse of a
// perspective (off-axis) projection maps clip z and w to eye z and w independently of clip x and y, so only its
// third and fourth rows' z and w entries matter.
float eye_distance(float depth, int layer) {
    mat4 m = eyes.view_from_clip[layer];
    return -(m[2][2] * depth + m[3][2]) / (m[2][3] * depth + m[3][3]);
}

// The depth-buffer values of the 2x2 pixels block .. block + (1, 1) of texel layer `texel`, in the order
// (0, 0), (1, 0), (0, 1), (1, 1): one gather (texels beyond the image's last row or column repeat its edge, as the
// sampler clamps). Gathering at the block's shared corner picks exactly those four texels.
vec4 block_depths(ivec2 block, int texel, ivec2 size) {
    const vec4 g = textureGather(depth_layers, vec3(vec2(block + 1) / vec2(size), float(texel)), 0);
    return g.wzxy;  // gather order: (0, 1), (1, 1), (1, 0), (0, 0)
}

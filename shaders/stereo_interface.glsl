// shaders/stereo_interface.glsl - resources shared by stereo_mesh.vert and stereo_mesh.frag.
// Mirrors renderer/stereo/stereo_uniforms.hpp and renderer/scene/mesh_vertex.hpp (std140 / push-constant offsets must
// match).

#define MATERIAL_COUNT 8

// Per frame: both eyes' clip-from-world matrices (off-axis frustum, Kooima), eye positions
// (world m, for specular), the direction towards the key light (world, unit), the material
// palette (linear RGBA per material id), and for the ambient-occlusion pass (stereo_ao.comp) each
// eye's view-from-clip matrix (inverse projection; eye space in m, looking along -z), each eye's
// pixels per metre at 1 m distance (x, y) and the occlusion parameters (sphere radius m, strength).
layout(set = 0, binding = 0, std140) uniform Eyes {
    mat4 clip_from_world[2];
    vec4 eye_position[2];
    vec4 light_direction;
    vec4 palette[MATERIAL_COUNT];
    mat4 view_from_clip[2];
    vec4 pixels_per_metre[2];
    vec4 occlusion;
} eyes;

// Per draw: world-from-model transform (m), base colour (linear RGBA), the eye index for the
// pass-per-eye strategy, whether the draw is lit (1) or flat (0), whether the base colour comes
// from the palette by vertex material (1) or from `colour` (0), and whether world_from_model maps
// straight to clip space for both eyes (1: screen-space overlay) or to world space (0), and the eyes that show the
// draw (bit 0 left, bit 1 right; the fragment shader discards the others).
// Compute shaders that only read Eyes define NO_DRAW_CONSTANTS.
#ifndef NO_DRAW_CONSTANTS
layout(push_constant, std430) uniform Draw {
    mat4 world_from_model;
    vec4 colour;
    uint eye;
    uint lit;
    uint palette;
    uint screen_space;
    uint eye_mask;
} draw;
#endif

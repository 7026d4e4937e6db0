// shaders/stereo_interface.glsl - resources shared by stereo_mesh.vert and stereo_mesh.frag.
// Mirrors renderer/stereo/stereo_uniforms.hpp (std140 / push-constant offsets must match).

#define MATERIAL_COUNT 8

// Per frame: both eyes' clip-from-world matrices (off-axis frustum, Kooima), eye positions
// (world m, for specular), the direction towards the light (world, unit) and the material
// palette (linear RGBA per material id).
layout(set = 0, binding = 0, std140) uniform Eyes {
    mat4 clip_from_world[2];
    vec4 eye_position[2];
    vec4 light_direction;
    vec4 palette[MATERIAL_COUNT];
} eyes;

// Per draw: world-from-model transform (m), base colour (linear RGBA), the eye index for the
// pass-per-eye strategy, whether the draw is lit (1) or flat (0), whether the base colour comes
// from the palette by vertex material (1) or from `colour` (0), and whether world_from_model maps
// straight to clip space for both eyes (1: screen-space overlay) or to world space (0).
layout(push_constant, std430) uniform Draw {
    mat4 world_from_model;
    vec4 colour;
    uint eye;
    uint lit;
    uint palette;
    uint screen_space;
} draw;

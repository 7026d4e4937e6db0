// shaders/stereo_interface.glsl - resources shared by stereo_mesh.vert and stereo_mesh.frag.
// Mirrors renderer/stereo_uniforms.hpp (std140 / push-constant offsets must match).

// Per frame: both eyes' clip-from-world matrices (off-axis frustum, Kooima), eye positions
// (world m, for specular) and the direction towards the light (world, unit).
layout(set = 0, binding = 0, std140) uniform Eyes {
    mat4 clip_from_world[2];
    vec4 eye_position[2];
    vec4 light_direction;
} eyes;

// Per draw: world-from-model transform (m), base colour (linear RGBA), the eye index for the
// pass-per-eye strategy, and whether the draw is lit (1) or flat (0).
layout(push_constant, std430) uniform Draw {
    mat4 world_from_model;
    vec4 colour;
    uint eye;
    uint lit;
} draw;

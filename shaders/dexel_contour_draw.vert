#version 450
// shaders/dexel_contour_draw.vert - a GPU contour vertex (grid units + material, compute/gpu_contourer.hpp
// GpuContourVertex) into clip space with one matrix (clip_from_grid = projection * view * world_from_grid).
layout(location = 0) in vec3 in_grid;
layout(location = 1) in uint in_material;

layout(push_constant) uniform Push {
    mat4 clip_from_grid;
} pc;

layout(location = 0) out vec3 out_grid;
layout(location = 1) flat out uint out_material;

void main() {
    out_grid = in_grid;
    out_material = in_material;
    gl_Position = pc.clip_from_grid * vec4(in_grid, 1.0);
}

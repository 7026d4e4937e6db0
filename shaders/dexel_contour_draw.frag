#version 450
// shaders/dexel_contour_draw.frag - flat shading of the contour: the facet normal from screen-space
// derivatives of the grid position, one fixed light, a colour per material id (8 colours, repeating).
layout(location = 0) in vec3 in_grid;
layout(location = 1) flat in uint in_material;
layout(location = 0) out vec4 out_colour;

const vec3 COLOURS[8] = vec3[8](vec3(0.80, 0.62, 0.45), vec3(0.85, 0.20, 0.20), vec3(0.20, 0.70, 0.25),
                                vec3(0.20, 0.35, 0.85), vec3(0.90, 0.80, 0.20), vec3(0.70, 0.30, 0.80),
                                vec3(0.20, 0.75, 0.80), vec3(0.95, 0.95, 0.95));

void main() {
    vec3 n = normalize(cross(dFdx(in_grid), dFdy(in_grid)));
    float light = 0.25 + 0.75 * abs(dot(n, normalize(vec3(0.4, 0.7, 0.6))));
    out_colour = vec4(COLOURS[in_material & 7u] * light, 1.0);
}

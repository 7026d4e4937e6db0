// shaders/anaglyph.frag - the anaglyph of the two eye layers of a stereo colour image, one output pixel per
// fragment, with the arithmetic of the CPU reference renderer::compose (renderer/output/stereo_output.cpp):
//   method 0 (Dubois): 8-bit codes decoded through the sRGB table, mixed by the Dubois matrices in linear
//                      light, re-encoded by the sRGB formula in float and rounded (the reference counts the
//                      code thresholds <= the value in double: a value within float rounding of a threshold
//                      may land on the neighbouring code);
//   method 1 (colour): (L.r, R.g, R.b) of the stored codes;
//   method 2 (gray):   (Y(L), Y(R), Y(R)), Rec. 601 luma (299 r + 587 g + 114 b + 500) / 1000 in integers.
// Alpha is 1. `swap` exchanges the eye layers (layer 0 = left eye).
#version 450

layout(set = 0, binding = 0) uniform sampler2DArray eyes;

// renderer/output/anaglyph_pass.cpp AnaglyphUniform (std140).
layout(set = 0, binding = 1, std140) uniform Tables {
    vec4 left_rows[3];     // Dubois M_L rows (xyz), output r, g, b
    vec4 right_rows[3];    // Dubois M_R rows (xyz)
    vec4 to_linear[64];    // code c decoded: to_linear[c / 4][c % 4]
} tables;

layout(push_constant) uniform Mix {
    int method;
    int swap_eyes;
} mix_;

layout(location = 0) out vec4 colour;

uvec3 codes(int layer) {
    const vec3 v = texelFetch(eyes, ivec3(ivec2(gl_FragCoord.xy), layer), 0).rgb;
    return uvec3(round(v * 255.0));
}

float linear(uint code) { return tables.to_linear[code >> 2][code & 3u]; }

// sRGB encoding (IEC 61966-2-1) of linear light v in [0, 1], as a value 0..1.
float srgb_from_linear(float v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055; }

// The nearest 8-bit sRGB code of linear v, clamped to 0..255. The float formula agrees with the reference's
// exact count of thresholds except within float rounding of a threshold, far below half a code's width.
uint encode(float v) {
    if (!(v > 0.0)) return 0u;
    if (v >= 1.0) return 255u;
    return uint(clamp(round(srgb_from_linear(v) * 255.0), 0.0, 255.0));
}

uint luma601(uvec3 c) { return (299u * c.r + 587u * c.g + 114u * c.b + 500u) / 1000u; }

void main() {
    const uvec3 l = codes(mix_.swap_eyes != 0 ? 1 : 0);
    const uvec3 r = codes(mix_.swap_eyes != 0 ? 0 : 1);
    uvec3 o;
    if (mix_.method == 0) {
        const vec3 ll = vec3(linear(l.r), linear(l.g), linear(l.b));
        const vec3 rl = vec3(linear(r.r), linear(r.g), linear(r.b));
        for (int c = 0; c < 3; ++c)
            o[c] = encode(dot(tables.left_rows[c].xyz, ll) + dot(tables.right_rows[c].xyz, rl));
    } else if (mix_.method == 1) {
        o = uvec3(l.r, r.g, r.b);
    } else {
        const uint yl = luma601(l), yr = luma601(r);
        o = uvec3(yl, yr, yr);
    }
    colour = vec4(vec3(o) / 255.0, 1.0);
}

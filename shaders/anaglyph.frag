// shaders/anaglyph.frag - the anaglyph of the two eye layers of a stereo colour image, one output pixel per
// fragment, with the arithmetic of the CPU reference renderer::compose (renderer/output/stereo_output.cpp):
//   method 0 (Dubois): 8-bit codes decoded through the sRGB table, mixed by the Dubois matrices in linear
//                      light, re-encoded to the nearest code by counting the code thresholds <= the value;
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
    vec4 thresholds[64];   // boundary between codes k and k + 1: thresholds[k / 4][k % 4], k < 255
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
float threshold(uint k) { return tables.thresholds[k >> 2][k & 3u]; }

// Number of thresholds <= v (0..255): the nearest 8-bit sRGB code of linear v, clamped.
uint encode(float v) {
    uint lo = 0u, hi = 255u;  // the answer is in [lo, hi]
    while (lo < hi) {
        const uint mid = (lo + hi) >> 1;  // is threshold(mid) <= v?
        if (threshold(mid) <= v) lo = mid + 1u; else hi = mid;
    }
    return lo;
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

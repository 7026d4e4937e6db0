#version 450
// shaders/stereo_ao_apply.comp - scales the colour layers of a stereo frame's opaque phase by the occlusion
// stereo_ao.comp computed per BLOCK x BLOCK pixels, upsampled with depth-aware bilinear weights (joint bilateral
// upsampling, Kopf et al., "Joint Bilateral Upsampling", SIGGRAPH 2007): each pixel blends the four values around it,
// each weighted by its bilinear weight times max(0, 1 - |z - z_i| / (R / 2)) (z_i the distance of the surface that
// value was computed for, R the occlusion radius), so values from another surface (an edge, the background) do
// not bleed across silhouettes. Pixels no value shares a surface with keep their colour. One invocation per block
// and eye, over the blocks of the region that may hold opaque surface; stereo_ao.comp has filled that region and a
// ring of one block around it.
#extension GL_GOOGLE_include_directive : require
#include "stereo_ao_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

void main() {
    ivec2 size = textureSize(depth_layers, 0).xy;
    ivec2 half_size = imageSize(half_occlusion).xy;
    ivec2 t = ivec2(gl_GlobalInvocationID.xy) + pass.origin;
    ivec2 block = t * BLOCK;
    if (block.x >= size.x || block.y >= size.y) return;
    int layer = int(pass.first_eye + gl_GlobalInvocationID.z);
    int texel = int(pass.first_texel + gl_GlobalInvocationID.z);
    float z[BLOCK * BLOCK];  // per pixel (a, b) of the block at a + BLOCK * b: distance, m; -1 = no surface
    bool any = false;
    for (int j = 0; j < BLOCK; j += 2) {
        for (int i = 0; i < BLOCK; i += 2) {
            const ivec2 q = block + ivec2(i, j);  // a 2x2 quad of the block, read with one gather
            const vec4 depths = block_depths(q, texel, size);
            for (int k = 0; k < 4; ++k) {
                const int a = i + (k & 1), b = j + (k >> 1);
                ivec2 p = block + ivec2(a, b);
                z[a + BLOCK * b] = -1.0;
                if (p.x >= size.x || p.y >= size.y) continue;
                float depth = depths[k];
                if (depth >= 1.0) continue;
                z[a + BLOCK * b] = eye_distance(depth, layer);
                any = any || z[a + BLOCK * b] > 0.0;
            }
        }
    }
    if (!any) return;  // background only
    vec2 v[9];  // the 3x3 block values around this block: (scale, distance)
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            v[j * 3 + i] = imageLoad(half_occlusion, ivec3(clamp(t + ivec2(i - 1, j - 1), ivec2(0), half_size - 1),
                                                         layer)).xy;
    float tolerance = 0.5 * eyes.occlusion.x;
    // Pixel (a, b) of the block lies (a + 0.5) / BLOCK - 0.5 texels from this block's value along x (likewise y),
    // towards the neighbour on that side: bilinear weights (1 - fx)(1 - fy) for this block, fx (1 - fy) and
    // (1 - fx) fy for the edge neighbours, fx fy for the diagonal one (BLOCK 2: 9/16, 3/16, 3/16, 1/16).
    for (int b = 0; b < BLOCK; ++b) {
        for (int a = 0; a < BLOCK; ++a) {
            const float zk = z[a + BLOCK * b];
            if (!(zk > 0.0)) continue;
            const vec2 d = (vec2(a, b) + 0.5) / float(BLOCK) - 0.5;
            const ivec2 o = ivec2(sign(d));  // -1 or +1 per axis (never 0)
            const vec2 f = abs(d);
            int idx[4] = int[](4, 4 + o.x, 4 + 3 * o.y, 4 + o.x + 3 * o.y);
            const float bilinear[4] = float[]((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
            float sum = 0.0, weight = 0.0;
            for (int n = 0; n < 4; ++n) {
                vec2 s = v[idx[n]];
                float w = bilinear[n] * max(0.0, 1.0 - abs(zk - s.y) / tolerance);
                sum += w * s.x;
                weight += w;
            }
            if (weight <= 1e-4) continue;
            float scale = sum / weight;
            ivec3 at = ivec3(block + ivec2(a, b), texel);
            vec4 c = imageLoad(colour_layers, at);
            imageStore(colour_layers, at, vec4(min(c.rgb * scale, vec3(1.0)), c.a));
        }
    }
}

#version 450
// shaders/stereo_ao_apply.comp - scales the colour layers of a stereo frame's opaque phase by the half-resolution
// occlusion of stereo_ao.comp, upsampled with depth-aware bilinear weights (joint bilateral upsampling, Kopf et
// al., "Joint Bilateral Upsampling", SIGGRAPH 2007): each pixel blends the four half-resolution values around it,
// each weighted by its bilinear weight times max(0, 1 - |z - z_i| / (R / 2)) (z_i the distance of the surface that
// value was computed for, R the occlusion radius), so values from another surface (an edge, the background) do
// not bleed across silhouettes. Pixels no value shares a surface with keep their colour. One invocation per 2x2 pixel block and eye, over the blocks of the
// region that may hold opaque surface; stereo_ao.comp has filled that region and a ring of one block around it.
#extension GL_GOOGLE_include_directive : require
#include "stereo_ao_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

void main() {
    ivec2 size = textureSize(depth_layers, 0).xy;
    ivec2 half_size = imageSize(half_occlusion).xy;
    ivec2 t = ivec2(gl_GlobalInvocationID.xy) + pass.origin;
    ivec2 block = t * 2;
    if (block.x >= size.x || block.y >= size.y) return;
    int layer = int(pass.first_eye + gl_GlobalInvocationID.z);
    int texel = int(pass.first_texel + gl_GlobalInvocationID.z);
    float z[4];
    bool any = false;
    const vec4 depths = block_depths(block, texel, size);
    for (int k = 0; k < 4; ++k) {
        ivec2 p = block + ivec2(k & 1, k >> 1);
        z[k] = -1.0;
        if (p.x >= size.x || p.y >= size.y) continue;
        float depth = depths[k];
        if (depth >= 1.0) continue;
        z[k] = eye_distance(depth, layer);
        any = any || z[k] > 0.0;
    }
    if (!any) return;  // background only
    vec2 v[9];  // the 3x3 half-resolution values around this block: (scale, distance)
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            v[j * 3 + i] = imageLoad(half_occlusion, ivec3(clamp(t + ivec2(i - 1, j - 1), ivec2(0), half_size - 1),
                                                         layer)).xy;
    float tolerance = 0.5 * eyes.occlusion.x;
    // Pixel (a, b) of the block lies a quarter texel from this block's value towards neighbour (2a - 1, 2b - 1):
    // bilinear weights 9/16 (this block), 3/16 (each edge neighbour) and 1/16 (the diagonal one).
    for (int k = 0; k < 4; ++k) {
        if (!(z[k] > 0.0)) continue;
        ivec2 ab = ivec2(k & 1, k >> 1);
        ivec2 o = ab * 2 - 1;  // -1 or +1 per axis
        int idx[4] = int[](4, 4 + o.x, 4 + 3 * o.y, 4 + o.x + 3 * o.y);
        const float bilinear[4] = float[](0.5625, 0.1875, 0.1875, 0.0625);
        float sum = 0.0, weight = 0.0;
        for (int n = 0; n < 4; ++n) {
            vec2 s = v[idx[n]];
            float w = bilinear[n] * max(0.0, 1.0 - abs(z[k] - s.y) / tolerance);
            sum += w * s.x;
            weight += w;
        }
        if (weight <= 1e-4) continue;
        float scale = sum / weight;
        ivec3 at = ivec3(block + ab, texel);
        vec4 c = imageLoad(colour_layers, at);
        imageStore(colour_layers, at, vec4(min(c.rgb * scale, vec3(1.0)), c.a));
    }
}

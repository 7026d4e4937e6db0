#version 450
// shaders/stereo_ao.comp - volumetric obscurance (Loos and Sloan, "Volumetric Obscurance", I3D 2010) of the
// opaque phase of a stereo frame, applied in place to the colour layers.
// For each covered pixel (depth < 1) at eye-space point P (distance z = -P.z in front of the eye) a sphere of
// radius R around P is sampled along 16 line samples parallel to the view axis, at the offsets of a fixed disk
// pattern in symmetric pairs (+u, -u). Each line's chord of the sphere has half-length h = R sqrt(1 - |u|^2);
// the part of the chord behind the surface seen at that offset (the solid, read from the depth layer) is
// occupied. The obscurance is occupied / total length: 0.5 on any plane, more in a concave cut (groove floor,
// the foot of a ridge), less on a convex edge or crest. The colour is scaled by 1 + strength * (1 - 2 obscurance),
// clamped to 0.3..1.45: cuts darken, edges and crests brighten, flat faces keep their colour.
// Samples whose surface lies more than 2R in front of P (another object in front) are left out; samples on the
// background count as empty. One invocation per 2x2 pixel block and eye: z = eye - first_eye.
#extension GL_GOOGLE_include_directive : require
#define NO_DRAW_CONSTANTS 1
#include "stereo_interface.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(set = 0, binding = 1) uniform sampler2DArray depth_layers;   // D32, DEPTH_STENCIL_READ_ONLY_OPTIMAL
layout(set = 0, binding = 2, rgba8) uniform image2DArray colour_layers;  // GENERAL

layout(push_constant, std430) uniform Pass {
    uint first_eye;    // eye (0 left, 1 right) of invocation z = 0
    uint first_texel;  // its layer in the bound views (0 when they hold that one layer only)
} pass;

const int kPairs = 8;
// Disk offsets (unit radius), a golden-angle spiral: radius sqrt((i + 0.5) / 8), angle i * 2.39996 rad.
const vec2 kDisk[kPairs] = vec2[](vec2(0.2500, 0.0000), vec2(-0.3193, 0.2925), vec2(0.0489, -0.5569),
                                  vec2(0.4024, 0.5249), vec2(-0.7385, -0.1306), vec2(0.6996, -0.4450),
                                  vec2(-0.2340, 0.8705), vec2(-0.4463, -0.8593));

// Distance in front of the eye (m) of the surface with depth-buffer value `depth` in eye `layer`. The inverse of a
// perspective (off-axis) projection maps clip z and w to eye z and w independently of clip x and y, so only its
// third and fourth rows' z and w entries matter.
float eye_distance(float depth, int layer) {
    mat4 m = eyes.view_from_clip[layer];
    return -(m[2][2] * depth + m[3][2]) / (m[2][3] * depth + m[3][3]);
}

// The colour scale of the surface point seen at pixel p (distance z in front of eye `layer`): 1 + strength *
// (1 - 2 obscurance), clamped; 1 when the sphere covers less than a pixel or no sample counts.
float occlusion_scale(ivec2 p, float z, int layer, int texel, ivec2 size) {
    float radius = eyes.occlusion.x, strength = eyes.occlusion.y;
    vec2 radius_px = radius * eyes.pixels_per_metre[layer].xy / z;
    if (max(radius_px.x, radius_px.y) < 1.0) return 1.0;  // the sphere is within one pixel: nothing to resolve
    float occupied = 0.0, total = 0.0;
    for (int i = 0; i < kPairs; ++i) {
        float h = radius * sqrt(max(1.0 - dot(kDisk[i], kDisk[i]), 0.0));
        for (int s = -1; s <= 1; s += 2) {
            ivec2 q = p + ivec2(round(float(s) * kDisk[i] * radius_px));
            if (q.x < 0 || q.y < 0 || q.x >= size.x || q.y >= size.y) continue;
            float dq = texelFetch(depth_layers, ivec3(q, texel), 0).r;
            float filled = 0.0;
            if (dq < 1.0) {
                float zq = eye_distance(dq, layer);
                if (z - zq > 2.0 * radius) continue;  // an object well in front: not this surface's shape
                filled = clamp(z + h - max(zq, z - h), 0.0, 2.0 * h);
            }
            occupied += filled;
            total += 2.0 * h;
        }
    }
    if (total <= 0.0) return 1.0;
    return clamp(1.0 + strength * (1.0 - 2.0 * occupied / total), 0.3, 1.45);
}

// One invocation per 2x2 pixel block: the obscurance varies over the sphere's size, not from pixel to pixel, so a
// block's pixels share one evaluation unless their distances differ by more than a tenth of the radius (an edge).
void main() {
    ivec2 size = imageSize(colour_layers).xy;
    ivec2 block = ivec2(gl_GlobalInvocationID.xy) * 2;
    if (block.x >= size.x || block.y >= size.y) return;
    int layer = int(pass.first_eye + gl_GlobalInvocationID.z);
    int texel = int(pass.first_texel + gl_GlobalInvocationID.z);
    float known_z = -1.0, known_scale = 1.0;
    for (int k = 0; k < 4; ++k) {
        ivec2 p = block + ivec2(k & 1, k >> 1);
        if (p.x >= size.x || p.y >= size.y) continue;
        float depth = texelFetch(depth_layers, ivec3(p, texel), 0).r;
        if (depth >= 1.0) continue;
        float z = eye_distance(depth, layer);
        if (!(z > 0.0)) continue;
        if (known_z < 0.0 || abs(z - known_z) > 0.1 * eyes.occlusion.x) {
            known_scale = occlusion_scale(p, z, layer, texel, size);
            known_z = z;
        }
        vec4 c = imageLoad(colour_layers, ivec3(p, texel));
        imageStore(colour_layers, ivec3(p, texel), vec4(min(c.rgb * known_scale, vec3(1.0)), c.a));
    }
}

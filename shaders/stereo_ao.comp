#version 450
// shaders/stereo_ao.comp - volumetric obscurance (Loos and Sloan, "Volumetric Obscurance", I3D 2010) of the
// opaque phase of a stereo frame at half or quarter resolution: one evaluation per BLOCK x BLOCK pixel block and
// eye, written to half_occlusion; stereo_ao_apply.comp then scales the colour layers with it.
// The block is represented by its nearest surface point P (distance z = -P.z in front of the eye). A sphere of
// radius R around P is sampled along 8 line samples parallel to the view axis, at the offsets of a fixed disk
// pattern in symmetric pairs (+u, -u) (a pattern turned from block to block would show as noise on faces seen at
// grazing angles, where the depth-aware upsampling cannot blend neighbouring blocks). Each line's
// chord of the sphere has half-length h = R sqrt(1 - |u|^2); the part of the chord behind the surface seen at
// that offset (the solid, read from the depth layer) is occupied. The obscurance is occupied / total length: 0.5
// on any plane, more in a concave cut (groove floor, the foot of a ridge), less on a convex edge or crest. The
// colour scale is 1 + strength * (1 - 2 obscurance), clamped to 0.3..1.45: cuts darken, edges and crests
// brighten, flat faces keep their colour. Pairs with a sample whose surface lies more than 2R in front of P
// (another object in front) are left out; samples on the background count as empty. A pair reaching past the
// image's edge is drawn in towards P (its offsets scaled until both samples lie inside, its chord the sphere's at
// the smaller offset), so the obscurance changes smoothly up to the edge, where it reaches one half, instead of
// stepping where a pair's offset leaves the image (close up, where R covers many pixels, those steps showed as
// rectangles inset from the image's edges).
// Dispatched over the blocks of the region that may hold opaque surface plus a ring of one block (the neighbours
// stereo_ao_apply.comp reads).
#extension GL_GOOGLE_include_directive : require
#include "stereo_ao_common.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

const int kPairs = 4;
// Disk offsets (unit radius), a golden-angle spiral: radius sqrt((i + 0.5) / 4), angle i * 2.39996 rad.
const vec2 kDisk[kPairs] = vec2[](vec2(0.3536, 0.0000), vec2(-0.4516, 0.4137), vec2(0.0692, -0.7876),
                                  vec2(0.5691, 0.7424));

// The colour scale of the surface point seen at pixel p (distance z in front of eye `layer`): 1 + strength *
// (1 - 2 obscurance), clamped; 1 when the sphere covers less than a pixel or no pair counts. A pair counts only
// when both its samples do (inside the image, no object well in front), so that any plane, even one seen at a
// grazing angle, stays at exactly one half.
float occlusion_scale(ivec2 p, float z, int layer, int texel, ivec2 size) {
    float radius = eyes.occlusion.x, strength = eyes.occlusion.y;
    vec2 radius_px = radius * eyes.pixels_per_metre[layer].xy / z;
    if (max(radius_px.x, radius_px.y) < 1.0) return 1.0;  // the sphere is within one pixel: nothing to resolve
    float occupied = 0.0, total = 0.0;
    vec2 room = vec2(min(p, size - 1 - p));  // pixels from p to the image's nearer edge, per axis
    for (int i = 0; i < kPairs; ++i) {
        vec2 reach = abs(kDisk[i] * radius_px);
        float shrink = 1.0;  // the pair's offsets scaled by this keep both samples inside the image
        if (reach.x > room.x) shrink = min(shrink, room.x / reach.x);
        if (reach.y > room.y) shrink = min(shrink, room.y / reach.y);
        vec2 u = kDisk[i] * shrink;
        float h = radius * sqrt(max(1.0 - dot(u, u), 0.0));
        ivec2 d = clamp(ivec2(round(u * radius_px)), -ivec2(room), ivec2(room));
        ivec2 qa = p + d, qb = p - d;
        float filled = 0.0;
        bool counts = true;
        for (int s = 0; s < 2; ++s) {
            float dq = texelFetch(depth_layers, ivec3(s == 0 ? qa : qb, texel), 0).r;
            if (dq >= 1.0) continue;  // background: empty
            float zq = eye_distance(dq, layer);
            counts = counts && z - zq <= 2.0 * radius;  // an object well in front: not this surface's shape
            filled += clamp(z + h - max(zq, z - h), 0.0, 2.0 * h);
        }
        if (!counts) continue;
        occupied += filled;
        total += 4.0 * h;
    }
    if (total <= 0.0) return 1.0;
    return clamp(1.0 + strength * (1.0 - 2.0 * occupied / total), 0.3, 1.45);
}

void main() {
    ivec2 size = textureSize(depth_layers, 0).xy;
    ivec2 t = ivec2(gl_GlobalInvocationID.xy) + pass.origin;
    ivec2 block = t * BLOCK;
    if (block.x >= size.x || block.y >= size.y) return;
    int layer = int(pass.first_eye + gl_GlobalInvocationID.z);
    int texel = int(pass.first_texel + gl_GlobalInvocationID.z);
    float near_z = 1e30;
    ivec2 near_p = block;
    for (int j = 0; j < BLOCK; j += 2) {
        for (int i = 0; i < BLOCK; i += 2) {
            const ivec2 q = block + ivec2(i, j);  // a 2x2 quad of the block, read with one gather
            if (q.x >= size.x || q.y >= size.y) continue;
            const vec4 depths = block_depths(q, texel, size);
            for (int k = 0; k < 4; ++k) {
                ivec2 p = q + ivec2(k & 1, k >> 1);
                if (p.x >= size.x || p.y >= size.y) continue;
                float depth = depths[k];
                if (depth >= 1.0) continue;
                float z = eye_distance(depth, layer);
                if (z > 0.0 && z < near_z) {
                    near_z = z;
                    near_p = p;
                }
            }
        }
    }
    vec4 result = vec4(1.0, -1.0, 0.0, 0.0);
    if (near_z < 1e30) {
        result.x = occlusion_scale(near_p, near_z, layer, texel, size);
        result.y = near_z;
    }
    imageStore(half_occlusion, ivec3(t, layer), result);
}

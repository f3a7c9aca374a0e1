#version 450
// lod_zoom's renderer: one invocation per sample of the prefix drawn this frame, each a disk of
// `disk` pixels around its position in the view, or-ed into a 32-bit-per-pixel image.
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Samples { vec4 sample_at[]; };  // x, y, t, radius
layout(std430, binding = 1) buffer Image { uint pixel[]; };
layout(push_constant) uniform View {
    vec2 origin;   // the view's lower-left corner, in box units
    float scale;   // pixels per box unit
    float disk;    // disk radius in pixels
    uint count;    // the prefix drawn
    uint size;     // the image is size x size pixels
};

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    vec2 p = (sample_at[i].xy - origin) * scale;
    int r = int(ceil(disk));
    for (int dy = -r; dy <= r; dy++)
        for (int dx = -r; dx <= r; dx++) {
            ivec2 q = ivec2(floor(p)) + ivec2(dx, dy);
            if (q.x < 0 || q.y < 0 || q.x >= int(size) || q.y >= int(size)) continue;
            vec2 centre = vec2(q) + 0.5;
            if (distance(centre, p) > disk) continue;
            atomicOr(pixel[(size - 1u - uint(q.y)) * size + uint(q.x)], 1u);  // row 0 at the top
        }
}

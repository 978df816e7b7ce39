// Integer hashing (PCG, Jarzynski & Olano 2020): the same bits as cityshade/interior/_hash.py,
// so per-room randomness on the GPU and in the numpy twins agrees exactly.
#ifndef COMMON_HASH_GLSL
#define COMMON_HASH_GLSL

uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Hash of an integer lattice point plus a salt: the "3D noise" that picks per-room values.
uint hash3(ivec3 p, uint salt) {
    return pcg_hash(uint(p.x) ^ pcg_hash(uint(p.y) ^ pcg_hash(uint(p.z) ^ pcg_hash(salt))));
}

// Uniform value in [0, 1) from the top 24 bits (exact in float32).
float unit_float(uint h) {
    return float(h >> 8u) * (1.0 / 16777216.0);
}

#endif

// Random access to a facade's detail maps D, M, A (paper §5-6), one codec per #define:
//   CODEC_RAW  uncompressed integer textures
//   CODEC_SVD  float X, S, Y: map(i, j) = round(sum_k X[i,k] S[k] Y[j,k])
//   CODEC_BMF  binary X, Y packed 32 terms per R32UI texel, float S: the sum runs over the set
//              bits of X[i] & Y[j], found with findLSB (or, with BMF_LSB_MOD37, the paper's
//              modulo-37 discrete-log table)
// Maps are indexed by MAP_DEPTH / MAP_MATERIAL / MAP_BOXES; cells are (column, row).

#define MAP_DEPTH 0
#define MAP_MATERIAL 1
#define MAP_BOXES 2

#if defined CODEC_RAW
uniform usampler2D u_raw[3];

uint relief_fetch(int map, ivec2 cell) {
    return texelFetch(u_raw[map], cell, 0).r;
}

#elif defined CODEC_SVD
uniform sampler2D u_svd_x[3];  // (terms, rows)
uniform sampler2D u_svd_y[3];  // (terms, columns)
uniform sampler2D u_svd_s[3];  // (terms, 1)
uniform int u_terms[3];

uint relief_fetch(int map, ivec2 cell) {
    float sum = 0.0;
    for (int k = 0; k < u_terms[map]; k++) {
        sum += texelFetch(u_svd_x[map], ivec2(k, cell.y), 0).r * texelFetch(u_svd_s[map], ivec2(k, 0), 0).r
             * texelFetch(u_svd_y[map], ivec2(k, cell.x), 0).r;
    }
    return uint(max(round(sum), 0.0));
}

#elif defined CODEC_BMF
// Texture arrays, layer = map, each layer zero-padded to the largest map's size.
uniform usampler2DArray u_bmf_x;  // (ceil(terms / 32), rows), term k in bit k % 32 of word k / 32
uniform usampler2DArray u_bmf_y;  // (ceil(terms / 32), columns)
uniform sampler2DArray u_bmf_s;   // (terms, 1)
uniform int u_words[3];

#if defined BMF_LSB_MOD37
// 2 is a primitive root modulo 37, so (1 << k) % 37 is distinct for k < 32: a table inverts it.
const int DISCRETE_LOG37[37] = int[37](0, 0, 1, 26, 2, 23, 27, 0, 3, 16, 24, 30, 28, 11, 0, 13, 4, 7, 17, 0,
                                       25, 22, 31, 15, 29, 10, 12, 6, 0, 21, 14, 9, 5, 20, 8, 19, 18);
int lowest_set_bit(uint bits) { return DISCRETE_LOG37[(bits & (~bits + 1u)) % 37u]; }
#else
int lowest_set_bit(uint bits) { return findLSB(bits); }
#endif

uint relief_fetch(int map, ivec2 cell) {
    float sum = 0.0;
    for (int w = 0; w < u_words[map]; w++) {
        uint bits = texelFetch(u_bmf_x, ivec3(w, cell.y, map), 0).r & texelFetch(u_bmf_y, ivec3(w, cell.x, map), 0).r;
        // At most 32 rounds: each clears one bit. (A `b < 32` counter makes compilers unroll all
        // 32 rounds, several times slower on llvmpipe.)
        while (bits != 0u) {
            sum += texelFetch(u_bmf_s, ivec3(w * 32 + lowest_set_bit(bits), 0, map), 0).r;
            bits &= bits - 1u;  // knock out the bit just used
        }
    }
    return uint(sum + 0.5);
}
#endif

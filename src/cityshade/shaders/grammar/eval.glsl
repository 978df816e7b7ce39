// Per-pixel evaluation of a compiled facade grammar (Krecklau & Kobbelt 2011, §3.1 and §4).
// The numpy twin is cityshade/grammar/_reference.py: keep the two in step.
//
// Inputs per pixel: start rule address, facade point uv (metres), facade size, seed vector s and
// the view ray in facade tangent space (x right, y up, z into the wall). Every loop is bounded
// by the GRAMMAR_MAX_* defines, so no grammar can hang the GPU.

#ifndef GRAMMAR_MAX_STEPS
#error "GRAMMAR_MAX_* defines come from cityshade.grammar._limits.DEFINES"
#endif

#if GRAMMAR_MAX_PARAMS != 4
#error "the parameters are kept in a vec4"
#endif

#if GRAMMAR_MAX_LAYERS != 4
#error "the layer frames are four variables and an ivec4 (f_frame0..3, f_index)"
#endif

#if GRAMMAR_MAX_STACK != 8 || GRAMMAR_MAX_EXPR_STACK != 8
#error "the random-seed stack is four vec4 (g_stack01..67), the expression stack two (g_values_lo, _hi)"
#endif

#define GRAMMAR_NOISE_SIZE 256
#define GRAMMAR_NOISE_DENSITY 8.0
#define GRAMMAR_OPAQUE 0.999
#define GRAMMAR_BIG 1e30
#define GRAMMAR_REPEAT_SLACK 1e-4

layout(std430, binding = BINDING_GRAMMAR_RULES) readonly buffer GrammarRules { vec4 grammar_rules[]; };  // by address
uniform sampler2D u_grammar_noise;      // R32F uniform noise
uniform sampler2DArray u_grammar_tiles; // RGBA8, layer = 3 * tile + usage - 1
uniform int u_grammar_tile_size;        // texels per tile side (a power of two)
uniform int u_grammar_tile_labels[64];

struct GrammarResult {
    vec3 color;
    float alpha;
    vec3 normal;    // tangent space
    vec2 specular;  // intensity, shininess / 128
    int terminal;   // address of the winning Mat, -1 for none
    int tile;       // its tile, -1 for a constant colour
    int label;
    bool glass;
    vec4 scope;     // the winning Mat's scope: its lower left in facade uv (layers' translations undone), its size
    bool view_dependent;  // an Intrusion was entered: the result depends on the view ray
    int hole;       // address of the last SkipMask that cut a hole here (skipped more layers than its
                    // other bit would), -1 for none: a window that is a hole, with what shows through it
    vec4 hole_scope;  // that SkipMask's scope, as scope
};

// ---- evaluation state (private to the invocation) -------------------------------------------
int g_addr;
vec2 g_lb, g_size, g_t, g_s;
vec2 g_split;   // split.index and split.total of the last Split or Repeat (0, 1 at the start)
vec2 g_facade;  // the start scope's size: facade.width, facade.height
vec3 g_tint;  // Tint's factor for colour Mats (1 unless tinted)
vec4 g_params;  // the parameters of the rule being evaluated (0 unless passed; GRAMMAR_MAX_PARAMS is 4)
// building.levels, .style, .use and .height for conditions: set by the caller before grammar_evaluate.
vec4 grammar_building = vec4(0.0);
// facade.level, the storey the face's bottom sits at (0 on the ground): set by the caller.
float grammar_level = 0.0;
// The building's seed vector (set by callers that know it): the random-seed stack's entry 0, so a
// Rand with l >= 1 and no RandStack entry decides once per building. Not set: the facade's seed.
vec2 grammar_building_seed = vec2(0.0);
// Seen through a hole (set by the caller, for one grammar_evaluate, which resets it): the address of
// a SkipMask. The layers above it contribute nothing, and it cuts its hole whatever its mask says, so
// the result is what the hole shows at this point (the recessed hole's room, relief/building.glsl).
int grammar_through = -1;
vec3 g_d;
vec2 g_dtdx, g_dtdy;
// The random-seed stack: two entries in each vec4, read and written through selects (as the
// layer frames below).
vec4 g_stack01, g_stack23, g_stack45, g_stack67;
int g_sp;
int g_depth;
// The entered Layers' frames: the scope their layers start from. Four named frames picked by
// selects (grammar_frame), not an array: llvmpipe reads and writes a dynamically indexed array
// through memory, lane by lane, which cost more than the rest of a step.
struct LayerFrame {
    vec4 lb_size, t_split;
    vec4 params;  // GRAMMAR_MAX_PARAMS is 4
    vec3 d, tint;
    int addr, sp;
};
LayerFrame f_frame0, f_frame1, f_frame2, f_frame3;
ivec4 f_index;  // per frame, the layer entered last
bool g_active;
int g_end;  // the layer ends after this step, skipping this many more layers; -1: it goes on
bool g_view_dependent;
vec3 g_C, g_N;
float g_A, g_AN, g_AS, g_best_w;
float g_AE;  // colour alpha composited from exact (nearest-texel) alphas: it picks the terminal
vec2 g_S;
int g_best_addr, g_best_tile;
ivec2 g_best_texel;
vec4 g_best_scope;  // the winning Mat's scope (GrammarResult.scope)
int g_through;       // grammar_through for this evaluation, -1 once its SkipMask is passed
int g_hole;          // GrammarResult.hole
vec4 g_hole_scope;
vec2 g_uv;  // the pixel's facade uv

vec4 grammar_texel(int address) {
    return grammar_rules[address];
}

float grammar_channel(int address, int index) {
    return grammar_texel(address + index / 4)[index % 4];
}

// The noise at a corner in rule `stream`'s own stream (its address hashed to a cell offset,
// as cityshade.grammar._random.stream_offset).
float grammar_random(vec2 corner, int stream) {
    uint h = uint(stream) * 0x9E3779B1u;
    h ^= h >> 15;
    h *= 0x85EBCA77u;
    ivec2 c = ivec2(floor(corner * GRAMMAR_NOISE_DENSITY + 0.5)) + ivec2((h >> 8) & 255u, h >> 24);
    ivec2 p = ivec2((c.x + c.y * 37) & (GRAMMAR_NOISE_SIZE - 1), c.y & (GRAMMAR_NOISE_SIZE - 1));
    return texelFetch(u_grammar_noise, p, 0).r;
}

// The seed cells of facade `face` of a building whose seed cells are `cells`
// (cityshade.grammar._random.facade_cells): facade 0 keeps them, the others hash them with their index.
ivec2 grammar_facade_cells(ivec2 cells, int face) {
    if (face == 0) return cells;
    uint h = (uint(cells.x) | (uint(cells.y) << 11)) ^ (uint(face) * 0x9E3779B1u);
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    h ^= h >> 16;
    return ivec2(1u + h % 2047u, 1u + (h >> 11) % 2047u);
}

// Mat's sampling: a constant (code 0), a tile fitted to the scope (> 0) or tiled (< 0).
// exact_alpha is the alpha of the nearest texel: labels and layer decisions use it in both modes,
// so they equal the numpy twin's, while the returned colour is filtered (mipmapped).
vec4 grammar_sample(int code, int usage, vec4 params, out ivec2 texel, out int tile, out float exact_alpha) {
    texel = ivec2(0);
    tile = -1;
    exact_alpha = params.a;
    if (code == 0) return params;
    tile = abs(code) - 1;
    int r = u_grammar_tile_size;
    bool fit = code > 0;
    vec2 uv = fit ? params.xy + (g_t - g_lb) / g_size * (params.zw - params.xy) : g_t * params.zw + params.xy;
    ivec2 ix = ivec2(floor(uv * float(r)));
    texel = fit ? clamp(ix, ivec2(0), ivec2(r - 1)) : (ix & ivec2(r - 1));
    int layer = 3 * tile + usage - 1;
    vec4 exact = texelFetch(u_grammar_tiles, ivec3(texel, layer), 0);
    exact_alpha = exact.a;
#ifdef GRAMMAR_NEAREST
    return exact;
#else
    // Derivatives come from the facade uv (taken before any branching) scaled to this mapping.
    vec2 k = fit ? (params.zw - params.xy) / g_size : params.zw;
    float half_texel = 0.5 / float(r);
    vec2 st = fit ? clamp(uv, vec2(half_texel), vec2(1.0 - half_texel)) : uv;
    return textureGrad(u_grammar_tiles, vec3(st, float(layer)), g_dtdx * k, g_dtdy * k);
#endif
}

LayerFrame grammar_frame(int k) {
    return k == 0 ? f_frame0 : (k == 1 ? f_frame1 : (k == 2 ? f_frame2 : f_frame3));
}

// Enters Layer `addr` with `layers` layers at the current scope.
void grammar_enter_layer(int addr, int layers) {
    int top = min(g_depth, GRAMMAR_MAX_LAYERS - 1);
    LayerFrame f = LayerFrame(vec4(g_lb, g_size), vec4(g_t, g_split), g_params, g_d, g_tint, addr, g_sp);
    if (top == 0) f_frame0 = f;
    else if (top == 1) f_frame1 = f;
    else if (top == 2) f_frame2 = f;
    else f_frame3 = f;
    f_index[top] = layers;
    g_depth = top + 1;
}

// The current layer is done, skipping `skip` more: enter the next layer below, or finish.
void grammar_end_layer(int skip) {
    for (int i = 0; i <= GRAMMAR_MAX_LAYERS; ++i) {
        if (g_depth == 0) {
            g_active = false;
            return;
        }
        int index = f_index[g_depth - 1] - 1 - skip;
        f_index[g_depth - 1] = index;
        if (index >= 0) break;
        g_depth -= 1;  // this Layer is exhausted: continue below it in the enclosing one
        skip = 0;
    }
    int index = f_index[g_depth - 1];
    LayerFrame f = grammar_frame(g_depth - 1);
    vec2 offset = float(index + 1) * g_s;  // layer i is translated by i * s
    g_lb = f.lb_size.xy + offset;
    g_size = f.lb_size.zw;
    g_t = f.t_split.xy + offset;
    g_split = f.t_split.zw;
    g_params = f.params;
    g_d = f.d;
    g_sp = f.sp;
    g_tint = f.tint;
    g_addr = int(grammar_channel(f.addr, 2 + index));
}

// A size drawn from rand(low, high) for this scope: the rule's part `part` has its own stream.
float grammar_drawn(float low, float high, int part) {
    return low + (high - low) * grammar_random(g_lb, g_addr + GRAMMAR_PART_STREAMS * (part + 1));
}

// `noise`: the step's draw (grammar_step_noise), part 0's stream.
void grammar_repeat(vec4 head, int a, float noise) {
    float size = g_size[a];
    // head.w: 1 (or 3) the paper's ceil, else the nearest count (half up); 2 (or 3) a rand size.
    float v = head.w >= 2.0 ? head.y + (grammar_texel(g_addr + 1).x - head.y) * noise : head.y;
    float ratio = size / v;
    float count = max(mod(head.w, 2.0) == 1.0 ? ceil(ratio - GRAMMAR_REPEAT_SLACK) : floor(ratio + 0.5), 1.0);
    float w = size / count;
    float i = clamp(floor((g_t[a] - g_lb[a]) / w), 0.0, count - 1.0);
    g_lb[a] = g_lb[a] + i * w;
    g_split = vec2(i, count);
    g_size[a] = w;
    g_addr = int(head.z);
}

// Split (eq. 1) with floating parts: absolute parts keep their size, relative parts and the
// copies of the Tile part (if any; -n in head.y, its size in the next texel) share the rest with
// one scale; the tile is repeated the nearest whole number of times, at least once.
// With rand sizes (GRAMMAR_RANDOM_PARTS added to n) each part's size is drawn per scope and the
// sums of the absolute and floating sizes are made here, in a first loop over the parts.
float grammar_part_size(float sv, bool random, int highs, int i) {
    return random ? grammar_drawn(abs(sv), grammar_channel(highs, i), i) : abs(sv);
}

void grammar_split(vec4 head, int a) {
    bool tiled = head.y < 0.0;
    int n = int(abs(head.y));
    bool random = n >= GRAMMAR_RANDOM_PARTS;
    n -= random ? GRAMMAR_RANDOM_PARTS : 0;
    int first = g_addr + (tiled ? 2 : 1);
    int highs = first + (n + 1) / 2;
    float size = g_size[a];
    float absolute = head.w;
    float relative = head.z;
    if (random) {
        absolute = 0.0;
        relative = 0.0;
        for (int i = 0; i < GRAMMAR_MAX_PARTS && i < n; ++i) {
            vec4 part = grammar_texel(first + i / 2);
            float sv = (i % 2 == 0) ? part.x : part.z;
            float ref = (i % 2 == 0) ? part.y : part.w;
            float drawn = grammar_part_size(sv, true, highs, i);
            absolute += sv < 0.0 ? drawn : 0.0;
            relative += (sv > 0.0 && ref >= 0.0) ? drawn : 0.0;
        }
    }
    float tile = tiled ? grammar_texel(g_addr + 1).x : 0.0;
    float count = tiled ? max(floor((size - absolute - relative) / tile + 0.5), 1.0) : 0.0;
    float floating = relative + count * tile;
    float scale = floating > 0.0 ? max(size - absolute, 0.0) / floating : 0.0;
    float pos = g_lb[a];
    float t = g_t[a];
    bool after_tile = false;
    bool found = false;
    bool over = false;  // an Overhang part reaches t: the last one is drawn over the others
    vec3 chosen = vec3(0.0);  // the part's index, lower end and size; set after the loop, which draws from g_lb
    int target = 0;
    for (int i = 0; i < GRAMMAR_MAX_PARTS && i < n; ++i) {
        vec4 part = grammar_texel(first + i / 2);
        float sv = (i % 2 == 0) ? part.x : part.z;
        float ref = (i % 2 == 0) ? part.y : part.w;
        float drawn = grammar_part_size(sv, random && ref >= 0.0, highs, i);
        float w = sv < 0.0 ? drawn : drawn * scale;
        bool is_tile = ref < 0.0;
        float span = is_tile ? w * count : w;
        float index = float(i) + (after_tile ? count - 1.0 : 0.0);
        vec4 child = grammar_texel(int(max(ref, 0.0)));
        if (!is_tile && child.x == 17.0 && t >= pos - child.y && t < pos + span + child.z) {
            // The part enlarged by its margins (child.y before, child.z after); its rule runs there.
            over = true;
            chosen = vec3(index, pos - child.y, span + child.y + child.z);
            target = int(child.w);
        } else if (!over && !found && (t < pos + span || i == n - 1)) {
            found = true;
            float k = is_tile ? clamp(floor((t - pos) / w), 0.0, count - 1.0) : 0.0;  // the copy of the tile
            // Parts after the tile count its copies: CGA's split.index over all elements made.
            chosen = vec3(index + k, pos + k * w, is_tile ? w : span);
            target = int(is_tile ? -ref - 1.0 : ref);
        }
        after_tile = after_tile || is_tile;
        pos = pos + span;
        if ((found || over) && pos > t + GRAMMAR_MAX_OVERHANG) break;  // no later part reaches back to t
    }
    g_split = vec2(chosen.x, float(n) + max(count - 1.0, 0.0));
    g_lb[a] = chosen.y;
    g_size[a] = chosen.z;
    g_addr = target;
}

float grammar_variable(int index) {
    if (index >= GRAMMAR_FIRST_PARAMETER) return g_params[min(index - GRAMMAR_FIRST_PARAMETER, 3)];
    if (index == GRAMMAR_FACADE_LEVEL) return grammar_level;
    if (index >= GRAMMAR_FIRST_BUILDING) return grammar_building[min(index - GRAMMAR_FIRST_BUILDING, 3)];
    vec2 pair = index < 2 ? g_split : (index < 4 ? g_size : g_facade);
    return pair[index % 2];
}

// The postfix tokens (code, value) of conditions and arguments, run on a small stack: push a
// number (0), a variable (1), apply an operator (3-17); the token (2, rule) returns the rule if
// the value on top is not 0. At most GRAMMAR_MAX_CASE_TOKENS tokens: the work is bounded.
// Division and modulo by 0 give 0 (as _expressions.apply). Returns -1 when no test was taken.
vec4 g_values_lo, g_values_hi;  // the program's stack, entries 0-3 and 4-7 (vectors: see g_stack01)

float grammar_value(int k) { return k < 4 ? g_values_lo[k & 3] : g_values_hi[k & 3]; }

void grammar_set_value(int k, float v) {
    if (k < 4) g_values_lo[k & 3] = v;
    else g_values_hi[k & 3] = v;
}

int grammar_program(int first, int n) {
    int sp = 0;
    for (int i = 0; i < GRAMMAR_MAX_CASE_TOKENS && i < n; ++i) {
        vec4 pair = grammar_texel(first + i / 2);
        int code = int(i % 2 == 0 ? pair.x : pair.z);
        float value = i % 2 == 0 ? pair.y : pair.w;
        if (code == 0 || code == 1) {
            grammar_set_value(min(sp, GRAMMAR_MAX_EXPR_STACK - 1), code == 0 ? value : grammar_variable(int(value)));
            sp = min(sp + 1, GRAMMAR_MAX_EXPR_STACK);
            continue;
        }
        if (code == 2) {
            sp = max(sp - 1, 0);
            if (grammar_value(sp) != 0.0) return int(value);
            continue;
        }
        int top = max(sp - 1, 0);
        float x = grammar_value(top);
        if (code == 16) {
            grammar_set_value(top, x == 0.0 ? 1.0 : 0.0);
            continue;
        }
        if (code == 17) {
            grammar_set_value(top, -x);
            continue;
        }
        sp = max(sp - 1, 1);
        top = sp - 1;
        float a = grammar_value(top);
        float b = x;
        float r;
        if (code == 3) r = a + b;
        else if (code == 4) r = a - b;
        else if (code == 5) r = a * b;
        else if (code == 6) r = b == 0.0 ? 0.0 : a / b;
        else if (code == 7) r = b == 0.0 ? 0.0 : a - b * floor(a / b);
        else if (code == 8) r = float(a == b);
        else if (code == 9) r = float(a != b);
        else if (code == 10) r = float(a < b);
        else if (code == 11) r = float(a <= b);
        else if (code == 12) r = float(a > b);
        else if (code == 13) r = float(a >= b);
        else if (code == 14) r = float(a != 0.0 && b != 0.0);
        else r = float(a != 0.0 || b != 0.0);
        grammar_set_value(top, r);
    }
    return -1;
}

float grammar_token(vec2 token) {
    return token.x == 0.0 ? token.y : grammar_variable(int(token.y));
}

// Case (head.x 14): the first condition that holds picks its rule, else the last rule (head.z).
// Bind (15), a reference with arguments: each argument's value becomes a parameter (the others 0),
// then the rule. Arguments of one token each (a number or a variable, the common case) are
// read directly; others run as a program. Both make one grammar_program call, so the shader has
// one copy of its loop.
void grammar_case_or_bind(vec4 head) {
    bool bind = head.x == 15.0;
    int n = int(head.y);
    int count = int(head.w);
    bool tokens = bind && n == count;
    int taken = grammar_program(g_addr + 1, tokens ? 0 : n);
    if (!bind) {
        g_addr = taken >= 0 ? taken : int(head.z);
        return;
    }
    vec4 values;
    if (tokens) {
        vec4 a = grammar_texel(g_addr + 1);
        vec4 b = count > 2 ? grammar_texel(g_addr + 2) : vec4(0.0);
        values = vec4(grammar_token(a.xy), grammar_token(a.zw), grammar_token(b.xy), grammar_token(b.zw));
    } else {
        values = g_values_lo;
    }
    g_params = values * vec4(greaterThan(vec4(float(count)), vec4(0.0, 1.0, 2.0, 3.0)));
    g_addr = int(head.z);
}

vec2 grammar_stack(int k) {
    vec4 pair = k < 2 ? g_stack01 : (k < 4 ? g_stack23 : (k < 6 ? g_stack45 : g_stack67));
    return (k & 1) == 0 ? pair.xy : pair.zw;
}

vec4 grammar_stack_put(vec4 pair, int k, vec2 corner) {
    return (k & 1) == 0 ? vec4(corner, pair.zw) : vec4(pair.xy, corner);
}

// RandStack: the scope's corner pushed (the last entry overwritten once the stack is full).
void grammar_push_stack(vec2 corner) {
    int slot = min(g_sp, GRAMMAR_MAX_STACK - 1);
    if (slot < 2) g_stack01 = grammar_stack_put(g_stack01, slot, corner);
    else if (slot < 4) g_stack23 = grammar_stack_put(g_stack23, slot, corner);
    else if (slot < 6) g_stack45 = grammar_stack_put(g_stack45, slot, corner);
    else g_stack67 = grammar_stack_put(g_stack67, slot, corner);
    g_sp = slot + 1;
}

// The one noise value a step draws: Rand's and RandUni's, from the scope at RandStack level
// head.z (0: this scope) in the rule's stream, or Repeat's rand size, from this scope in its
// part 0's stream.
float grammar_step_noise(int op, vec4 head) {
    bool repeat = op == 1 || op == 2;
    int level = repeat ? 0 : int(head.z);
    vec2 corner = level == 0 ? g_lb : grammar_stack(max(g_sp - level, 0));
    return grammar_random(corner, g_addr + (repeat ? GRAMMAR_PART_STREAMS : 0));
}

void grammar_rand(vec4 head, float r) {
    int n = int(head.y);
    for (int i = 0; i < GRAMMAR_MAX_PARTS; ++i) {
        vec4 part = grammar_texel(g_addr + 1 + i / 2);
        float accumulated = (i % 2 == 0) ? part.x : part.z;
        if (r < accumulated || i == n - 1) {
            g_addr = int((i % 2 == 0) ? part.y : part.w);
            return;
        }
    }
}

void grammar_intrusion(vec4 head) {
    g_view_dependent = true;
    float depth = head.y;
    vec2 local = g_t - g_lb;
    vec3 d = g_d;
    float tx = d.x > 0.0 ? (g_size.x - local.x) / d.x : (d.x < 0.0 ? -local.x / d.x : GRAMMAR_BIG);
    float ty = d.y > 0.0 ? (g_size.y - local.y) / d.y : (d.y < 0.0 ? -local.y / d.y : GRAMMAR_BIG);
    float tz = d.z > 0.0 ? depth / d.z : GRAMMAR_BIG;
    int face = (tz <= tx && tz <= ty) ? 2 : (tx <= ty ? (d.x < 0.0 ? 1 : 3) : (d.y < 0.0 ? 4 : 5));
    float h = min(min(tx, ty), tz);
    vec3 p = vec3(local + d.xy * h, d.z * h);
    // Each face seen from inside the box: (u, v) on it, its size, and the ray in its frame.
    vec2 new_local, new_size;
    vec3 new_d;
    if (face == 1) {
        new_local = vec2(p.z, p.y); new_size = vec2(depth, g_size.y); new_d = vec3(d.z, d.y, -d.x);
    } else if (face == 2) {
        new_local = p.xy; new_size = g_size; new_d = d;
    } else if (face == 3) {
        new_local = vec2(depth - p.z, p.y); new_size = vec2(depth, g_size.y); new_d = vec3(-d.z, d.y, d.x);
    } else if (face == 4) {
        new_local = vec2(p.x, p.z); new_size = vec2(g_size.x, depth); new_d = vec3(d.x, d.z, -d.y);
    } else {
        new_local = vec2(p.x, depth - p.z); new_size = vec2(g_size.x, depth); new_d = vec3(d.x, -d.z, d.y);
    }
    vec2 new_lb = g_lb + float(face) * g_s;
    int next = int(grammar_channel(g_addr, 1 + face));
    g_lb = new_lb;
    g_size = new_size;
    g_t = new_lb + clamp(new_local, vec2(0.0), new_size);
    g_d = new_d;
    g_addr = next;
}

// The current scope in facade uv: g_lb is the same for every pixel of a scope; so are the whole seed
// vectors it was translated by (layers, the start), which undo it exactly.
vec4 grammar_current_scope() {
    vec2 shift = mix(round((g_t - g_uv) / g_s) * g_s, vec2(0.0), equal(g_s, vec2(0.0)));  // no seed: none
    return vec4(g_lb - shift, g_size);
}

// SkipMask: skips head.z layers where the mask's nearest texel is 0, head.w where it is 1 (in both
// modes: holes have the numpy twin's edges). The bit that skips more cuts a hole.
// `bit`: the mask's nearest texel (the step's sample).
void grammar_skip_mask(vec4 head, float bit) {
    bool one = bit > 0.5;
    if (g_addr == g_through) {  // seen through this hole
        one = head.w > head.z;
        g_through = -1;
    }
    // as the terminal, decided on exact alphas: a hole under an opaque Mat (where only the filtered
    // alpha goes on) shows nothing, as in the numpy twin, which stops there
    if ((one ? head.w > head.z : head.z > head.w) && g_AE < GRAMMAR_OPAQUE) {
        g_hole = g_addr;
        g_hole_scope = grammar_current_scope();
    }
    g_end = int(one ? head.w : head.z);
}

// rgba, texel, tile, a_exact: the step's sample of the Mat's tile or colour (grammar_evaluate).
void grammar_mat(vec4 head, int op, vec4 rgba, ivec2 texel, int tile, float a_exact) {
    if (g_through >= 0) {  // a layer above the hole seen through: not in the way
        g_end = 0;
        return;
    }
    int usage = int(head.y);
    if (op == 13) {
        ivec2 unused_texel;
        int unused_tile;
        float mask_exact;
        rgba.a *= grammar_sample(int(head.w), 1, grammar_texel(g_addr + 2), unused_texel, unused_tile, mask_exact).a;
        a_exact *= mask_exact;
    }
    float a = rgba.a;
    if (usage == 1) {
        float w = (1.0 - g_A) * a;
        g_C += w * rgba.rgb * g_tint;
        g_A += w;
        float w_exact = (1.0 - g_AE) * a_exact;
        g_AE += w_exact;
        if (w_exact > g_best_w) {
            g_best_w = w_exact;
            g_best_addr = g_addr;
            g_best_tile = tile;
            g_best_texel = texel;
            g_best_scope = grammar_current_scope();
        }
    } else if (usage == 2) {
        float w = (1.0 - g_AN) * a;
        g_N += w * (rgba.rgb * 2.0 - 1.0);
        g_AN += w;
    } else {
        float w = (1.0 - g_AS) * a;
        g_S += w * rgba.rg;
        g_AS += w;
    }
    // Both alphas must be opaque. The exact one is where the numpy twin stops; once it is opaque,
    // later Mats weigh at most 0.001 on the exact track and cannot change the terminal.
    if (g_A >= GRAMMAR_OPAQUE && g_AE >= GRAMMAR_OPAQUE) {
        g_active = false;
    } else {
        g_end = 0;
    }
}

GrammarResult grammar_evaluate(int start, vec2 uv, vec2 facade, vec2 seed, vec3 dir, vec2 duv_dx, vec2 duv_dy) {
    g_addr = start;
    g_s = seed;
    g_lb = seed;
    g_size = facade;
    g_facade = facade;
    g_split = vec2(0.0, 1.0);
    g_params = vec4(0.0);
    g_t = uv + seed;
    g_uv = uv;
    g_d = dir;
    g_dtdx = duv_dx;
    g_dtdy = duv_dy;
    g_stack01 = vec4(grammar_building_seed.x > 0.0 ? grammar_building_seed : seed, 0.0, 0.0);  // seed cells are >= 1
    g_stack23 = g_stack45 = g_stack67 = vec4(0.0);
    g_sp = 1;
    g_depth = 0;
    g_active = true;
    g_view_dependent = false;
    g_C = vec3(0.0); g_N = vec3(0.0); g_S = vec2(0.0);
    g_A = 0.0; g_AN = 0.0; g_AS = 0.0; g_best_w = 0.0; g_AE = 0.0;
    g_tint = vec3(1.0);
    g_best_addr = -1; g_best_tile = -1; g_best_texel = ivec2(0); g_best_scope = vec4(vec2(0.0), facade);
    g_through = grammar_through;
    grammar_through = -1;
    g_hole = -1; g_hole_scope = vec4(0.0);

    for (int step = 0; step < GRAMMAR_MAX_STEPS && g_active; ++step) {
        vec4 head = grammar_texel(g_addr);
        // Binds (a reference's arguments) and Cases lead straight on to the next rule: they take
        // steps of the same budget without the operator dispatch below.
        for (; (head.x == 14.0 || head.x == 15.0) && step < GRAMMAR_MAX_STEPS - 1; ++step) {
            grammar_case_or_bind(head);
            head = grammar_texel(g_addr);
        }
        int op = int(head.x);
        if (op == 14 || op == 15) break;  // the budget ran out on a chain of them (the checks refuse such grammars)
        g_end = -1;
        // The step's one noise value and one tile sample, made here for the operators that use
        // them: the GPU runs every branch below where any pixel of its group takes it, so each
        // kind of fetch appears once. A Mat (12, 13) samples its tile or colour; a SkipMask (10) its mask.
        float noise = grammar_step_noise(op, head);
        bool mask = op == 10;
        bool mat = op == 12 || op == 13;
        vec4 params = mat && !(op == 12 && head.w == 0.0) ? grammar_texel(g_addr + 1) : vec4(0.0, 0.0, 1.0, 1.0);
        ivec2 texel;
        int tile;
        float exact;
        vec4 sampled = grammar_sample(mask ? int(head.y) : (mat ? int(head.z) : 0), mask ? 1 : int(head.y), params,
                                      texel, tile, exact);
        if (op == 1 || op == 2) {
            grammar_repeat(head, op - 1, noise);
        } else if (op == 3 || op == 4) {
            grammar_split(head, op - 3);
        } else if (op == 5) {
            grammar_rand(head, noise);
        } else if (op == 6) {
            int n = int(head.y);
            int k = min(int(floor(noise * float(n))), n - 1);
            g_addr = int(grammar_channel(g_addr, 3 + k));
        } else if (op == 7) {
            grammar_push_stack(g_lb);
            g_addr = int(head.y);
        } else if (op == 8) {
            grammar_enter_layer(g_addr, int(head.y));
            g_end = 0;
        } else if (op == 9) {
            g_end = int(head.y);
        } else if (op == 10) {
            grammar_skip_mask(head, exact);
        } else if (op == 11) {
            grammar_intrusion(head);
        } else if (op == 17) {
            g_addr = int(head.w);  // an Overhang not reached through its Split (a start rule): its rule as it is
        } else if (op == 16) {
            g_tint *= grammar_texel(g_addr + 1).rgb;
            g_addr = int(head.y);
        } else {
            grammar_mat(head, op, sampled, texel, tile, exact);
        }
        // the layer ends here for the operators that set g_end: one copy of its loop in the shader,
        // as the GPU runs every branch of the dispatch above where any pixel of its group takes it
        if (g_end >= 0) grammar_end_layer(g_end);
    }

    GrammarResult result;
    result.color = g_C + (1.0 - g_A) * 0.5;
    result.alpha = g_A;
    vec3 n = g_N + (1.0 - g_AN) * vec3(0.0, 0.0, 1.0);
    result.normal = n / max(length(n), 1e-6);
    result.specular = g_S + (1.0 - g_AS) * vec2(0.08, 0.25);
    result.terminal = g_best_addr;
    result.tile = g_best_tile;
    result.scope = g_best_scope;
    result.view_dependent = g_view_dependent;
    result.hole = g_hole;
    result.hole_scope = g_hole_scope;
    bool has_tile = g_best_tile >= 0;
    result.glass = has_tile && texelFetch(u_grammar_tiles, ivec3(g_best_texel, 3 * g_best_tile + 2), 0).b > 0.5;
    // A constant colour is a wall unless written Color(r, g, b, label): then head.w is 1 + label.
    vec4 best = grammar_texel(max(g_best_addr, 0));
    int constant = (best.x == 12.0 && best.z == 0.0 && best.w >= 2.0) ? int(best.w) - 1 : GRAMMAR_WALL_LABEL;
    result.label = has_tile ? u_grammar_tile_labels[g_best_tile] : (g_best_addr >= 0 ? constant : 0);
    return result;
}

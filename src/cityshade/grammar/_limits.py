"""Compile-time limits of the GPU evaluator. They bound every loop in the shader (so no grammar can
hang the GPU), are passed to it as #defines, and the checks refuse grammars that exceed them."""

MAX_STEPS = 128  # operators visited per pixel, over all layers
MAX_LAYER_DEPTH = 4  # nested Layer operators
MAX_STACK = 8  # random-seed stack entries (entry 0 is the facade's seed)
MAX_PARTS = 16  # parts of one Split or Rand
MAX_INTRUSIONS = 3  # nested Intrusion operators
MAX_CASE_TOKENS = 32  # postfix tokens of one Case (all its conditions): its loop's bound
MAX_EXPR_STACK = 8  # stack slots a condition (or a reference's arguments) may use
MAX_PARAMS = 4  # parameters of one rule, Floor(i, k)
MAX_TEXELS = 2048
RANDOM_PARTS = 32  # added to a Split's part count (> MAX_PARTS) when its sizes are rand(low, high)
PART_STREAMS = MAX_TEXELS  # part i of the rule at address r draws from stream r + PART_STREAMS * (i + 1)  # rule addresses are exact integers in a 16-bit float channel up to 2048
MAX_OVERHANG = 1.0  # metres an Overhang reaches past its part of a Split, on each side
TEXTURE_WIDTH = 256
HALF_MAX = 65504.0  # the largest 16-bit float: every number of a rule, and Split's sums, are stored as one

DEFINES = {
    "GRAMMAR_MAX_STEPS": MAX_STEPS,
    "GRAMMAR_MAX_LAYERS": MAX_LAYER_DEPTH,
    "GRAMMAR_MAX_STACK": MAX_STACK,
    "GRAMMAR_MAX_PARTS": MAX_PARTS,
    "GRAMMAR_MAX_CASE_TOKENS": MAX_CASE_TOKENS,
    "GRAMMAR_MAX_EXPR_STACK": MAX_EXPR_STACK,
    "GRAMMAR_RANDOM_PARTS": RANDOM_PARTS,
    "GRAMMAR_MAX_PARAMS": MAX_PARAMS,
    "GRAMMAR_PART_STREAMS": PART_STREAMS,
    "GRAMMAR_MAX_OVERHANG": MAX_OVERHANG,
}

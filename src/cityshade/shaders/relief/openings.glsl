// Which window opening of the relief atlas (relief/building.glsl, cityshade/relief/_city.py) a
// grammar result recesses: its glazed terminal's, else the hole's it shows. The deferred grammar
// pass finds it once per pixel (grammar/deferred.glsl), so the buildings pass need not evaluate
// the grammar again for it; the id pass, and pixels the deferred pass passed nothing on for,
// find it from their own evaluation.
#ifndef RELIEF_OPENINGS_GLSL
#define RELIEF_OPENINGS_GLSL

#include "grammar/eval.glsl"

#define RELIEF_MAX_OPENINGS 64
uniform int u_relief_openings;  // how many glazed terminals and holes have a window opening
uniform ivec2 u_relief_terminals[RELIEF_MAX_OPENINGS];  // rule address (Mat or SkipMask), first atlas row of its opening

// The index of a glazed terminal's or a hole's opening, -1 for none.
int relief_opening(int terminal) {
    for (int i = 0; i < u_relief_openings; i++)
        if (terminal >= 0 && u_relief_terminals[i].x == terminal) return i;
    return -1;
}

struct GrammarOpening {
    int index;   // relief_opening's, -1 for none
    bool hole;   // a hole's (u_relief_terminals[index].x is its SkipMask), not a glazed terminal's
    vec4 scope;  // the terminal's or the hole's scope (GrammarResult.scope, grammar uv): the window's rectangle
};

GrammarOpening grammar_opening(GrammarResult g) {
    int index = g.glass || g.label == GRAMMAR_WINDOW_LABEL ? relief_opening(g.terminal) : -1;
    bool hole = index < 0;
    if (hole) index = relief_opening(g.hole);
    return GrammarOpening(index, hole, hole ? g.hole_scope : g.scope);
}

#endif

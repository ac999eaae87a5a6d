// QUANTUM_INDEPENDENT_ITERATIONS, before a particle loop: each iteration reads and writes only its
// own particle's entries, so the compiler may vectorize without checking the arrays for overlap.
// GCC takes `ivdep`. Clang ignores that pragma and `__restrict` on local pointers, and without
// this its vectorizer left the contact search scalar (a match under the sanitizers spent half its
// time there); it takes `vectorize(assume_safety)` instead.
#pragma once

#if defined(__clang__)
#define QUANTUM_INDEPENDENT_ITERATIONS _Pragma("clang loop vectorize(assume_safety)")
#else
#define QUANTUM_INDEPENDENT_ITERATIONS _Pragma("GCC ivdep")
#endif

// avg's binding points, one table for its GLSL and its C++
// (server/solvers/avg/*.cpp include this file; only #define lines), from
// the solver's free ranges of the shared table (bindings.glsl); its passes
// read the view G-buffer at the shared GS_UNIT_GBUFFER_* units.

#ifndef AVG_BINDINGS_GLSL
#define AVG_BINDINGS_GLSL

#define AVG_BINDING_VPLS 6      // avg/vpl.glsl: the VPLs
#define AVG_UNIT_VPL_SHADOWS 7  // illuminate.frag.glsl: the VPLs' shadow maps
// filter.frag.glsl (split layout): the interleaved sums before filtering.
#define AVG_UNIT_SPLIT_INDIRECT 12
#define AVG_UNIT_SPLIT_DIRECT 13

#endif

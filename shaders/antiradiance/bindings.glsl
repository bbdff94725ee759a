// antiradiance's binding points, one table for its GLSL and its C++
// (server/solvers/antiradiance/antiradiance_solver.cpp includes this file;
// only #define lines), from the solver's free buffer range of the shared
// table (bindings.glsl). Each pass has its own names: a slot may carry
// another buffer in another pass.

#ifndef AR_BINDINGS_GLSL
#define AR_BINDINGS_GLSL

// display.frag.glsl: the leaves, their grid and the glossy leaves' radiance.
#define AR_BINDING_ELEMENTS 6          // antiradiance/elements.glsl
#define AR_BINDING_GRID 7              // cell starts, then leaf ids
#define AR_BINDING_GLOSSY_RADIANCE 10  // slot x bin
#define AR_BINDING_BIN_DIRECTIONS 11   // antiradiance/glossy.glsl

// element_direct.comp.glsl: the leaves' direct irradiance (reads the
// elements at AR_BINDING_ELEMENTS).
#define AR_BINDING_ELEMENT_DIRECT 7

// The glossy leaves' direct radiance per bin: the shared
// render/glossy_bin_direct.comp.glsl (its slots in bindings.glsl).

#endif

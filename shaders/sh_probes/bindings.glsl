// sh_probes' binding points, one table for its GLSL and its C++
// (server/solvers/sh_probes/sh_probes_solver.cpp includes this file; only
// #define lines). Buffers and texture units from the solver's free ranges
// of the shared table (bindings.glsl); image units are its own.

#ifndef SH_BINDINGS_GLSL
#define SH_BINDINGS_GLSL

// Shader storage buffers.
#define SH_BINDING_COEFFICIENTS 6  // the probes' SH coefficients (the solution)
#define SH_BINDING_VALID 7         // per probe: 1 where it sees the scene from outside
#define SH_BINDING_PREVIOUS 8      // the coefficients before a sweep (tail estimate)
#define SH_BINDING_SHOWN 9         // the coefficients the display interpolates (blended)
#define SH_BINDING_BATCH 10        // the probes of the batch being worked on
#define SH_BINDING_SEES_CHANGE 11  // per probe: whether its cube map sees a change

// Texture units: the probe atlas' G-buffer.
#define SH_UNIT_DISTANCE 12
#define SH_UNIT_NORMAL 13  // w: 1 = back face
#define SH_UNIT_ALBEDO 14
#define SH_UNIT_MATERIAL 15  // rg: metallic, roughness

// Image units: the probe atlas' radiance layers.
#define SH_IMAGE_DIRECT 0
#define SH_IMAGE_INDIRECT 1
#define SH_IMAGE_RADIANCE 2

#endif

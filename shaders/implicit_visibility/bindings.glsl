// implicit_visibility's binding points, one table for its GLSL and its C++
// (server/solvers/implicit_visibility/*.cpp include this file; only
// #define lines). Each compute pass binds nothing of the shared table
// (bindings.glsl) and numbers its buffers from 1; the display pass uses
// the solver's texture unit 13.

#ifndef IV_BINDINGS_GLSL
#define IV_BINDINGS_GLSL

// pull.comp.glsl: push-pull, children's radiance area-averaged up the tree.
#define IV_PULL_CHILDREN 1
#define IV_PULL_AREAS 2
#define IV_PULL_RADIANCE 3

// leaf_direct.comp.glsl: the leaves' direct and environment irradiance.
#define IV_LEAF_LEAVES 4
#define IV_LEAF_DIRECT_E 5
#define IV_LEAF_ENV_E 6
#define IV_LEAF_RADIANCE 7

// gather.comp.glsl: one bounce over the links (reads one radiance buffer,
// writes the other).
#define IV_GATHER_LEAVES 1
#define IV_GATHER_DIRECT_E 2
#define IV_GATHER_ENV_E 3
#define IV_GATHER_OFFSETS 4
#define IV_GATHER_LINKS 5
#define IV_GATHER_RADIANCE_IN 6
#define IV_GATHER_RADIANCE_OUT 7
#define IV_GATHER_INDIRECT_E 8
// ... and the glossy elements' outgoing radiance per bin (glossy.glsl).
#define IV_GATHER_NODE_SLOTS 9
#define IV_GATHER_GLOSSY_NODES 10
#define IV_GATHER_GLOSSY_RADIANCE 11
#define IV_GATHER_BIN_LUT 13
// ... and each link's receiver bin (two per uint) and the bins' directions.
#define IV_GATHER_LINK_BINS 14
#define IV_GATHER_RECEIVER_BINS 15

// glossy_pull.comp.glsl: the glossy nodes' radiance per bin, area-averaged
// up the tree (the direct light's, once per illumination).
#define IV_GLOSSY_PULL_CHILDREN 1
#define IV_GLOSSY_PULL_AREAS 2
#define IV_GLOSSY_PULL_NODE_SLOTS 3
#define IV_GLOSSY_PULL_SLOT_NODES 4
#define IV_GLOSSY_PULL_RADIANCE 5

// vertex_irradiance.vert.glsl and final.frag.glsl: display.
#define IV_VERTEX_INDIRECT_E 1
#define IV_UNIT_INDIRECT 13  // the per-pixel indirect irradiance texture

#endif

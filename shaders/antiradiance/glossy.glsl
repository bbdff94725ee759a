// antiradiance's directional bins on the GPU (std430 mirrors of
// AntiradianceSolver's buffers): the bins' main directions and, per glossy
// leaf, the reflected indirect radiance per bin (glossy_transfer.h).
#include "antiradiance/bindings.glsl"
layout(std430, binding = AR_BINDING_BIN_DIRECTIONS) readonly buffer BinDirections { vec4 bin_direction[]; };
uniform int uBins;

// The view G-buffer as solvers' final passes read it (render/gbuffer.h;
// bound by GBuffer::BindTextures(8)).
#include "bindings.glsl"
layout(binding = GS_UNIT_GBUFFER_POSITION) uniform sampler2D uGPosition;   // w = 0: background
layout(binding = GS_UNIT_GBUFFER_NORMAL) uniform sampler2D uGNormal;
layout(binding = GS_UNIT_GBUFFER_ALBEDO) uniform sampler2D uGAlbedo;      // a: metallic
layout(binding = GS_UNIT_GBUFFER_EMISSION) uniform sampler2D uGEmission;  // a: roughness
layout(binding = GS_UNIT_GBUFFER_SPECULAR) uniform sampler2D uGSpecular;  // dielectric F0, F90

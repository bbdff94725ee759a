// The view G-buffer as solvers' final passes read it (render/gbuffer.h;
// bound by GBuffer::BindTextures(8)).
layout(binding = 8) uniform sampler2D uGPosition;   // w = 0: background
layout(binding = 9) uniform sampler2D uGNormal;
layout(binding = 10) uniform sampler2D uGAlbedo;
layout(binding = 11) uniform sampler2D uGEmission;

// Binding points, one table for GLSL and C++: shaders include this file
// ("bindings.glsl" through the shader library) and server/gl/bindings.h
// includes it into C++, so a slot is agreed in one place. Only #define
// lines here: the file is read by both preprocessors.
//
// Shared slots (render/ and scene/: every solver's programs see them):
//   shader storage buffers 0-3 and 12, texture units 0-2, 4-6 and 8-11.
// Free for a solver's own resources: buffers 4-11 and 13-15, texture units
// 3, 7 and 12-15; a solver's own table lives beside its shaders.

#ifndef GS_BINDINGS_GLSL
#define GS_BINDINGS_GLSL

// Shader storage buffers.
#define GS_BINDING_MATERIALS 0            // scene/gpu_scene: Material[]
#define GS_BINDING_PUNCTUAL_LIGHTS 1      // render/direct_lighting
#define GS_BINDING_AREA_SAMPLES 2         // render/direct_lighting
#define GS_BINDING_DIR_SHADOW_MATRICES 3  // render/direct_lighting
#define GS_BINDING_EMITTER_POLYGONS 12    // render/direct_lighting
#define GS_BINDING_NON_FINITE 7           // render/tonemap (view pass only)
// scene/gpu_deform (its own pass before the solvers, which bind their own).
#define GS_BINDING_DEFORM_VERTICES 4
#define GS_BINDING_DEFORM_SKIN 5
#define GS_BINDING_DEFORM_MORPH 6
#define GS_BINDING_DEFORM_JOINTS 8
#define GS_BINDING_DEFORM_WEIGHTS 9
// render/glossy_bin_direct (its own compute pass, beside the direct
// light's slots): glossy elements in, bin directions, radiance per bin out.
#define GS_BINDING_GLOSSY_BIN_ELEMENTS 4
#define GS_BINDING_GLOSSY_BIN_DIRECTIONS 5
#define GS_BINDING_GLOSSY_BIN_RADIANCE 6

// Uniform blocks.
#define GS_UBO_VIEW 0  // render/gbuffer: the view's eye (render/shade_surface.glsl)

// Texture units.
#define GS_UNIT_BASE_COLOR 0     // scene material textures (G-buffer pass)
#define GS_UNIT_EMISSIVE 1
#define GS_UNIT_METALLIC_ROUGHNESS 2  // linear: B metallic, G roughness
#define GS_UNIT_HDR 0            // tone map input (view pass only)
#define GS_UNIT_ENVIRONMENT 0    // render/sky: the G-buffer's background (before the materials)
#define GS_UNIT_REFINE_MEAN 0     // render/show_refined (view pass only)
#define GS_UNIT_REFINE_HISTORY 1
#define GS_UNIT_CARRY_MEAN 2
#define GS_UNIT_CARRY_CENTRE 3
#define GS_UNIT_REPROJECT_PREVIOUS 4  // render/show_refined: the picture before a camera move
#define GS_UNIT_CUBE_SHADOWS 4   // render/direct_lighting
#define GS_UNIT_DIR_SHADOWS 5
#define GS_UNIT_GBUFFER 8        // 8 position, 9 normal, 10 albedo, 11 emission
#define GS_UNIT_GBUFFER_POSITION 8
#define GS_UNIT_GBUFFER_NORMAL 9
#define GS_UNIT_GBUFFER_ALBEDO 10
#define GS_UNIT_GBUFFER_EMISSION 11
#define GS_UNIT_GBUFFER_SPECULAR 6  // rgb: dielectric F0, a: F90

#endif  // GS_BINDINGS_GLSL

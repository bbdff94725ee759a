// The binding points shared by C++ and GLSL (shaders/bindings.glsl), as
// constants. Include this wherever C++ binds a buffer or texture that a
// shared shader declares.
#pragma once

#include "bindings.glsl"  // shaders/ is on gistream_gl's include path

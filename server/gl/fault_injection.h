// Test-only GPU fault injection, so that the engine's handling of a lost
// context and of GL_OUT_OF_MEMORY can be exercised on llvmpipe, which
// produces neither. Off unless a fault directory is set (EngineOptions::
// test_fault_dir; gistreamd: $GISTREAM_TEST_FAULT_DIR). Then a file there
// triggers one fault and is removed when it fires:
//   gpu_reset       the next reset check reports GL_GUILTY_CONTEXT_RESET
//   gpu_reset_fail  as gpu_reset, and recreating the context then fails
//   gpu_oom         the next allocation check reports GL_OUT_OF_MEMORY
// Nothing on the public API can set the directory or write the files.
#pragma once

#include <filesystem>

#include "gl/gl.h"

namespace gistream::gl {

// Process-wide (every engine in the process sees the same directory; the
// last one set wins); empty turns injection off.
void SetFaultDirectory(const std::filesystem::path& dir);

enum class InjectedReset { kNone, kReset, kResetAndFailRecovery };
// Consumes gpu_reset / gpu_reset_fail.
InjectedReset TakeInjectedReset();

// glGetError(), or GL_OUT_OF_MEMORY once when gpu_oom is there (the real
// error, if any, is still cleared). For the checks after allocations.
GLenum AllocationError();

}  // namespace gistream::gl

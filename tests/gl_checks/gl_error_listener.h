// Every test in a binary that renders fails when the driver reports a GL
// error (KHR_debug, GL_DEBUG_TYPE_ERROR) while it runs. A test that
// provokes errors on purpose (fault injection) says so first.
#pragma once

namespace gistream::testing {

// The running test expects GL errors: they do not fail it.
void AllowGlErrorsInThisTest();

}  // namespace gistream::testing

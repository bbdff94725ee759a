// The one include for OpenGL: 4.5 core prototypes, resolved by libglvnd's
// libOpenGL (GL_GLEXT_PROTOTYPES is set by the build).
#pragma once

#include <GL/glcorearb.h>

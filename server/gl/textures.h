// Texture and framebuffer creation: render targets, layered targets and
// depth-compare arrays, and framebuffers over them. The one place that
// knows these parameter sets, so passes do not keep private copies.
#pragma once

#include <algorithm>
#include <initializer_list>

#include "gl/handle.h"

namespace gistream::gl {

// A single-level 2D render target read with texelFetch / nearest
// filtering (GL_LINEAR when `linear`), clamped at the edges.
inline Texture RenderTarget(GLenum format, int width, int height, bool linear = false) {
  Texture t = Texture::Create(GL_TEXTURE_2D);
  glTextureStorage2D(t.id(), 1, format, std::max(width, 1), std::max(height, 1));
  const GLint filter = linear ? GL_LINEAR : GL_NEAREST;
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, filter);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, filter);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

// A single-level 2D array render target (`layers` layers), nearest
// filtering (complete without mipmaps).
inline Texture LayeredTarget(GLenum format, int width, int height, int layers) {
  Texture t = Texture::Create(GL_TEXTURE_2D_ARRAY);
  glTextureStorage3D(t.id(), 1, format, std::max(width, 1), std::max(height, 1),
                     std::max(layers, 1));
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return t;
}

// Square 32-bit depth maps with hardware comparison (sampler*Shadow, 2x2
// PCF through GL_LINEAR): GL_TEXTURE_2D_ARRAY or GL_TEXTURE_CUBE_MAP_ARRAY
// (`layers` = 6 x cubes).
inline Texture DepthCompareArray(GLenum target, int size, int layers) {
  Texture t = Texture::Create(target);
  glTextureStorage3D(t.id(), 1, GL_DEPTH_COMPONENT32F, size, size, std::max(layers, 1));
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTextureParameteri(t.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  return t;
}

// A framebuffer drawing into `colors` (attachments 0, 1, ... in order, all
// enabled as draw buffers; whole layered textures attach layered) and
// `depth` (0: none).
inline Framebuffer FramebufferOf(std::initializer_list<GLuint> colors, GLuint depth = 0) {
  Framebuffer fbo = Framebuffer::Create();
  GLenum draw[8];
  GLsizei count = 0;
  for (GLuint color : colors) {
    draw[count] = GL_COLOR_ATTACHMENT0 + GLenum(count);
    glNamedFramebufferTexture(fbo.id(), draw[count], color, 0);
    ++count;
  }
  if (depth != 0) glNamedFramebufferTexture(fbo.id(), GL_DEPTH_ATTACHMENT, depth, 0);
  if (count > 0) glNamedFramebufferDrawBuffers(fbo.id(), count, draw);
  return fbo;
}

}  // namespace gistream::gl

// Headless EGL: enumerate devices through EGL_EXT_platform_device, pick one,
// create an OpenGL 4.5 core context (robust with reset notification where
// the driver offers it) with no surface. The context is current on the
// thread that calls MakeCurrent: gistream's render thread.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "util/status.h"

namespace gistream::gl {

struct EglDeviceInfo {
  int index = 0;
  std::string extensions;  // EGL_EXTENSIONS of the device
  std::string drm_path;    // EGL_DRM_DEVICE_FILE_EXT when known
  bool software = false;   // EGL_MESA_device_software
};

absl::StatusOr<std::vector<EglDeviceInfo>> EnumerateEglDevices();

class EglContext {
 public:
  // device_index -1: the first hardware device, else Mesa's software device.
  static absl::StatusOr<std::unique_ptr<EglContext>> Create(int device_index);
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  absl::Status MakeCurrent();
  void ReleaseCurrent();

  bool robust() const { return robust_; }
  const std::string& description() const { return description_; }

 private:
  EglContext() = default;
  void* display_ = nullptr;  // EGLDisplay
  void* context_ = nullptr;  // EGLContext
  bool robust_ = false;
  std::string description_;
};

}  // namespace gistream::gl

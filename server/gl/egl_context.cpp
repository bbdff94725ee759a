#include "gl/egl_context.h"
#include "gl/driver_quirks.h"
#include "gl/gl.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>

#include "util/log.h"

namespace gistream::gl {
namespace {

struct EglExt {
  PFNEGLQUERYDEVICESEXTPROC query_devices = nullptr;
  PFNEGLQUERYDEVICESTRINGEXTPROC query_device_string = nullptr;
  PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display = nullptr;
};

absl::StatusOr<EglExt> LoadExtensions() {
  EglExt ext;
  ext.query_devices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  ext.query_device_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));
  ext.get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!ext.query_devices || !ext.query_device_string || !ext.get_platform_display) {
    return absl::FailedPreconditionError(
        "EGL: EGL_EXT_device_enumeration / EGL_EXT_platform_device not available");
  }
  return ext;
}

bool HasExtension(const std::string& list, const char* name) {
  const size_t n = std::strlen(name);
  for (size_t pos = list.find(name); pos != std::string::npos; pos = list.find(name, pos + 1)) {
    const bool starts = pos == 0 || list[pos - 1] == ' ';
    const bool ends = pos + n == list.size() || list[pos + n] == ' ';
    if (starts && ends) return true;
  }
  return false;
}

std::string EglErrorName(EGLint error) {
  switch (error) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    default: return absl::StrCat("EGL error 0x", absl::Hex(error));
  }
}

std::vector<EGLDeviceEXT> QueryDevices(const EglExt& ext) {
  EGLint count = 0;
  if (!ext.query_devices(0, nullptr, &count) || count <= 0) return {};
  std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
  ext.query_devices(count, devices.data(), &count);
  devices.resize(static_cast<size_t>(count));
  return devices;
}

EglDeviceInfo Describe(const EglExt& ext, EGLDeviceEXT device, int index) {
  EglDeviceInfo info;
  info.index = index;
  if (const char* e = ext.query_device_string(device, EGL_EXTENSIONS)) info.extensions = e;
  info.software = HasExtension(info.extensions, "EGL_MESA_device_software");
  if (HasExtension(info.extensions, "EGL_EXT_device_drm")) {
    if (const char* p = ext.query_device_string(device, EGL_DRM_DEVICE_FILE_EXT)) info.drm_path = p;
  }
  return info;
}

}  // namespace

absl::StatusOr<std::vector<EglDeviceInfo>> EnumerateEglDevices() {
  GS_ASSIGN_OR_RETURN(EglExt ext, LoadExtensions());
  std::vector<EglDeviceInfo> out;
  const std::vector<EGLDeviceEXT> devices = QueryDevices(ext);
  for (size_t i = 0; i < devices.size(); ++i) out.push_back(Describe(ext, devices[i], int(i)));
  return out;
}

namespace {

// The device to render on: the requested one, else the first hardware
// device, else the first software one; and why, for the description.
absl::StatusOr<std::pair<int, std::string>> ChooseDevice(const EglExt& ext,
                                                         const std::vector<EGLDeviceEXT>& devices,
                                                         int device_index) {
  if (device_index >= 0) {
    if (device_index >= int(devices.size())) {
      return absl::InvalidArgumentError(absl::StrCat(
          "--egl-device: ", device_index, " is out of range (", devices.size(), " EGL devices)"));
    }
    return std::make_pair(device_index, std::string("requested"));
  }
  for (size_t i = 0; i < devices.size(); ++i) {
    if (!Describe(ext, devices[i], int(i)).software)
      return std::make_pair(int(i), std::string("first hardware device"));
  }
  for (size_t i = 0; i < devices.size(); ++i) {
    if (Describe(ext, devices[i], int(i)).software)
      return std::make_pair(int(i), std::string("software device"));
  }
  return std::make_pair(0, std::string("first device"));
}

// An initialized display of the device with what a surfaceless OpenGL
// context needs; its config (null with EGL_KHR_no_config_context).
struct EglDisplay {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLint major = 0, minor = 0;
  bool no_config = false;
  EGLConfig config = nullptr;
};

absl::StatusOr<EglDisplay> InitializeDisplay(const EglExt& ext, EGLDeviceEXT device, int chosen) {
  EglDisplay d;
  d.display = ext.get_platform_display(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
  if (d.display == EGL_NO_DISPLAY) {
    return absl::FailedPreconditionError(
        absl::StrCat("EGL: no display for device ", chosen, ": ", EglErrorName(eglGetError())));
  }
  if (!eglInitialize(d.display, &d.major, &d.minor)) {
    return absl::FailedPreconditionError(absl::StrCat("EGL: eglInitialize failed on device ",
                                                      chosen, ": ", EglErrorName(eglGetError())));
  }
  const std::string display_ext = eglQueryString(d.display, EGL_EXTENSIONS);
  if (!HasExtension(display_ext, "EGL_KHR_surfaceless_context")) {
    return absl::FailedPreconditionError("EGL: EGL_KHR_surfaceless_context is required");
  }
  if (!eglBindAPI(EGL_OPENGL_API)) {
    return absl::FailedPreconditionError("EGL: eglBindAPI(EGL_OPENGL_API) failed");
  }
  const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
  EGLint num_configs = 0;
  d.no_config = HasExtension(display_ext, "EGL_KHR_no_config_context");
  if (!d.no_config && (!eglChooseConfig(d.display, config_attribs, &d.config, 1, &num_configs) ||
                       num_configs == 0)) {
    return absl::FailedPreconditionError("EGL: no OpenGL-capable config");
  }
  return d;
}

// An OpenGL 4.5 core context: robust with reset notification first, a
// plain one as fallback; EGL_NO_CONTEXT when neither is made.
std::pair<EGLContext, bool> CreateCoreContext(const EglDisplay& d) {
  for (bool robust : {true, false}) {
    std::vector<EGLint> attribs = {
        EGL_CONTEXT_MAJOR_VERSION,       4,
        EGL_CONTEXT_MINOR_VERSION,       5,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT};
#ifndef NDEBUG
    attribs.insert(attribs.end(), {EGL_CONTEXT_OPENGL_DEBUG, EGL_TRUE});
#endif
    if (robust) {
      attribs.insert(attribs.end(),
                     {EGL_CONTEXT_OPENGL_ROBUST_ACCESS, EGL_TRUE,
                      EGL_CONTEXT_OPENGL_RESET_NOTIFICATION_STRATEGY, EGL_LOSE_CONTEXT_ON_RESET});
    }
    attribs.push_back(EGL_NONE);
    EGLContext ctx = eglCreateContext(d.display, d.no_config ? EGL_NO_CONFIG_KHR : d.config,
                                      EGL_NO_CONTEXT, attribs.data());
    if (ctx != EGL_NO_CONTEXT) return {ctx, robust};
  }
  return {EGL_NO_CONTEXT, false};
}

}  // namespace

absl::StatusOr<std::unique_ptr<EglContext>> EglContext::Create(int device_index) {
  GS_ASSIGN_OR_RETURN(EglExt ext, LoadExtensions());
  const std::vector<EGLDeviceEXT> devices = QueryDevices(ext);
  if (devices.empty()) return absl::FailedPreconditionError("EGL: no devices found");
  GS_ASSIGN_OR_RETURN(const auto choice, ChooseDevice(ext, devices, device_index));
  const auto& [chosen, why] = choice;
  const EglDeviceInfo info = Describe(ext, devices[size_t(chosen)], chosen);
  GS_ASSIGN_OR_RETURN(const EglDisplay display,
                      InitializeDisplay(ext, devices[size_t(chosen)], chosen));
  auto self = std::unique_ptr<EglContext>(new EglContext());
  self->display_ = display.display;
  std::tie(self->context_, self->robust_) = CreateCoreContext(display);
  if (!self->context_) {
    return absl::FailedPreconditionError(
        absl::StrCat("EGL: could not create an OpenGL 4.5 core context on device ", chosen, ": ",
                     EglErrorName(eglGetError())));
  }
  self->description_ = absl::StrCat(
      "EGL ", display.major, ".", display.minor, " device ", chosen, " of ", devices.size(), " (",
      why, info.software ? ", software" : "", info.drm_path.empty() ? "" : ", " + info.drm_path,
      self->robust_ ? ", robust" : "", ")");
  return self;
}

EglContext::~EglContext() {
  // The display stays initialized: EGL displays are per-device singletons
  // in the process, and eglTerminate would invalidate other contexts on it.
  if (context_) {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
  }
}

absl::Status EglContext::MakeCurrent() {
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
    return absl::FailedPreconditionError(
        absl::StrCat("EGL: eglMakeCurrent failed: ", EglErrorName(eglGetError())));
  }
  auto text = [](GLenum name) {
    const GLubyte* s = glGetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
  };
  SetCurrentQuirks(DriverQuirks::Detect(text(GL_RENDERER), text(GL_VENDOR)));
  return absl::OkStatus();
}

void EglContext::ReleaseCurrent() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

}  // namespace gistream::gl

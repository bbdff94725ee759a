// OpenEXR through OpenImageIO, written to memory via an IOProxy.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <vector>

#include "encode/encode.h"
#include "encode/encode_checks.h"
#include "encode/image_format.h"

namespace gistream {

absl::StatusOr<std::string> EncodeExr(std::span<const float> rgba, int width, int height) {
  GS_RETURN_IF_ERROR(CheckImageArgs(rgba.size(), width, height, 4, "exr"));
  ConfigureOpenImageIO();
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("openexr");
  if (!out) {
    return absl::InternalError(absl::StrCat("exr: no OpenEXR writer: ", OIIO::geterror()));
  }
  OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::FLOAT);
  spec.attribute("compression", "zip");  // lossless
  if (!out->set_ioproxy(&proxy) || !out->open("frame.exr", spec)) {
    return absl::InternalError(absl::StrCat("exr: cannot open writer: ", out->geterror()));
  }
  // Write R, G, B of each RGBA pixel: the x stride skips alpha.
  if (!out->write_image(OIIO::TypeDesc::FLOAT, rgba.data(), 4 * sizeof(float)) || !out->close()) {
    return absl::InternalError(absl::StrCat("exr: encoding failed: ", out->geterror()));
  }
  return std::string(bytes.begin(), bytes.end());
}

}  // namespace gistream

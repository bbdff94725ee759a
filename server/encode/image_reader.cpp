#include "encode/image_reader.h"

#include "encode/exr_header.h"
#include "encode/image_format.h"
#include "encode/jpeg_markers.h"
#include "encode/png_chunks.h"

namespace gistream {

absl::StatusOr<MemoryImageReader> OpenImageFromMemory(std::span<const uint8_t> bytes,
                                                      const std::string& format,
                                                      const std::string& field,
                                                      const ExrHeaderLimits& exr_limits) {
  ConfigureOpenImageIO();
  // OpenEXR allocates what its header's attributes claim before reading.
  if (format == "exr") GS_RETURN_IF_ERROR(CheckExrHeader(bytes, field, exr_limits));
  // libpng allocates a chunk's claimed length before reading it.
  if (format == "png") GS_RETURN_IF_ERROR(CheckPngChunks(bytes, field));
  MemoryImageReader reader;
  if (format == "jpeg") {
    reader.owned_bytes = StripJpegMetadata(bytes);
    bytes = reader.owned_bytes;
  }
  reader.proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(bytes.data(), bytes.size());
  reader.input = OIIO::ImageInput::create(format);
  if (!reader.input) {
    return absl::InternalError(absl::StrCat(field, ": no ", format, " reader: ", OIIO::geterror()));
  }
  OIIO::ImageSpec config;
  OIIO::Filesystem::IOProxy* proxy_ptr = reader.proxy.get();
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  // PNG alpha is straight (unassociated); keep it so, as glTF expects.
  config.attribute("oiio:UnassociatedAlpha", 1);
  if (!reader.input->open("memory." + format, reader.spec, config)) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, ": corrupt ", format, " image: ", reader.input->geterror()));
  }
  return reader;
}

}  // namespace gistream

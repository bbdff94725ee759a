#include "encode/image_reader.h"

#include <algorithm>
#include <cstring>

#include "encode/exr_header.h"
#include "encode/image_format.h"
#include "encode/jpeg_markers.h"
#include "encode/png_chunks.h"

namespace gistream {
namespace {

// OpenImageIO 2.4's IOMemReader accepts any seek and reads at a negative
// offset from before its buffer: an EXR whose line offset table holds -4
// made OpenEXR read 4 bytes before the file (heap-buffer-overflow, found
// by image_decode_fuzzer). Same reader, with every offset checked.
class BoundedMemReader final : public OIIO::Filesystem::IOMemReader {
 public:
  using IOMemReader::IOMemReader;

  bool seek(int64_t offset) override {
    if (offset < 0) return false;
    m_pos = offset;
    return true;
  }
  size_t read(void* buf, size_t size) override {
    const size_t n = pread(buf, size, m_pos);
    m_pos += int64_t(n);
    return n;
  }
  size_t pread(void* buf, size_t size, int64_t offset) override {
    const OIIO::cspan<unsigned char> data = buffer();
    if (size == 0 || offset < 0 || uint64_t(offset) >= uint64_t(data.size())) return 0;
    const size_t n = std::min(size, size_t(data.size()) - size_t(offset));
    std::memcpy(buf, data.data() + offset, n);
    return n;
  }
};

}  // namespace

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
  reader.proxy = std::make_unique<BoundedMemReader>(bytes.data(), bytes.size());
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

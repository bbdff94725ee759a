// JPEG through libjpeg-turbo. libjpeg reports errors by calling error_exit,
// which must not return; we longjmp out of a function that holds only C
// structs, so no C++ destructor is skipped.
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

// jpeglib.h uses size_t and FILE without including their headers.
#include <jpeglib.h>

#include "encode/encode.h"
#include "encode/encode_checks.h"

namespace gistream {
namespace {

struct JpegError {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

[[noreturn]] void OnJpegError(j_common_ptr cinfo) {
  auto* err = reinterpret_cast<JpegError*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, err->message);
  std::longjmp(err->jump, 1);
}

void IgnoreJpegMessage(j_common_ptr) {}

struct JpegJob {
  const uint8_t* rgba;
  int width;
  int height;
  int quality;
  unsigned char* out;  // preallocated, large enough that libjpeg never grows it
  unsigned long out_size;
  char message[JMSG_LENGTH_MAX];
};

bool RunJpeg(JpegJob* job) {
  jpeg_compress_struct cinfo;
  JpegError err;
  cinfo.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = OnJpegError;
  err.mgr.output_message = IgnoreJpegMessage;
  if (setjmp(err.jump)) {
    std::memcpy(job->message, err.message, sizeof(job->message));
    jpeg_destroy_compress(&cinfo);
    return false;
  }
  jpeg_create_compress(&cinfo);
  jpeg_mem_dest(&cinfo, &job->out, &job->out_size);
  cinfo.image_width = static_cast<JDIMENSION>(job->width);
  cinfo.image_height = static_cast<JDIMENSION>(job->height);
  cinfo.input_components = 4;
  cinfo.in_color_space = JCS_EXT_RGBA;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, job->quality, TRUE);
  cinfo.dct_method = JDCT_ISLOW;
  jpeg_start_compress(&cinfo, TRUE);
  const size_t row_bytes = static_cast<size_t>(job->width) * 4;
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(job->rgba + cinfo.next_scanline * row_bytes);
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  return true;
}

// Worst-case JPEG size (libjpeg-turbo's tjBufSize for 4:4:4): 6 bytes per
// MCU-padded pixel plus headers.
size_t JpegBound(int width, int height) {
  const size_t w = (static_cast<size_t>(width) + 15) & ~size_t{15};
  const size_t h = (static_cast<size_t>(height) + 15) & ~size_t{15};
  return w * h * 6 + 2048;
}

}  // namespace

absl::StatusOr<std::string> EncodeJpeg(std::span<const uint8_t> rgba, int width, int height,
                                       int quality) {
  GS_RETURN_IF_ERROR(CheckImageArgs(rgba.size(), width, height, 4, "jpeg"));
  if (quality < 1 || quality > 100) {
    return absl::InvalidArgumentError(
        absl::StrCat("jpeg.quality: ", quality, " is out of range [1, 100]"));
  }
  std::vector<unsigned char> buffer(JpegBound(width, height));
  JpegJob job{rgba.data(), width, height, quality, buffer.data(), buffer.size(), {}};
  if (!RunJpeg(&job)) {
    return absl::InternalError(absl::StrCat("jpeg: encoding failed: ", job.message));
  }
  std::string out(reinterpret_cast<const char*>(job.out), job.out_size);
  // Only if the bound above were wrong would libjpeg have switched buffers.
  if (job.out != buffer.data()) std::free(job.out);
  return out;
}

}  // namespace gistream

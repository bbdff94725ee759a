// PNG through libpng. Like libjpeg, libpng reports errors with longjmp, so
// the function that can be jumped out of holds only C state.
#include <png.h>

#include <csetjmp>
#include <cstring>
#include <new>

#include "encode/encode.h"
#include "encode/encode_checks.h"

namespace gistream {
namespace {

struct PngJob {
  const uint8_t* rgba;
  int width;
  int height;
  std::string* out;
  char message[256];
};

[[noreturn]] void OnPngError(png_structp png, png_const_charp message) {
  auto* job = static_cast<PngJob*>(png_get_error_ptr(png));
  std::strncpy(job->message, message, sizeof(job->message) - 1);
  std::longjmp(png_jmpbuf(png), 1);
}

void IgnorePngWarning(png_structp, png_const_charp) {}

void WriteToString(png_structp png, png_bytep data, png_size_t length) {
  auto* job = static_cast<PngJob*>(png_get_io_ptr(png));
  try {
    job->out->append(reinterpret_cast<const char*>(data), length);
  } catch (const std::bad_alloc&) {
    png_error(png, "out of memory");
  }
}

void FlushNothing(png_structp) {}

bool RunPng(PngJob* job) {
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, job, OnPngError, IgnorePngWarning);
  if (png == nullptr) {
    std::strncpy(job->message, "png_create_write_struct failed", sizeof(job->message) - 1);
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    std::strncpy(job->message, "png_create_info_struct failed", sizeof(job->message) - 1);
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, job, WriteToString, FlushNothing);
  // Frames are streamed: fast compression matters more than the last few
  // percent of size.
  png_set_compression_level(png, 1);
  png_set_IHDR(png, info, static_cast<png_uint_32>(job->width),
               static_cast<png_uint_32>(job->height), 8, PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const size_t row_bytes = static_cast<size_t>(job->width) * 4;
  for (int y = 0; y < job->height; ++y) {
    png_write_row(png, const_cast<png_bytep>(job->rgba + static_cast<size_t>(y) * row_bytes));
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

absl::StatusOr<std::string> EncodePng(std::span<const uint8_t> rgba, int width, int height) {
  GS_RETURN_IF_ERROR(CheckImageArgs(rgba.size(), width, height, 4, "png"));
  std::string out;
  PngJob job{rgba.data(), width, height, &out, {}};
  if (!RunPng(&job)) {
    return absl::InternalError(absl::StrCat("png: encoding failed: ", job.message));
  }
  return out;
}

}  // namespace gistream

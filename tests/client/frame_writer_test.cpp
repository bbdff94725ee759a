// FrameWriter: image formats give a file per frame (an unchanged frame is a
// copy of the last picture); video formats append access units to one raw
// stream file and skip unchanged frames.
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "frame_writer.h"

namespace gistream::client {
namespace frame_writer_test {

std::string Slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

v1::Frame MakeFrame(v1::ImageFormat format, const std::string& image, bool unchanged) {
  v1::Frame f;
  f.set_format(format);
  f.set_image(image);
  f.set_unchanged(unchanged);
  return f;
}

std::filesystem::path TempDir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("gistream_frame_writer_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

TEST(FrameWriter, UnchangedImageFramesRepeatTheLastPicture) {
  const auto dir = TempDir("png");
  auto writer = FrameWriter::Create(dir, v1::IMAGE_FORMAT_PNG);
  ASSERT_TRUE(writer.ok());
  // Before any picture an unchanged frame has nothing to repeat.
  EXPECT_FALSE(writer->Write(0, MakeFrame(v1::IMAGE_FORMAT_PNG, "", true)).ok());
  ASSERT_TRUE(writer->Write(0, MakeFrame(v1::IMAGE_FORMAT_PNG, "pic1", false)).ok());
  ASSERT_TRUE(writer->Write(1, MakeFrame(v1::IMAGE_FORMAT_PNG, "", true)).ok());
  EXPECT_EQ(Slurp(dir / "frame_00001.png"), "pic1");
  // A changed frame without bytes is an error.
  EXPECT_FALSE(writer->Write(2, MakeFrame(v1::IMAGE_FORMAT_PNG, "", false)).ok());
}

TEST(FrameWriter, VideoFramesGoToOneStream) {
  const auto dir = TempDir("h264");
  auto writer = FrameWriter::Create(dir, v1::IMAGE_FORMAT_H264);
  ASSERT_TRUE(writer.ok());
  ASSERT_TRUE(writer->Write(0, MakeFrame(v1::IMAGE_FORMAT_H264, "AU1", false)).ok());
  ASSERT_TRUE(writer->Write(1, MakeFrame(v1::IMAGE_FORMAT_H264, "", true)).ok());
  ASSERT_TRUE(writer->Write(2, MakeFrame(v1::IMAGE_FORMAT_H264, "AU2", false)).ok());
  EXPECT_EQ(writer->PathFor(0, v1::IMAGE_FORMAT_H264), dir / "stream.h264");
  EXPECT_EQ(Slurp(dir / "stream.h264"), "AU1AU2");
}

}  // namespace frame_writer_test
}  // namespace gistream::client

// The CLI's wait line: its text (spinner-free elapsed time, bar and ETA),
// nothing at all when disabled (not a terminal), and erased when done.
#include <chrono>
#include <stdlib.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "progress_line.h"

namespace gistream::client {
namespace progress_line_test {

using std::chrono::duration;

TEST(ProgressLine, FormatsWaitsBarsAndEtas) {
  EXPECT_EQ(FormatProgressLine("loading scene x", duration<double>(3.2), std::nullopt),
            "loading scene x... 3s");
  EXPECT_EQ(
      FormatProgressLine("reference side: pathtrace 1024/4096 spp", duration<double>(30.0), 0.25),
      "[#####...............] 25% reference side: pathtrace 1024/4096 spp, ETA 1m30s");
  EXPECT_EQ(FormatProgressLine("frame 1/36", duration<double>(2.0), 0.0),
            "[....................] 0% frame 1/36, ETA ?");
  EXPECT_EQ(FormatProgressLine("x", duration<double>(7300.0), std::nullopt), "x... 2h01m");
  // Never wider than asked.
  EXPECT_LE(FormatProgressLine(std::string(200, 'a'), duration<double>(1.0), 0.5, 40).size(), 40u);
}

// A file the line writes to through its own FILE*, read back by path (so
// reading never moves the writer's position).
class TempFile {
 public:
  TempFile() {
    char name[] = "/tmp/gistream_progress_XXXXXX";
    const int fd = mkstemp(name);
    path_ = name;
    file_ = fdopen(fd, "w");
  }
  ~TempFile() {
    std::fclose(file_);
    std::remove(path_.c_str());
  }
  std::FILE* file() const { return file_; }
  std::string Contents() const {
    std::ifstream in(path_, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
};

TEST(ProgressLine, DisabledPrintsNothing) {
  TempFile f;
  {
    ProgressLine line(f.file(), /*enabled=*/false, std::chrono::milliseconds(0));
    line.Wait("loading");
    line.Update("frame 1/2", 0.5);
    line.Done();
  }
  std::fflush(f.file());
  EXPECT_EQ(f.Contents(), "");
}

TEST(ProgressLine, ShowsAfterTheDelayAndErasesWhenDone) {
  TempFile f;
  {
    ProgressLine line(f.file(), /*enabled=*/true, std::chrono::milliseconds(0));
    line.Wait("loading scene x");
    // The ticker draws within its 250 ms period; wait for it, however long.
    while (f.Contents().find("loading scene x") == std::string::npos) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    line.Done();
  }
  const std::string out = f.Contents();
  ASSERT_GE(out.size(), 4u);
  EXPECT_EQ(out.substr(out.size() - 4), "\r\033[K") << "the line ends erased";
}

}  // namespace progress_line_test
}  // namespace gistream::client

// StreamedFile (streamed_file.hpp), what `pbd run --stats` and `--breaks` write: every record is on disk once
// append() returns, before close (a run stopped by an error or a signal keeps what it made); a file that cannot be
// written is refused when opened, before any work; a FIFO without a reader is an error, not a hang.
#include "error_checks.hpp"
#include "pbd/io/streamed_file.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>

namespace pbd {
namespace {

std::string text_of(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(StreamedFile, EveryRecordIsOnDiskOnceAppendedBeforeTheFileIsClosed) {
  const test::TempDir dir("pbd_streamed_file");
  const auto file = dir / "stats.csv";
  std::ofstream(file) << "an older, longer file that must not show through\n";
  StreamedFile csv(file, "step,value\n");
  EXPECT_EQ(text_of(file), "step,value\n") << "the header, at once";
  csv.append("1,0.5\n");
  csv.append("2,0.25\n");
  EXPECT_EQ(text_of(file), "step,value\n1,0.5\n2,0.25\n");
  csv.close();
  csv.close();
  EXPECT_EQ(text_of(file), "step,value\n1,0.5\n2,0.25\n");
  test::expect_words(test::error_of([&] { csv.append("3,0\n"); }), {"stats.csv", "after it was closed"});
}

TEST(StreamedFile, WhatCannotBeWrittenIsRefusedWhenOpened) {
  const test::TempDir dir("pbd_streamed_file");
  test::expect_words(test::error_of([&] { StreamedFile(dir.path(), "h\n"); }), {dir.path().string(), "folder"});
  test::expect_words(test::error_of([&] { StreamedFile("/nonexistent-pbd-dir/s.csv", "h\n"); }),
                     {"/nonexistent-pbd-dir/s.csv", "cannot open for writing"});
  test::expect_words(test::error_of([&] { StreamedFile("/dev/full", "h\n"); }), {"/dev/full", "No space left"});
  if (std::filesystem::is_directory("/sys/kernel"))  // sysfs: no file can be created there, even by root
    test::expect_words(test::error_of([&] { StreamedFile("/sys/kernel/pbd_stats.csv", "h\n"); }),
                       {"/sys/kernel/pbd_stats.csv", "cannot open for writing"});
}

TEST(StreamedFile, AFifoWithoutAReaderIsAnErrorNotAHang) {
  const test::TempDir dir("pbd_streamed_file");
  const auto fifo = dir / "stats.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0666), 0);
  test::expect_words(test::error_of([&] { StreamedFile(fifo, "h\n"); }), {"stats.csv", "FIFO that no process reads"});
  // With a reader, records go through it as written.
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  StreamedFile csv(fifo, "h\n");
  csv.append("1\n");
  char bytes[8] = {};
  EXPECT_EQ(::read(reader, bytes, sizeof bytes), 4);
  EXPECT_STREQ(bytes, "h\n1\n");
  ::close(reader);
}

}  // namespace
}  // namespace pbd

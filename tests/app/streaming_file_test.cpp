// StreamingFile (app/streaming_file.h) writes a file past the page cache where the filesystem allows
// it (O_DIRECT), through it where not: the bytes are what write() was given, in order, whatever the
// sizes of the pieces and of the whole, and a file that cannot be created or written is named in the
// error (issue 11 item 8).
#include "streaming_file.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace predvs {
namespace {

namespace fs = std::filesystem;

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// n pseudo-random bytes (seeded).
std::string bytes(size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (char& c : s) c = static_cast<char>(rng() & 0xff);
  return s;
}

/// Writes `content` through StreamingFile (O_DIRECT where possible when `direct`) at `path` in pieces
/// of the given sizes (cycled) and closes it; returns whether the writes bypassed the page cache when
/// the file was opened.
bool writeInPieces(const fs::path& path, const std::string& content, const std::vector<size_t>& pieces,
                   bool direct = true) {
  StreamingFile f(path.string(), direct);
  const bool was_direct = f.direct();
  size_t at = 0, k = 0;
  while (at < content.size()) {
    const size_t n = std::min(pieces[k++ % pieces.size()], content.size() - at);
    f.write(content.data() + at, n);
    at += n;
  }
  f.close();
  return was_direct;
}

TEST(StreamingFile, WritesTheBytesGivenWhateverTheSizes) {
  const fs::path dir = fs::temp_directory_path() / "predvs_streaming_file";
  fs::create_directories(dir);
  constexpr size_t kBuf = StreamingFile::kBufferBytes, kAlign = StreamingFile::kAlignment;
  // GIVEN files empty, of one byte, of whole and partial blocks and buffers, and of three buffers
  // and a tail, written in pieces of 1 byte to more than a buffer, past the page cache where the
  // filesystem allows it and through it
  const std::vector<size_t> sizes = {0, 1, kAlign - 1, kAlign, kAlign + 1, kBuf - 1, kBuf, kBuf + kAlign, 3 * kBuf + 12345};
  const std::vector<std::vector<size_t>> pieces = {{1, 7, 4093}, {640000}, {kBuf + 1}, {kAlign}};
  int case_no = 0;
  for (bool direct : {true, false})
    for (size_t size : sizes)
      for (const auto& p : pieces) {
        if (size > kBuf + kAlign && p.front() == 1) continue;  // byte by byte over megabytes: slow, same path
        const std::string content = bytes(size, static_cast<std::uint32_t>(++case_no));
        const fs::path path = dir / ("f" + std::to_string(case_no) + ".bin");
        writeInPieces(path, content, p, direct);
        // THEN the file holds exactly those bytes
        const std::string back = readAll(path);
        EXPECT_EQ(back.size(), content.size()) << "size " << size << ", first piece " << p.front() << ", direct " << direct;
        EXPECT_TRUE(back == content) << "size " << size << ", first piece " << p.front() << ", direct " << direct;
        fs::remove(path);
      }
  fs::remove_all(dir);
}

TEST(StreamingFile, WritesTheSameBytesOnTmpfs) {
  // GIVEN tmpfs (/dev/shm on Linux: it refused O_DIRECT before Linux 6.6, takes it since)
  const fs::path shm = "/dev/shm";
  if (!fs::is_directory(shm)) GTEST_SKIP() << "no /dev/shm";
  const fs::path path = shm / "predvs_streaming_file_test.bin";
  const std::string content = bytes(2 * StreamingFile::kBufferBytes + 999, 7);
  // WHEN a file is written there
  writeInPieces(path, content, {100000});
  // THEN it holds the same bytes, whichever way it went
  EXPECT_TRUE(readAll(path) == content);
  fs::remove(path);
}

TEST(StreamingFile, NamesAFileItCannotCreate) {
  const std::string path = (fs::temp_directory_path() / "predvs_no_such_dir" / "x.csv").string();
  try {
    StreamingFile f(path);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(StreamingFile, NamesAFileItCannotWrite) {
  // GIVEN a device that is full on every write (/dev/full)
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const std::string content = bytes(3 * StreamingFile::kBufferBytes, 3);
  // WHEN more than a buffer is written and the file closed
  try {
    StreamingFile f("/dev/full");
    f.write(content.data(), content.size());
    f.close();
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    // THEN the failure names the file
    EXPECT_NE(std::string(e.what()).find("/dev/full"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace predvs

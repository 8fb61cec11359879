// predvs app — a large output file written front to back past the page cache.
//
// `predvs predict` writes predictions.csv of a 2-million-row track, 626 MB, in one pass and never
// reads it back. Written through the page cache (std::ofstream, write(2)), the kernel copies every
// byte into freshly zeroed cache pages: on the measured machine 1.4-1.5 s of system CPU for those
// 626 MB (`dd bs=4M`: 413 MB/s), plus the writeback after it. Opened with O_DIRECT, the device reads
// the bytes straight from the process's buffer (`dd bs=4M oflag=direct`: 0.38 s, 0.11 s of CPU).
// StreamingFile gathers what it is given in 4 MB buffers aligned to 4 kB; each full buffer is
// written whole by a thread of its own, which waits on the device while the caller fills the next
// buffer (two buffers in all), so the device's time is off the caller's path; the last partial
// block goes through the page cache (O_DIRECT takes whole aligned blocks). Where the filesystem
// refuses O_DIRECT (tmpfs, some network filesystems) or a direct write fails for its alignment, the
// file is written the usual way from there on: only the speed depends on it, never the bytes
// (docs/PERFORMANCE.md "`predvs predict` throughput", "Twelfth pass").
#pragma once

#include <condition_variable>
#include <cstddef>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace predvs {

class StreamingFile {
 public:
  /// Creates (truncates) the file, opened with O_DIRECT when `direct` and the filesystem allows it
  /// (false: through the page cache, as tests compare); throws std::runtime_error naming it when it
  /// cannot.
  explicit StreamingFile(const std::string& path, bool direct = true);
  /// Closes a file that close() did not, without reporting.
  ~StreamingFile();
  StreamingFile(const StreamingFile&) = delete;
  StreamingFile& operator=(const StreamingFile&) = delete;

  /// Appends n bytes; throws std::runtime_error naming the file when a write failed (this one or
  /// an earlier buffer's, written in the background).
  void write(const char* data, size_t n);
  /// Writes what is gathered and closes the file; throws std::runtime_error naming it on failure.
  void close();
  /// True while the writes bypass the page cache (O_DIRECT), for tests.
  bool direct() const { return direct_; }

  /// The gathering buffer (bytes; a multiple of kAlignment).
  static constexpr size_t kBufferBytes = size_t{4} << 20;
  /// The alignment of the buffers and of every direct write's size (bytes).
  static constexpr size_t kAlignment = 4096;

 private:
  struct FreeAligned {
    void operator()(char* p) const;
  };
  using Buffer = std::unique_ptr<char, FreeAligned>;
  static Buffer alignedBuffer();
  /// Writes the first n bytes of b (n a multiple of kAlignment while direct); throws on failure.
  void writeOut(const char* b, size_t n);
  /// Clears O_DIRECT: the writes go through the page cache from now on.
  void stopDirect();
  /// Hands the full buffer to the writing thread (started on the first call), after the buffer
  /// before it is written; rethrows that write's failure.
  void submitFull();
  /// Waits until the writing thread has no buffer; rethrows its failure.
  void waitWritten();
  /// Stops and joins the writing thread (no-op when none).
  void stopThread();

  std::string path_;
  int fd_ = -1;
  bool direct_ = false;
  Buffer filling_;  ///< the buffer write() fills
  size_t used_ = 0;
  Buffer spare_;    ///< the other one: written by the thread, or free
  // The writing thread's side, under mutex_.
  std::thread writer_;
  std::mutex mutex_;
  std::condition_variable changed_;
  const char* pending_ = nullptr;  ///< a full buffer to write (nullptr: none)
  bool stop_ = false;
  std::exception_ptr failure_;
};

}  // namespace predvs

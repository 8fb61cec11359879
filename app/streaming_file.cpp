#include "streaming_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>

namespace predvs {

void StreamingFile::FreeAligned::operator()(char* p) const { std::free(p); }

StreamingFile::Buffer StreamingFile::alignedBuffer() {
  Buffer b(static_cast<char*>(std::aligned_alloc(kAlignment, kBufferBytes)));
  if (!b) throw std::bad_alloc();
  return b;
}

StreamingFile::StreamingFile(const std::string& path, bool direct) : path_(path), filling_(alignedBuffer()) {
#ifdef O_DIRECT
  if (direct) {
    fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | O_DIRECT, 0644);
    direct_ = fd_ >= 0;
  }
#else
  (void)direct;
#endif
  if (fd_ < 0) fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error(path + ": cannot create: " + std::strerror(errno));
}

StreamingFile::~StreamingFile() {
  stopThread();
  if (fd_ >= 0) ::close(fd_);
}

void StreamingFile::write(const char* data, size_t n) {
  while (n > 0) {
    const size_t take = std::min(n, kBufferBytes - used_);
    std::memcpy(filling_.get() + used_, data, take);
    used_ += take;
    data += take;
    n -= take;
    if (used_ == kBufferBytes) submitFull();
  }
}

void StreamingFile::submitFull() {
  waitWritten();
  if (!spare_) spare_ = alignedBuffer();
  if (!writer_.joinable()) {
    writer_ = std::thread([this] {
      std::unique_lock<std::mutex> lock(mutex_);
      for (;;) {
        changed_.wait(lock, [&] { return pending_ != nullptr || stop_; });
        if (pending_ == nullptr) return;  // stopped, nothing left
        const char* b = pending_;
        lock.unlock();
        std::exception_ptr failure;
        try {
          writeOut(b, kBufferBytes);
        } catch (...) {
          failure = std::current_exception();
        }
        lock.lock();
        if (failure) failure_ = failure;
        pending_ = nullptr;
        changed_.notify_all();
      }
    });
  }
  std::swap(filling_, spare_);  // spare_ now holds the full buffer, which the thread writes
  used_ = 0;
  std::lock_guard<std::mutex> lock(mutex_);
  pending_ = spare_.get();
  changed_.notify_all();
}

void StreamingFile::waitWritten() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return pending_ == nullptr; });
  if (failure_) std::rethrow_exception(failure_);
}

void StreamingFile::stopThread() {
  if (!writer_.joinable()) return;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return pending_ == nullptr; });
    stop_ = true;
    changed_.notify_all();
  }
  writer_.join();
}

void StreamingFile::close() {
  if (fd_ < 0) return;
  waitWritten();
  stopThread();
  const size_t whole = direct_ ? used_ / kAlignment * kAlignment : used_;
  if (whole > 0) writeOut(filling_.get(), whole);
  if (whole < used_) {  // the last partial block: O_DIRECT takes whole blocks only
    stopDirect();
    writeOut(filling_.get() + whole, used_ - whole);
  }
  used_ = 0;
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) throw std::runtime_error(path_ + ": write failed: " + std::strerror(errno));
}

void StreamingFile::writeOut(const char* b, size_t n) {
  size_t done = 0;
  while (done < n) {
    const ssize_t w = ::write(fd_, b + done, n - done);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0 && errno == EINVAL && direct_) {  // this device's alignment is not 4 kB: the usual way
      stopDirect();
      continue;
    }
    if (w <= 0) throw std::runtime_error(path_ + ": write failed: " + (w < 0 ? std::strerror(errno) : "no progress"));
    done += static_cast<size_t>(w);
    // A short direct write leaves the file at an offset O_DIRECT may not accept next.
    if (direct_ && done < n) stopDirect();
  }
}

void StreamingFile::stopDirect() {
  if (!direct_) return;
  direct_ = false;
#ifdef O_DIRECT
  const int flags = ::fcntl(fd_, F_GETFL);
  if (flags < 0 || ::fcntl(fd_, F_SETFL, flags & ~O_DIRECT) < 0)
    throw std::runtime_error(path_ + ": cannot leave O_DIRECT: " + std::strerror(errno));
#endif
}

}  // namespace predvs

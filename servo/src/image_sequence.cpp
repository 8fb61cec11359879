#include "predvs/servo/image_sequence.h"

#include <visp3/core/vpException.h>
#include <visp3/core/vpImageConvert.h>
#include <visp3/io/vpImageIo.h>

#include <opencv2/core.hpp>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <vector>

namespace fs = std::filesystem;

namespace predvs {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool isImageFile(const fs::path& p) {
  static const char* exts[] = {".pgm", ".ppm", ".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff"};
  const std::string e = lower(p.extension().string());
  for (const char* x : exts)
    if (e == x) return true;
  return false;
}

std::invalid_argument openError(const std::string& spec, const std::string& why) {
  return std::invalid_argument("images '" + spec + "': " + why);
}

/// Reads one image file into grey; false with `why` on any failure (never throws).
bool readImageFile(const std::string& path, vpImage<unsigned char>& image, std::string& why) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    why = "missing file";
    return false;
  }
  try {
    vpImageIo::read(image, path);
  } catch (const vpException& e) {
    why = std::string("unreadable or corrupt image (") + e.getStringMessage() + ")";
    return false;
  } catch (const std::exception& e) {
    why = std::string("unreadable or corrupt image (") + e.what() + ")";
    return false;
  }
  if (image.getWidth() == 0 || image.getHeight() == 0) {
    why = "unreadable or corrupt image (empty)";
    return false;
  }
  return true;
}

/// The common part: size check against the first frame, time stamps, frame budget.
class SequenceBase : public ImageSequence {
 public:
  explicit SequenceBase(const ImageSequenceOptions& options) : options_(options) {}
  unsigned width() const override { return width_; }
  unsigned height() const override { return height_; }

 protected:
  /// Applies the size rule to a frame that was read; Skipped with the reason when it differs.
  ImageRead accept(ImageFrame& frame, std::string& why) {
    if (width_ == 0) {
      width_ = frame.image.getWidth();
      height_ = frame.image.getHeight();
    } else if (frame.image.getWidth() != width_ || frame.image.getHeight() != height_) {
      why = "size " + std::to_string(frame.image.getWidth()) + "x" + std::to_string(frame.image.getHeight()) +
            " differs from the sequence's " + std::to_string(width_) + "x" + std::to_string(height_);
      return ImageRead::Skipped;
    }
    return ImageRead::Ok;
  }
  bool budgetLeft() {
    if (options_.max_frames >= 0 && delivered_ >= options_.max_frames) return false;
    ++delivered_;
    return true;
  }
  ImageSequenceOptions options_;
  unsigned width_ = 0, height_ = 0;
  long delivered_ = 0;
};

/// Files named by a list (pattern indices or a directory listing); a missing entry is a skip.
class FileListSequence : public SequenceBase {
 public:
  struct Entry {
    long index;
    std::string path;  ///< empty: no file for this index
  };
  FileListSequence(std::vector<Entry> entries, long first, std::string description, const ImageSequenceOptions& options)
      : SequenceBase(options), entries_(std::move(entries)), first_(first), description_(std::move(description)) {}

  ImageRead next(ImageFrame& frame, std::string& why) override {
    if (pos_ >= entries_.size() || !budgetLeft()) return ImageRead::End;
    const Entry& e = entries_[pos_++];
    frame.index = e.index;
    frame.t_s = static_cast<double>(e.index - first_) * options_.frame_period_s;
    frame.origin = e.path;
    why.clear();
    if (e.path.empty() || !readImageFile(e.path, frame.image, why)) {
      if (why.empty()) why = "missing file";
      return ImageRead::Skipped;
    }
    return accept(frame, why);
  }
  long size() const override {
    const long n = static_cast<long>(entries_.size());
    return options_.max_frames >= 0 ? std::min(n, options_.max_frames) : n;
  }
  std::string describe() const override { return description_; }

 private:
  std::vector<Entry> entries_;
  size_t pos_ = 0;
  long first_ = 0;
  std::string description_;
};

/// A video decoded by OpenCV (cv::VideoCapture, so ViSP's vpVideoReader repeated first frame
/// after open() does not arise here).
class VideoSequence : public SequenceBase {
 public:
  VideoSequence(const std::string& spec, const ImageSequenceOptions& options) : SequenceBase(options), spec_(spec) {
    // OpenCV logs every backend it tries on stderr: silence it while opening (the error here is
    // one line), FFmpeg first, then any other backend.
    const auto level = cv::utils::logging::getLogLevel();
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
    bool opened = false, decoded = false;
    try {
      opened = capture_.open(spec, cv::CAP_FFMPEG) || capture_.open(spec, cv::CAP_ANY);
      // Decode the first frame now, so that an unreadable video fails at open time.
      decoded = opened && capture_.read(first_) && !first_.empty();
    } catch (const cv::Exception&) {
    }
    cv::utils::logging::setLogLevel(level);
    if (!opened) throw openError(spec, "cannot open the video (not an image, pattern, directory or readable video)");
    if (!decoded) throw openError(spec, "cannot decode any frame of the video");
    const double n = capture_.get(cv::CAP_PROP_FRAME_COUNT);
    frame_count_ = n > 0 ? static_cast<long>(n) : -1;
  }

  ImageRead next(ImageFrame& frame, std::string& why) override {
    if (!budgetLeft()) return ImageRead::End;
    frame.index = pos_;
    frame.t_s = static_cast<double>(pos_) * options_.frame_period_s;
    frame.origin = "video:" + std::to_string(pos_);
    why.clear();
    cv::Mat bgr;
    bool ok;
    if (pos_ == 0) {
      bgr = first_;
      ok = true;
    } else {
      try {
        ok = capture_.read(bgr) && !bgr.empty();
      } catch (const cv::Exception&) {
        ok = false;
      }
    }
    ++pos_;
    if (!ok) {
      // Before the announced frame count a failed decode is a corrupt frame, after it the end.
      if (frame_count_ > 0 && pos_ < frame_count_ && ++failures_ < kMaxConsecutiveFailures) {
        why = "frame could not be decoded";
        return ImageRead::Skipped;
      }
      return ImageRead::End;
    }
    failures_ = 0;
    cv::Mat grey;
    if (bgr.channels() == 1) {
      grey = bgr;
    } else {
      cv::cvtColor(bgr, grey, bgr.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
    }
    if (grey.depth() != CV_8U) grey.convertTo(grey, CV_8U);
    vpImageConvert::convert(grey, frame.image);
    return accept(frame, why);
  }
  /// Unknown: the container's frame count is not reliable (MPEG-1 streams report 1).
  long size() const override { return -1; }
  std::string describe() const override {
    return "video " + spec_ + (frame_count_ > 0 ? " (container says " + std::to_string(frame_count_) + " frames)" : "");
  }

 private:
  static constexpr int kMaxConsecutiveFailures = 10;
  std::string spec_;
  cv::VideoCapture capture_;
  cv::Mat first_;
  long frame_count_ = -1;
  long pos_ = 0;
  int failures_ = 0;
};

/// "dir/image.%04d.pgm" -> the position of the one integer conversion; throws otherwise.
bool findConversion(const std::string& name, size_t& begin, size_t& end) {
  size_t count = 0;
  for (size_t i = 0; i < name.size(); ++i) {
    if (name[i] != '%') continue;
    if (i + 1 < name.size() && name[i + 1] == '%') {
      ++i;
      continue;
    }
    size_t j = i + 1;
    while (j < name.size() && (std::isdigit(static_cast<unsigned char>(name[j])) || name[j] == '0')) ++j;
    if (j < name.size() && name[j] == 'l') ++j;
    if (j >= name.size() || (name[j] != 'd' && name[j] != 'i' && name[j] != 'u')) return false;
    begin = i;
    end = j + 1;
    ++count;
    i = j;
  }
  return count == 1;
}

std::string formatIndex(const std::string& pattern, long index) {
  // Normalise the conversion to %l? so that a long is passed whatever the user wrote.
  size_t b = 0, e = 0;
  findConversion(pattern, b, e);
  std::string conv = pattern.substr(b, e - b);
  if (conv.find('l') == std::string::npos) conv.insert(conv.size() - 1, "l");
  const std::string fmt = pattern.substr(0, b) + conv + pattern.substr(e);
  std::vector<char> buf(fmt.size() + 32);
  std::snprintf(buf.data(), buf.size(), fmt.c_str(), index);
  return std::string(buf.data());
}

std::unique_ptr<ImageSequence> openPattern(const std::string& spec, const ImageSequenceOptions& options) {
  const fs::path p(spec);
  const std::string name = p.filename().string();
  size_t b = 0, e = 0;
  if (p.parent_path().string().find('%') != std::string::npos || !findConversion(name, b, e))
    throw openError(spec, "a pattern needs exactly one integer conversion (e.g. %04d) in the file name");
  const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw openError(spec, "no directory '" + dir.string() + "'");
  const std::string prefix = name.substr(0, b), suffix = name.substr(e);
  std::map<long, std::string> found;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string f = entry.path().filename().string();
    if (f.size() <= prefix.size() + suffix.size() || f.compare(0, prefix.size(), prefix) != 0 ||
        f.compare(f.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string digits = f.substr(prefix.size(), f.size() - prefix.size() - suffix.size());
    if (digits.empty() || digits.size() > 15 ||
        !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
      continue;
    const long index = std::stol(digits);
    if (formatIndex(name, index) != f) continue;  // another width of the number
    found[index] = (dir / f).string();
  }
  if (found.empty()) throw openError(spec, "no file matches the pattern");
  long first = found.begin()->first;
  if (options.first >= 0) first = options.first;
  const long last = found.rbegin()->first;
  if (first > last) throw openError(spec, "no file at or after index " + std::to_string(first));
  std::vector<FileListSequence::Entry> entries;
  for (long i = first; i <= last; ++i) {
    const auto it = found.find(i);
    entries.push_back({i, it == found.end() ? std::string() : it->second});
  }
  const std::string description = "pattern " + spec + " (indices " + std::to_string(first) + ".." +
                                  std::to_string(last) + ", " + std::to_string(entries.size()) + " frames)";
  return std::make_unique<FileListSequence>(std::move(entries), first, description, options);
}

std::unique_ptr<ImageSequence> openDirectory(const std::string& spec, const ImageSequenceOptions& options) {
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(spec, ec))
    if (entry.is_regular_file(ec) && isImageFile(entry.path())) files.push_back(entry.path().string());
  if (ec) throw openError(spec, "cannot list the directory (" + ec.message() + ")");
  if (files.empty()) throw openError(spec, "the directory holds no image file (pgm, ppm, png, jpg, jpeg, bmp, tif, tiff)");
  std::sort(files.begin(), files.end());
  std::vector<FileListSequence::Entry> entries;
  for (size_t i = 0; i < files.size(); ++i) entries.push_back({static_cast<long>(i), files[i]});
  const std::string description = "directory " + spec + " (" + std::to_string(files.size()) + " images)";
  return std::make_unique<FileListSequence>(std::move(entries), 0, description, options);
}

}  // namespace

std::unique_ptr<ImageSequence> openImageSequence(const std::string& spec, const ImageSequenceOptions& options) {
  if (!(options.frame_period_s > 0.0)) throw openError(spec, "the frame period must be > 0 s");
  if (spec.empty()) throw std::invalid_argument("images '': expected a pattern, a directory or a video file");
  std::error_code ec;
  if (spec.find('%') != std::string::npos && !fs::exists(spec, ec)) return openPattern(spec, options);
  if (fs::is_directory(spec, ec)) return openDirectory(spec, options);
  if (!fs::exists(spec, ec)) throw openError(spec, "no such file or directory");
  if (isImageFile(spec)) {
    // One image: a sequence of one frame (e.g. ViSP-images/AprilTag/AprilTag.pgm).
    vpImage<unsigned char> probe;
    std::string why;
    if (!readImageFile(spec, probe, why)) throw openError(spec, why);
    std::vector<FileListSequence::Entry> entries{{0, spec}};
    return std::make_unique<FileListSequence>(std::move(entries), 0, "image " + spec, options);
  }
  return std::make_unique<VideoSequence>(spec, options);
}

}  // namespace predvs

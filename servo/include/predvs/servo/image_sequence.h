// predvs — image streams: a recorded sequence read frame by frame.
//
// A sequence is opened from one specification string:
//   - a printf pattern with one integer conversion ("dir/image.%04d.pgm"): the directory is
//     listed once at open(); the frames are the indices from the smallest one with a file (or
//     `first`) to the largest one with a file; an index in between with no file is a Skipped
//     frame ("missing file"), so a hole in a recording is logged, not the end of it;
//   - a directory: every image file in it (pgm, ppm, png, jpg, jpeg, bmp, tif, tiff), in
//     lexicographic order of name (index = rank from 0);
//   - one image file (those extensions): a sequence of one frame;
//   - a video file (any other existing file): decoded frame by frame by OpenCV's cv::VideoCapture
//     (index = frame number from 0; ViSP's vpVideoReader, which returns the first frame twice
//     after open(), is not used). A frame that fails to decode before the container's frame
//     count is Skipped (up to 10 in a row), after it the video ends; size() is -1 (that count is
//     not reliable: MPEG-1 streams report 1). The first frame is decoded at open(), so an
//     unreadable video fails there.
// Frames are converted to 8-bit grey. Each frame is stamped with its acquisition time
// t = (index - first) * frame_period_s (a recorded sequence carries no clock of its own).
//
// Robustness: a missing, unreadable or corrupt frame, or a frame whose size differs from the
// first frame's, is a Skipped status with the reason (the caller logs it and goes on), never an
// exception. Only a specification that cannot be opened at all (no file, unreadable video, empty
// directory) throws std::invalid_argument with a one-line message naming it.
#pragma once

#include <visp3/core/vpImage.h>

#include <memory>
#include <string>

namespace predvs {

/// One frame of a sequence.
struct ImageFrame {
  long index = 0;             ///< frame number in the sequence (pattern index, file rank, video frame)
  double t_s = 0.0;           ///< acquisition time stamp (s)
  std::string origin;         ///< the file it came from (or "video:<n>")
  vpImage<unsigned char> image;
};

/// What next() returned.
enum class ImageRead { Ok, Skipped, End };

struct ImageSequenceOptions {
  double frame_period_s = 1.0 / 30.0;  ///< the time stamp step between consecutive frames
  long first = -1;                     ///< pattern: first index (-1: the smallest index with a file)
  long max_frames = -1;                ///< stop after this many frames, skipped ones included (-1: all)
};

class ImageSequence {
 public:
  virtual ~ImageSequence() = default;
  /// Reads the next frame into `frame`. Ok: `frame` holds it. Skipped: `frame.index`/`origin` name
  /// the frame and `why` says what was wrong (the sequence goes on). End: no more frames.
  virtual ImageRead next(ImageFrame& frame, std::string& why) = 0;
  /// Number of frames when known in advance, -1 otherwise.
  virtual long size() const = 0;
  /// Size of the frames (that of the first readable frame; 0 before it is read).
  virtual unsigned width() const = 0;
  virtual unsigned height() const = 0;
  /// "pattern dir/image.%04d.pgm (501 frames)" and the like.
  virtual std::string describe() const = 0;
};

/// Opens `spec` (see above). Throws std::invalid_argument "images 'spec': reason" when it cannot.
std::unique_ptr<ImageSequence> openImageSequence(const std::string& spec, const ImageSequenceOptions& options = {});

}  // namespace predvs

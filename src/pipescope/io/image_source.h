#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <future>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipescope/io/dataset.h"

namespace pipescope {

// One frame of a sequence. `grey` is single-channel CV_32F in 8-bit grey levels (0..255; 16-bit
// input is scaled by 255/65535) so thresholds mean the same for every input depth; with
// ImageSourceOptions::native_depth it keeps the decoded depth (CV_8U or CV_16U; colour is still
// made grey), and GreyLevelsPerUnit() gives the scale.
struct Frame {
  std::size_t index = 0;  // position in the sequence, counting skipped frames
  double timestamp = 0.0;
  std::string name;  // file name, or "frame N" for video
  cv::Mat grey;
};

struct ImageSourceOptions {
  // Expected frame size from camera.yaml; 0 disables the check.
  int expected_width = 0;
  int expected_height = 0;
  // Frames in the depth they were decoded in, for pipelines that fold the conversion into their
  // own first pass.
  bool native_depth = false;
  // Decode the next frame on a second thread while the caller works on this one: PNG decoding
  // costs as much as a dense pair registration.
  bool read_ahead = true;
  // When set, only the frames whose index it accepts are decoded and returned; the others are
  // passed over without decoding (a mosaic that needs one frame in dozens). Indices and
  // timestamps stay those of the whole sequence.
  std::function<bool(std::size_t index)> wanted = {};
};

// Streams the frames of a dataset one at a time, so a 26 000-frame run holds one frame in
// memory. A frame that cannot be decoded is skipped with a warning and counted; a frame whose
// size differs from the camera's is an InputError, since every later frame would be wrong too.
class ImageSource {
 public:
  virtual ~ImageSource() = default;

  // Opens the folder or video the manifest names. Throws InputError for a missing or empty
  // folder, an unreadable video, or a timestamps file whose length does not match.
  static std::unique_ptr<ImageSource> Open(const DatasetManifest& manifest,
                                           const ImageSourceOptions& options = {});

  // The next usable frame, or nullopt at the end.
  std::optional<Frame> Next();

  // Number of frames in the sequence, if known (0 otherwise).
  virtual std::size_t FrameCount() const = 0;

  const std::vector<std::string>& skipped_frames() const { return skipped_frames_; }

 protected:
  ImageSource(std::vector<double> timestamps, double fps, ImageSourceOptions options);

  // Reads the raw frame at the current position; returns false at the end. Sets `image` empty
  // for an undecodable frame. Called from one thread at a time, in order.
  // With decode false the frame is passed over: `image` stays empty.
  virtual bool ReadRaw(cv::Mat* image, std::string* name, bool decode) = 0;

  // Waits for a frame being read ahead. Every derived class calls it first in its destructor:
  // the reading thread uses the derived class's members.
  void StopReadingAhead();

 private:
  struct RawFrame {
    bool more = false;   // false at the end of the sequence
    bool wanted = true;  // false: passed over without decoding (options.wanted)
    cv::Mat image;
    std::string name;
  };
  RawFrame ReadNextRaw();
  double TimestampOf(std::size_t index) const;

  std::vector<double> timestamps_;  // from the timestamps file; empty: index / fps
  double fps_;
  ImageSourceOptions options_;
  std::size_t next_index_ = 0;
  std::size_t raw_index_ = 0;  // the next frame ReadNextRaw reads (its thread only)
  std::vector<std::string> skipped_frames_;
  std::filesystem::path camera_path_;
  std::size_t previous_fingerprint_ = 0;
  std::future<RawFrame> ahead_;  // the next raw frame, when reading ahead
};

// Why a decoded frame cannot be used, or "" when it can: uniform (black, white, no signal), or
// the same image as the frame before (`previous_fingerprint` carries a hash of each frame to the
// next). Such a frame tells no method anything and would read as "no motion".
std::string UnusableFrameFlaw(const cv::Mat& raw, std::size_t* previous_fingerprint);

// The factor from a frame's pixel values to 8-bit grey levels: 255 / 65535 for CV_16U, 1 for
// CV_8U and float.
double GreyLevelsPerUnit(int depth);

// The fraction of `grey`'s pixels (any depth) at or above `level` 8-bit grey levels.
double SaturatedFraction(const cv::Mat& grey, double level);

// Converts an 8- or 16-bit, grey or colour image to CV_32F grey in 8-bit grey levels.
cv::Mat ToFloatGrey(const cv::Mat& image);

// Image files of a folder (PNG, JPEG, TIFF, BMP), sorted by file name.
std::vector<std::filesystem::path> ListImageFiles(const std::filesystem::path& folder);

// The images named on a command line (`IMAGES...`): files as given, folders expanded to their
// images by ListImageFiles. Throws InputError for a missing path or a folder without images.
std::vector<std::filesystem::path> ExpandImageArguments(const std::vector<std::string>& arguments);

// Reads a timestamps file: one time in seconds per line, '#' comments allowed.
std::vector<double> ReadTimestampsFile(const std::filesystem::path& path);

}  // namespace pipescope

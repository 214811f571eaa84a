#include "pipescope/io/image_source.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <sstream>
#include <string_view>

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

bool HasImageExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg" ||
         extension == ".tif" || extension == ".tiff" || extension == ".bmp" ||
         extension == ".pgm" || extension == ".ppm";
}

// Decodes an image file; empty when it cannot be. A PNG without its closing IEND chunk or a JPEG
// without its end marker is cut short (a copy or a capture that stopped): refused here, before
// libpng or libjpeg print their complaints over the terminal.
cv::Mat DecodeImageFile(const std::filesystem::path& file) {
  std::ifstream stream(file, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(stream)),
                                std::istreambuf_iterator<char>());
  if (bytes.size() < 16) return {};
  const std::string_view all(bytes.data(), bytes.size());
  if (all.starts_with("\x89PNG") && all.substr(all.size() - 8, 4) != "IEND") return {};
  if (all.starts_with("\xFF\xD8") &&
      all.substr(all.size() - std::min<std::size_t>(all.size(), 64)).find("\xFF\xD9") ==
          std::string_view::npos) {
    return {};
  }
  return cv::imdecode(bytes, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
}

class FolderImageSource : public ImageSource {
 public:
  FolderImageSource(std::vector<std::filesystem::path> files, std::vector<double> timestamps,
                    double fps, ImageSourceOptions options)
      : ImageSource(std::move(timestamps), fps, options), files_(std::move(files)) {}

  ~FolderImageSource() override { StopReadingAhead(); }

  std::size_t FrameCount() const override { return files_.size(); }

 protected:
  bool ReadRaw(cv::Mat* image, std::string* name, bool decode) override {
    if (position_ >= files_.size()) return false;
    const std::filesystem::path& file = files_[position_++];
    *name = file.string();
    if (decode) *image = DecodeImageFile(file);
    return true;
  }

 private:
  std::vector<std::filesystem::path> files_;
  std::size_t position_ = 0;
};

class VideoImageSource : public ImageSource {
 public:
  VideoImageSource(const std::filesystem::path& video, std::vector<double> timestamps, double fps,
                   ImageSourceOptions options)
      : ImageSource(std::move(timestamps), fps, options) {
    if (!std::filesystem::is_regular_file(video)) {
      throw InputError("video not found: " + video.string());
    }
    capture_.open(video.string());
    if (!capture_.isOpened()) {
      throw InputError("cannot open video " + video.string());
    }
    const double count = capture_.get(cv::CAP_PROP_FRAME_COUNT);
    frame_count_ = count > 0 ? static_cast<std::size_t>(count) : 0;
  }

  ~VideoImageSource() override { StopReadingAhead(); }

  std::size_t FrameCount() const override { return frame_count_; }

 protected:
  bool ReadRaw(cv::Mat* image, std::string* name, bool decode) override {
    *name = "frame " + std::to_string(position_++);
    return decode ? capture_.read(*image) : capture_.grab();
  }

 private:
  cv::VideoCapture capture_;
  std::size_t frame_count_ = 0;
  std::size_t position_ = 0;
};

}  // namespace

double GreyLevelsPerUnit(int depth) {
  switch (depth) {
    case CV_8U:
      return 1.0;
    case CV_16U:
      return 255.0 / 65535.0;
    case CV_32F:
    case CV_64F:
      return 1.0;  // already in grey levels
    default:
      throw InputError("unsupported image depth (expected 8- or 16-bit)");
  }
}

namespace {

cv::Mat ToGrey(const cv::Mat& image) {
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  } else {
    grey = image;
  }
  GreyLevelsPerUnit(grey.depth());  // rejects other depths
  return grey;
}

}  // namespace

cv::Mat ToFloatGrey(const cv::Mat& image) {
  const cv::Mat grey = ToGrey(image);
  cv::Mat result;
  grey.convertTo(result, CV_32F, GreyLevelsPerUnit(grey.depth()));
  return result;
}

std::vector<std::filesystem::path> ListImageFiles(const std::filesystem::path& folder) {
  if (!std::filesystem::is_directory(folder)) {
    throw InputError("image folder not found: " + folder.string());
  }
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.is_regular_file() && HasImageExtension(entry.path())) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end(),
            [](const auto& a, const auto& b) { return a.filename() < b.filename(); });
  return files;
}

std::vector<std::filesystem::path> ExpandImageArguments(const std::vector<std::string>& arguments) {
  std::vector<std::filesystem::path> files;
  for (const std::string& argument : arguments) {
    if (std::filesystem::is_directory(argument)) {
      const std::vector<std::filesystem::path> folder = ListImageFiles(argument);
      if (folder.empty()) throw InputError("folder " + argument + " holds no images");
      files.insert(files.end(), folder.begin(), folder.end());
    } else if (std::filesystem::is_regular_file(argument)) {
      files.emplace_back(argument);
    } else {
      throw InputError("image not found: " + argument);
    }
  }
  return files;
}

std::vector<double> ReadTimestampsFile(const std::filesystem::path& path) {
  std::ifstream stream(path);
  if (!stream) throw InputError("cannot read timestamps file " + path.string());
  std::vector<double> timestamps;
  std::string line;
  int line_number = 0;
  while (std::getline(stream, line)) {
    ++line_number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    double time = 0;
    if (!(fields >> time) || !std::isfinite(time)) {
      throw InputError(path.string() + ":" + std::to_string(line_number) +
                       ": expected a time in seconds");
    }
    if (!timestamps.empty() && !(time > timestamps.back())) {
      throw InputError(path.string() + ":" + std::to_string(line_number) +
                       ": times must increase from frame to frame (" +
                       std::string(line.substr(first, line.find_first_of(" \t\r", first) - first)) +
                       " follows a time no earlier)");
    }
    timestamps.push_back(time);
  }
  if (timestamps.empty()) {
    throw InputError("timestamps file " + path.string() +
                     " holds no times (one time in seconds per frame)");
  }
  return timestamps;
}

ImageSource::ImageSource(std::vector<double> timestamps, double fps, ImageSourceOptions options)
    : timestamps_(std::move(timestamps)), fps_(fps), options_(options) {}

std::unique_ptr<ImageSource> ImageSource::Open(const DatasetManifest& manifest,
                                               const ImageSourceOptions& options) {
  std::vector<double> timestamps;
  if (!manifest.timestamps_path.empty()) {
    timestamps = ReadTimestampsFile(manifest.timestamps_path);
  } else if (!(manifest.fps > 0)) {
    throw InputError("dataset " + manifest.name + ": give 'fps' or a 'timestamps' file");
  }
  std::unique_ptr<ImageSource> source;
  if (!manifest.images_dir.empty()) {
    std::vector<std::filesystem::path> files = ListImageFiles(manifest.images_dir);
    if (files.empty()) {
      throw InputError("image folder " + manifest.images_dir.string() +
                       " holds no PNG, JPEG or TIFF frames");
    }
    if (!timestamps.empty() && timestamps.size() != files.size()) {
      throw InputError(manifest.timestamps_path.string() + " has " +
                       std::to_string(timestamps.size()) + " times but " +
                       manifest.images_dir.string() + " has " + std::to_string(files.size()) +
                       " frames");
    }
    source = std::make_unique<FolderImageSource>(std::move(files), std::move(timestamps),
                                                 manifest.fps, options);
  } else if (!manifest.video_path.empty()) {
    source = std::make_unique<VideoImageSource>(manifest.video_path, std::move(timestamps),
                                                manifest.fps, options);
  } else {
    throw InputError("dataset " + manifest.name + " names neither 'images' nor 'video'");
  }
  source->camera_path_ = manifest.camera_path;
  return source;
}

double ImageSource::TimestampOf(std::size_t index) const {
  if (!timestamps_.empty()) {
    if (index >= timestamps_.size()) {
      throw InputError("the timestamps file has fewer times than the sequence has frames");
    }
    return timestamps_[index];
  }
  return static_cast<double>(index) / fps_;
}

ImageSource::RawFrame ImageSource::ReadNextRaw() {
  RawFrame raw;
  const std::size_t index = raw_index_++;
  raw.wanted = !options_.wanted || options_.wanted(index);
  raw.more = ReadRaw(&raw.image, &raw.name, raw.wanted);
  return raw;
}

void ImageSource::StopReadingAhead() {
  if (!ahead_.valid()) return;
  try {
    ahead_.get();
  } catch (...) {
    // The frame is not wanted any more, and neither is its error.
  }
}

std::optional<Frame> ImageSource::Next() {
  while (true) {
    RawFrame next = ahead_.valid() ? ahead_.get() : ReadNextRaw();
    if (!next.more) return std::nullopt;
    if (options_.read_ahead) {
      ahead_ = std::async(std::launch::async, [this] { return ReadNextRaw(); });
    }
    const cv::Mat& raw = next.image;
    const std::string& name = next.name;
    const std::size_t index = next_index_++;
    if (!next.wanted) continue;
    if (raw.empty()) {
      spdlog::warn("skipping unreadable frame {}", name);
      skipped_frames_.push_back(name);
      continue;
    }
    if (options_.expected_width > 0 &&
        (raw.cols != options_.expected_width || raw.rows != options_.expected_height)) {
      throw InputError("frame " + name + " is " + std::to_string(raw.cols) + "x" +
                       std::to_string(raw.rows) + " but the camera calibration " +
                       camera_path_.string() + " is " + std::to_string(options_.expected_width) +
                       "x" + std::to_string(options_.expected_height));
    }
    if (const std::string flaw = UnusableFrameFlaw(raw, &previous_fingerprint_); !flaw.empty()) {
      spdlog::warn("skipping frame {}: {}", name, flaw);
      skipped_frames_.push_back(name);
      continue;
    }
    Frame frame;
    frame.index = index;
    frame.timestamp = TimestampOf(index);
    frame.name = name;
    try {
      frame.grey = options_.native_depth ? ToGrey(raw) : ToFloatGrey(raw);
    } catch (const InputError& error) {
      throw InputError("frame " + name + ": " + error.what());
    }
    return frame;
  }
}

std::string UnusableFrameFlaw(const cv::Mat& raw, std::size_t* previous_fingerprint) {
  // Every 8th row: enough to tell a frame with an image from one without, at a fraction of a
  // millisecond.
  const int rows = (raw.rows + 7) / 8;
  const cv::Mat sampled(rows, raw.cols, raw.type(), raw.data, raw.step[0] * 8);
  double low = 0.0, high = 0.0;
  cv::minMaxLoc(sampled.reshape(1), &low, &high);
  const double grey_levels = (high - low) * GreyLevelsPerUnit(raw.depth());
  std::size_t fingerprint = 0;
  for (int row = 0; row < rows; ++row) {
    const std::string_view bytes(reinterpret_cast<const char*>(sampled.ptr(row)),
                                 sampled.cols * sampled.elemSize());
    fingerprint = fingerprint * 1000003u ^ std::hash<std::string_view>{}(bytes);
  }
  const bool duplicate = fingerprint == *previous_fingerprint;
  *previous_fingerprint = fingerprint;
  if (grey_levels < 2.0) {
    return "uniform (" + std::to_string(static_cast<int>(low * GreyLevelsPerUnit(raw.depth()))) +
           " grey levels everywhere): black, white or no signal";
  }
  if (duplicate) return "the same image as the frame before (a repeated frame)";
  return {};
}

double SaturatedFraction(const cv::Mat& grey, double level) {
  const double level_in_units = level / GreyLevelsPerUnit(grey.depth());
  return static_cast<double>(cv::countNonZero(grey >= level_in_units)) / grey.total();
}

}  // namespace pipescope

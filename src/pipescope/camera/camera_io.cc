#include "pipescope/camera/camera_io.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void FailKey(const fs::path& path, const std::string& key,
                          const std::string& problem) {
  throw InputError(path.string() + ": key '" + key + "': " + problem);
}

std::string Lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// Builds the camera after checking the parameter count against the model, so the message names
// the key that holds the parameters.
Camera MakeCamera(const fs::path& path, const std::string& params_key, CameraModelId model_id,
                  int width, int height, std::vector<double> params) {
  const int num_params = CameraModelNumParams(model_id);
  if (static_cast<int>(params.size()) != num_params) {
    FailKey(path, params_key,
            "model '" + CameraModelName(model_id) + "' takes " + std::to_string(num_params) +
                " values (" + CameraModelParamsInfo(model_id) + "), got " +
                std::to_string(params.size()));
  }
  try {
    return Camera(model_id, width, height, std::move(params));
  } catch (const InputError& error) {
    FailKey(path, params_key, error.what());
  }
}

////////////////////////////////////////////////////////////////////////////////////////////////
// yaml-cpp helpers. `key` is the full dotted name used in messages.
////////////////////////////////////////////////////////////////////////////////////////////////

YAML::Node RequireYaml(const fs::path& path, const YAML::Node& parent, const std::string& name,
                       const std::string& key) {
  const YAML::Node node = parent[name];
  if (!node || node.IsNull()) FailKey(path, key, "missing");
  return node;
}

std::string YamlString(const fs::path& path, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar()) FailKey(path, key, "expected a string");
  return node.Scalar();
}

double YamlDouble(const fs::path& path, const YAML::Node& node, const std::string& key) {
  try {
    if (node.IsScalar()) return node.as<double>();
  } catch (const YAML::Exception&) {
  }
  FailKey(path, key, "expected a number, got '" + (node.IsScalar() ? node.Scalar() : "") + "'");
}

int YamlPositiveInt(const fs::path& path, const YAML::Node& node, const std::string& key) {
  const std::string text = node.IsScalar() ? node.Scalar() : "";
  long long value = 0;
  try {
    if (!node.IsScalar()) FailKey(path, key, "expected a positive integer");
    value = node.as<long long>();
  } catch (const YAML::Exception&) {
    FailKey(path, key, "expected a positive integer, got '" + text + "'");
  }
  if (value <= 0 || value > 1'000'000'000) {
    FailKey(path, key, "must be a positive integer, got " + text);
  }
  return static_cast<int>(value);
}

std::vector<double> YamlDoubleList(const fs::path& path, const YAML::Node& node,
                                   const std::string& key) {
  if (!node.IsSequence()) FailKey(path, key, "expected a list of numbers");
  std::vector<double> values;
  for (std::size_t i = 0; i < node.size(); ++i) {
    values.push_back(YamlDouble(path, node[i], key + "[" + std::to_string(i) + "]"));
  }
  return values;
}

////////////////////////////////////////////////////////////////////////////////////////////////
// pipescope camera.yaml
////////////////////////////////////////////////////////////////////////////////////////////////

Camera ReadPipescopeYaml(const fs::path& path, const YAML::Node& root) {
  const std::string model_name =
      YamlString(path, RequireYaml(path, root, "model", "model"), "model");
  CameraModelId model_id;
  try {
    model_id = CameraModelFromName(model_name);
  } catch (const InputError& error) {
    FailKey(path, "model", error.what());
  }
  const int width = YamlPositiveInt(path, RequireYaml(path, root, "width", "width"), "width");
  const int height = YamlPositiveInt(path, RequireYaml(path, root, "height", "height"), "height");
  std::vector<double> params =
      YamlDoubleList(path, RequireYaml(path, root, "params", "params"), "params");
  return MakeCamera(path, "params", model_id, width, height, std::move(params));
}

////////////////////////////////////////////////////////////////////////////////////////////////
// Kalibr camchain
////////////////////////////////////////////////////////////////////////////////////////////////

Camera ReadKalibrCamchain(const fs::path& path, const YAML::Node& root) {
  const YAML::Node cam = root["cam0"];
  if (!cam.IsMap()) FailKey(path, "cam0", "expected a mapping");
  const auto require = [&](const std::string& name) {
    return RequireYaml(path, cam, name, "cam0." + name);
  };
  const std::string camera_model = YamlString(path, require("camera_model"), "cam0.camera_model");
  if (camera_model != "pinhole") {
    FailKey(path, "cam0.camera_model",
            "unsupported Kalibr camera model '" + camera_model + "' (only 'pinhole' is read)");
  }
  const std::vector<double> intrinsics =
      YamlDoubleList(path, require("intrinsics"), "cam0.intrinsics");
  if (intrinsics.size() != 4) {
    FailKey(path, "cam0.intrinsics",
            "expected 4 values (fu, fv, pu, pv), got " + std::to_string(intrinsics.size()));
  }
  const YAML::Node resolution = require("resolution");
  if (!resolution.IsSequence() || resolution.size() != 2) {
    FailKey(path, "cam0.resolution", "expected [width, height]");
  }
  const int width = YamlPositiveInt(path, resolution[0], "cam0.resolution[0]");
  const int height = YamlPositiveInt(path, resolution[1], "cam0.resolution[1]");

  const std::string distortion_model =
      YamlString(path, require("distortion_model"), "cam0.distortion_model");
  std::vector<double> params = intrinsics;
  if (distortion_model == "none") {
    return MakeCamera(path, "cam0.intrinsics", CameraModelId::kPinholeRadtan, width, height,
                      {intrinsics[0], intrinsics[1], intrinsics[2], intrinsics[3], 0, 0, 0, 0, 0});
  }
  const std::vector<double> coeffs =
      YamlDoubleList(path, require("distortion_coeffs"), "cam0.distortion_coeffs");
  if (distortion_model != "radtan" && distortion_model != "equidistant") {
    FailKey(path, "cam0.distortion_model",
            "unsupported Kalibr distortion model '" + distortion_model +
                "' (expected radtan, equidistant or none)");
  }
  if (coeffs.size() != 4) {
    FailKey(path, "cam0.distortion_coeffs",
            "distortion model '" + distortion_model + "' takes 4 values, got " +
                std::to_string(coeffs.size()));
  }
  params.insert(params.end(), coeffs.begin(), coeffs.end());
  if (distortion_model == "radtan") {
    // Kalibr's k1 k2 r1 r2 are OpenCV's k1 k2 p1 p2; no k3.
    params.push_back(0.0);
    return MakeCamera(path, "cam0.distortion_coeffs", CameraModelId::kPinholeRadtan, width, height,
                      std::move(params));
  }
  return MakeCamera(path, "cam0.distortion_coeffs", CameraModelId::kKannalaBrandt, width, height,
                    std::move(params));
}

////////////////////////////////////////////////////////////////////////////////////////////////
// OpenCV calibrations (FileStorage, or plain YAML with the same keys as ROS writes them)
////////////////////////////////////////////////////////////////////////////////////////////////

struct OpenCvCalibration {
  std::vector<double> camera_matrix;  // 3x3, row-major.
  std::vector<double> distortion;
  int width = 0;
  int height = 0;
  std::string distortion_model;  // Empty when the file has none.
  std::string distortion_model_key;
};

Camera CameraFromOpenCvCalibration(const fs::path& path, const OpenCvCalibration& calibration) {
  const std::vector<double>& k = calibration.camera_matrix;
  if (k.size() != 9) {
    FailKey(path, "camera_matrix",
            "expected a 3x3 matrix, got " + std::to_string(k.size()) + " values");
  }
  if (k[3] != 0.0 || k[6] != 0.0 || k[7] != 0.0 || k[8] != 1.0) {
    FailKey(path, "camera_matrix", "expected the form [fx 0 cx; 0 fy cy; 0 0 1]");
  }
  if (std::abs(k[1]) > 1e-9 * std::abs(k[0])) {
    FailKey(path, "camera_matrix", "non-zero skew K(0,1) is not supported");
  }

  const std::string model = Lowercase(calibration.distortion_model);
  const bool fisheye = model == "fisheye" || model == "equidistant" || model == "equi" ||
                       model == "kannala-brandt" || model == "kannala_brandt";
  const bool radtan = model.empty() || model == "plumb_bob" || model == "rational_polynomial" ||
                      model == "radtan" || model == "radial-tangential" || model == "pinhole" ||
                      model == "pinhole-radtan" || model == "opencv";
  if (!fisheye && !radtan) {
    FailKey(path, calibration.distortion_model_key,
            "unsupported model '" + calibration.distortion_model +
                "' (expected fisheye/equidistant, or plumb_bob/radtan/pinhole)");
  }

  const std::vector<double>& d = calibration.distortion;
  std::vector<double> params = {k[0], k[4], k[2], k[5]};
  if (fisheye) {
    if (d.size() != 4) {
      FailKey(path, "distortion_coefficients",
              "the fisheye model takes 4 values (k1, k2, k3, k4), got " + std::to_string(d.size()));
    }
    params.insert(params.end(), d.begin(), d.end());
    return MakeCamera(path, "distortion_coefficients", CameraModelId::kKannalaBrandt,
                      calibration.width, calibration.height, std::move(params));
  }
  if (d.size() != 4 && d.size() != 5 && d.size() != 8 && d.size() != 12 && d.size() != 14) {
    FailKey(
        path, "distortion_coefficients",
        "expected 4 (k1 k2 p1 p2) or 5 (k1 k2 p1 p2 k3) values, got " + std::to_string(d.size()));
  }
  // The rational, thin-prism and tilt terms (k4.. of OpenCV) are not in pinhole-radtan; zeros
  // are what OpenCV writes when they were not estimated, so those files are still read.
  if (d.size() > 5 && std::any_of(d.begin() + 5, d.end(), [](double v) { return v != 0.0; })) {
    FailKey(path, "distortion_coefficients",
            "non-zero rational/thin-prism/tilt terms (values 6.." + std::to_string(d.size()) +
                ") are not supported by pinhole-radtan");
  }
  params.insert(params.end(), d.begin(), d.begin() + 4);
  params.push_back(d.size() >= 5 ? d[4] : 0.0);
  return MakeCamera(path, "distortion_coefficients", CameraModelId::kPinholeRadtan,
                    calibration.width, calibration.height, std::move(params));
}

// A calibration's matrices hold a few values (3x3, at most 14 coefficients).
constexpr int kMaxCvMatrixValues = 64;

// OpenCV allocates an `!!opencv-matrix` of `rows` x `cols` before it counts `data`, so a bad
// size could ask for any amount of memory: the size must be small and match the data.
void CheckCvMatrixSize(const fs::path& path, const cv::FileNode& node, const std::string& key) {
  const cv::FileNode rows = node["rows"];
  const cv::FileNode cols = node["cols"];
  const cv::FileNode data = node["data"];
  if (!rows.isInt() || !cols.isInt() || !data.isSeq()) {
    FailKey(path, key, "expected a matrix with integers 'rows' and 'cols' and a list 'data'");
  }
  const long long count = static_cast<long long>(static_cast<int>(rows)) * static_cast<int>(cols);
  if (static_cast<int>(rows) < 1 || static_cast<int>(cols) < 1 || count > kMaxCvMatrixValues ||
      count != static_cast<long long>(data.size())) {
    FailKey(path, key,
            "'rows' x 'cols' (" + std::to_string(static_cast<int>(rows)) + " x " +
                std::to_string(static_cast<int>(cols)) + ") must match the " +
                std::to_string(data.size()) + " values of 'data' (at most " +
                std::to_string(kMaxCvMatrixValues) + ")");
  }
}

std::vector<double> CvMatrixValues(const fs::path& path, const cv::FileStorage& storage,
                                   const std::string& key) {
  const cv::FileNode node = storage[key];
  if (node.empty() || node.isNone()) FailKey(path, key, "missing");
  if (node.isMap()) CheckCvMatrixSize(path, node, key);
  try {
    if (node.isSeq()) {
      std::vector<double> values;
      node >> values;
      return values;
    }
    cv::Mat matrix;
    node >> matrix;
    if (matrix.empty() || matrix.channels() != 1) FailKey(path, key, "expected a matrix");
    cv::Mat values;
    matrix.convertTo(values, CV_64F);
    values = values.reshape(1, 1).clone();
    return std::vector<double>(values.ptr<double>(), values.ptr<double>() + values.total());
  } catch (const cv::Exception& error) {
    FailKey(path, key, "cannot read a matrix: " + error.err);
  }
}

int CvPositiveInt(const fs::path& path, const cv::FileStorage& storage, const std::string& key) {
  const cv::FileNode node = storage[key];
  if (node.empty() || node.isNone()) FailKey(path, key, "missing");
  if (!node.isInt() && !node.isReal()) FailKey(path, key, "expected a positive integer");
  const double value = node.real();
  if (!(value > 0.0) || value != std::floor(value) || value > 1e9) {
    FailKey(path, key, "must be a positive integer");
  }
  return static_cast<int>(value);
}

// Rejects what OpenCV 4.6's parser would crash on or misread (found by fuzzing): it reads the
// text only up to a NUL byte, and its XML parser dereferences a null pointer when the text ends
// inside a tag (right after `name=`). A complete XML file ends after its last tag's '>'.
void CheckOpenCvStorageText(const fs::path& path, const std::string& text) {
  if (text.find('\0') != std::string::npos) {
    throw InputError(path.string() + ": contains a NUL byte; expected a text calibration file");
  }
  const std::size_t start = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");  // and a BOM
  const std::size_t last_open = text.rfind('<');
  const std::size_t last_close = text.rfind('>');
  if (start != std::string::npos && text[start] == '<' &&
      (last_close == std::string::npos || last_close < last_open)) {
    throw InputError(path.string() + ": the XML ends inside a tag (is the file cut short?)");
  }
}

Camera ReadOpenCvStorage(const fs::path& path, const std::string& text) {
  CheckOpenCvStorageText(path, text);
  cv::FileStorage storage;
  try {
    storage.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& error) {
    throw InputError(path.string() + ": cannot parse as an OpenCV FileStorage file: " + error.err);
  } catch (const std::length_error& error) {
    // OpenCV's parser can take a malformed entry for a negative length (found by fuzzing).
    throw InputError(path.string() +
                     ": cannot parse as an OpenCV FileStorage file: " + error.what());
  }
  if (!storage.isOpened()) {
    throw InputError(path.string() + ": cannot parse as an OpenCV FileStorage file");
  }
  // Keys are looked up in the root node, which OpenCV asserts is a mapping (found by fuzzing).
  if (!storage.root().isMap()) {
    throw InputError(path.string() +
                     ": expected an OpenCV FileStorage mapping with key 'camera_matrix'");
  }
  OpenCvCalibration calibration;
  try {
    calibration.camera_matrix = CvMatrixValues(path, storage, "camera_matrix");
    calibration.distortion = CvMatrixValues(path, storage, "distortion_coefficients");
    calibration.width = CvPositiveInt(path, storage, "image_width");
    calibration.height = CvPositiveInt(path, storage, "image_height");
    for (const char* key : {"distortion_model", "camera_model"}) {
      const cv::FileNode node = storage[key];
      if (node.empty() || node.isNone()) continue;
      if (!node.isString()) FailKey(path, key, "expected a string");
      calibration.distortion_model = node.string();
      calibration.distortion_model_key = key;
      break;
    }
  } catch (const cv::Exception& error) {
    // OpenCV asserts on the structure it reads; whatever else it rejects is still the file's.
    throw InputError(path.string() + ": cannot read as an OpenCV FileStorage file: " + error.err);
  }
  return CameraFromOpenCvCalibration(path, calibration);
}

// A matrix in plain YAML: either {rows, cols, data: [...]} (ROS camera_info) or a flat list.
std::vector<double> YamlMatrixValues(const fs::path& path, const YAML::Node& root,
                                     const std::string& key) {
  const YAML::Node node = RequireYaml(path, root, key, key);
  if (node.IsMap())
    return YamlDoubleList(path, RequireYaml(path, node, "data", key + ".data"), key + ".data");
  return YamlDoubleList(path, node, key);
}

Camera ReadOpenCvStyleYaml(const fs::path& path, const YAML::Node& root) {
  OpenCvCalibration calibration;
  calibration.camera_matrix = YamlMatrixValues(path, root, "camera_matrix");
  calibration.distortion = YamlMatrixValues(path, root, "distortion_coefficients");
  calibration.width =
      YamlPositiveInt(path, RequireYaml(path, root, "image_width", "image_width"), "image_width");
  calibration.height = YamlPositiveInt(
      path, RequireYaml(path, root, "image_height", "image_height"), "image_height");
  for (const char* key : {"distortion_model", "camera_model"}) {
    const YAML::Node node = root[key];
    if (!node || node.IsNull()) continue;
    calibration.distortion_model = YamlString(path, node, key);
    calibration.distortion_model_key = key;
    break;
  }
  return CameraFromOpenCvCalibration(path, calibration);
}

// OpenCV's own YAML dialect (`%YAML:1.0`, `!!opencv-matrix`) is beyond yaml-cpp, and XML is
// OpenCV's alone, so those go to cv::FileStorage.
bool IsOpenCvStorage(const fs::path& path, const std::string& text) {
  std::string_view head(text);
  if (head.starts_with("\xEF\xBB\xBF")) head.remove_prefix(3);
  const std::size_t start = head.find_first_not_of(" \t\r\n");
  head.remove_prefix(start == std::string_view::npos ? head.size() : start);
  return head.starts_with("%YAML:") || head.starts_with("<?xml") ||
         head.starts_with("<opencv_storage") || Lowercase(path.extension().string()) == ".xml";
}

std::string Short(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  return buffer;
}

// A calibration no camera in a pipe can have is refused here, naming the file, instead of
// giving a map that is wrong by orders of magnitude: the optical axis must meet the image, the
// focal length must lie within a 0.05x-100x of the image size (fields of view from about 1
// degree to beyond 360), and the lens must be invertible near the centre and see at least
// 5 degrees across.
}  // namespace

void CheckCameraIsPlausible(const fs::path& path, const Camera& camera) {
  const std::string size = std::to_string(camera.Width()) + "x" + std::to_string(camera.Height());
  Eigen::Vector2d centre;
  if (camera.Project(Eigen::Vector3d(0, 0, 1), &centre) != ProjectionStatus::kValid) {
    throw InputError(path.string() + ": the principal point (" + Short(centre.x()) + ", " +
                     Short(centre.y()) + ") lies outside the " + size + " image");
  }
  const double step = 1e-4;  // radians: the focal length from a small angle off the axis
  Eigen::Vector2d beside;
  camera.Project(Eigen::Vector3d(std::tan(step), 0, 1), &beside);
  const double focal_px = (beside - centre).norm() / step;
  const double image_px = std::max(camera.Width(), camera.Height());
  if (!(focal_px >= 0.05 * image_px && focal_px <= 100.0 * image_px)) {
    throw InputError(path.string() + ": focal length " + Short(focal_px) +
                     " px is implausible for a " + size + " image (expected " +
                     Short(0.05 * image_px) + " to " + Short(100.0 * image_px) + " px)");
  }
  // Pixels on a grid: those near the principal point must go to rays and back.
  double widest_deg = 0.0;
  const double near_px = 0.3 * std::min(camera.Width(), camera.Height());
  for (int row = 0; row <= 8; ++row) {
    for (int col = 0; col <= 8; ++col) {
      const Eigen::Vector2d pixel((camera.Width() - 1) * col / 8.0,
                                  (camera.Height() - 1) * row / 8.0);
      Eigen::Vector3d ray;
      Eigen::Vector2d back;
      const bool round_trip = camera.Unproject(pixel, &ray) &&
                              camera.Project(ray, &back) != ProjectionStatus::kBehindCamera &&
                              (back - pixel).norm() < 0.5;
      if (round_trip) {
        widest_deg = std::max(
            widest_deg, std::acos(std::clamp(ray.normalized().z(), -1.0, 1.0)) * 180.0 / M_PI);
      } else if ((pixel - centre).norm() < near_px) {
        throw InputError(path.string() + ": the lens model cannot be inverted at pixel (" +
                         Short(pixel.x()) + ", " + Short(pixel.y()) +
                         ") near the image centre; are the distortion coefficients right?");
      }
    }
  }
  if (widest_deg < 2.5) {
    throw InputError(path.string() + ": the image sees only " + Short(2 * widest_deg) +
                     " degrees across; are the focal length and distortion coefficients right?");
  }
}

namespace {

Camera ParseCamera(const fs::path& path) {
  const std::string text = ReadTextFile(path);
  if (IsOpenCvStorage(path, text)) return ReadOpenCvStorage(path, text);
  // Const, so that looking up absent keys below cannot insert them.
  const YAML::Node root = [&] {
    try {
      return YAML::Load(text);
    } catch (const YAML::Exception& error) {
      throw InputError(path.string() + ": not valid YAML: " + error.what());
    }
  }();
  if (!root.IsMap()) {
    throw InputError(path.string() +
                     ": expected a camera calibration mapping with key 'model' (pipescope), "
                     "'cam0' (Kalibr) or 'camera_matrix' (OpenCV)");
  }
  if (root["cam0"]) return ReadKalibrCamchain(path, root);
  if (root["camera_matrix"] && !root["model"]) return ReadOpenCvStyleYaml(path, root);
  return ReadPipescopeYaml(path, root);
}

}  // namespace

Camera ReadCamera(const fs::path& path) {
  Camera camera = ParseCamera(path);
  CheckCameraIsPlausible(path, camera);
  return camera;
}

void WriteCameraYaml(const fs::path& path, const Camera& camera) {
  std::string text = "# pipescope camera; params: " + CameraModelParamsInfo(camera.ModelId()) +
                     "\nmodel: " + camera.ModelName() +
                     "\nwidth: " + std::to_string(camera.Width()) +
                     "\nheight: " + std::to_string(camera.Height()) + "\nparams: [";
  for (std::size_t i = 0; i < camera.Params().size(); ++i) {
    char buffer[32];
    // 17 significant digits round-trip every double exactly.
    std::snprintf(buffer, sizeof(buffer), "%.17g", camera.Params()[i]);
    text += (i == 0 ? "" : ", ") + std::string(buffer);
  }
  text += "]\n";
  WriteTextFileAtomically(path, text);
}

}  // namespace pipescope

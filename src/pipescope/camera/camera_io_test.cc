#include "pipescope/camera/camera_io.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <string>
#include <utility>
#include <vector>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

namespace fs = std::filesystem;

// Asserts that reading `path` throws InputError whose message names the file and `key`.
void ExpectReadErrorNames(const fs::path& path, const std::string& key) {
  try {
    ReadCamera(path);
    ADD_FAILURE() << "expected InputError reading " << path;
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find("'" + key + "'"), std::string::npos) << message;
  }
}

TEST(CameraIo, WriteReadRoundTripForEveryModel) {
  const fs::path dir = MakeTestDirectory("camera_io_round_trip");
  const std::vector<Camera> cameras = {
      Camera(CameraModelId::kPinholeRadtan, 752, 480,
             {458.654, 457.296, 367.215, 248.375, -0.28340811, 0.07395907, 0.00019359,
              1.76187114e-05, 1.0 / 3.0}),
      Camera(CameraModelId::kKannalaBrandt, 512, 512,
             {190.97847715128717, 190.9733070521226, 254.93170605935475, 256.8974428996504,
              0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202,
              0.00020293673591811182}),
      Camera(CameraModelId::kFisheyePoly, 1280, 960,
             {410.123456789, -8.5e-3, 3.25e-12, -1.0 / 7.0, 640.25, 479.75})};
  for (const Camera& camera : cameras) {
    const fs::path path = dir / (camera.ModelName() + ".yaml");
    WriteCameraYaml(path, camera);
    const Camera read = ReadCamera(path);
    EXPECT_EQ(read.ModelId(), camera.ModelId());
    EXPECT_EQ(read.Width(), camera.Width());
    EXPECT_EQ(read.Height(), camera.Height());
    EXPECT_EQ(read.Params(), camera.Params());  // Bit-exact thanks to %.17g.
  }
}

TEST(CameraIo, ReadsOpenCvFileStorageYamlAndXml) {
  const fs::path dir = MakeTestDirectory("camera_io_opencv");
  const cv::Mat camera_matrix =
      (cv::Mat_<double>(3, 3) << 500.5, 0, 320.25, 0, 501.5, 239.75, 0, 0, 1);
  const cv::Mat five = (cv::Mat_<double>(1, 5) << -0.3, 0.1, 0.001, -0.002, 0.05);
  const cv::Mat four = (cv::Mat_<double>(4, 1) << -0.3, 0.1, 0.001, -0.002);
  for (const std::string name : {"five.yaml", "five.xml", "four.yml"}) {
    cv::FileStorage storage((dir / name).string(), cv::FileStorage::WRITE);
    storage << "image_width" << 640 << "image_height" << 480;
    storage << "camera_matrix" << camera_matrix;
    storage << "distortion_coefficients" << (name.starts_with("four") ? four : five);
    storage.release();
  }
  for (const std::string name : {"five.yaml", "five.xml", "four.yml"}) {
    SCOPED_TRACE(name);
    if (name.ends_with("yaml")) {
      ASSERT_TRUE(ReadTextFile(dir / name).starts_with("%YAML:1.0"));
    }
    const Camera camera = ReadCamera(dir / name);
    EXPECT_EQ(camera.ModelId(), CameraModelId::kPinholeRadtan);
    EXPECT_EQ(camera.Width(), 640);
    EXPECT_EQ(camera.Height(), 480);
    const double k3 = name.starts_with("four") ? 0.0 : 0.05;
    EXPECT_EQ(camera.Params(),
              (std::vector<double>{500.5, 501.5, 320.25, 239.75, -0.3, 0.1, 0.001, -0.002, k3}));
  }
}

TEST(CameraIo, ReadsOpenCvFisheyeFileStorage) {
  const fs::path dir = MakeTestDirectory("camera_io_opencv_fisheye");
  cv::FileStorage storage((dir / "fisheye.yaml").string(), cv::FileStorage::WRITE);
  storage << "distortion_model"
          << "fisheye";
  storage << "image_width" << 1024 << "image_height" << 768;
  storage << "camera_matrix"
          << (cv::Mat_<double>(3, 3) << 300.0, 0, 512.0, 0, 301.0, 384.0, 0, 0, 1);
  storage << "distortion_coefficients" << (cv::Mat_<double>(1, 4) << 0.01, -0.02, 0.003, -0.0004);
  storage.release();
  const Camera camera = ReadCamera(dir / "fisheye.yaml");
  EXPECT_EQ(camera.ModelId(), CameraModelId::kKannalaBrandt);
  EXPECT_EQ(camera.Params(),
            (std::vector<double>{300.0, 301.0, 512.0, 384.0, 0.01, -0.02, 0.003, -0.0004}));
}

TEST(CameraIo, OpenCvErrorsNameTheKey) {
  const fs::path dir = MakeTestDirectory("camera_io_opencv_errors");
  const cv::Mat camera_matrix = (cv::Mat_<double>(3, 3) << 500, 0, 320, 0, 500, 240, 0, 0, 1);
  {
    cv::FileStorage storage((dir / "six.yaml").string(), cv::FileStorage::WRITE);
    storage << "image_width" << 640 << "image_height" << 480 << "camera_matrix" << camera_matrix;
    storage << "distortion_coefficients" << (cv::Mat_<double>(1, 6) << 0.1, 0, 0, 0, 0, 0.2);
  }
  ExpectReadErrorNames(dir / "six.yaml", "distortion_coefficients");
  {
    cv::FileStorage storage((dir / "no_width.xml").string(), cv::FileStorage::WRITE);
    storage << "image_height" << 480 << "camera_matrix" << camera_matrix;
    storage << "distortion_coefficients" << (cv::Mat_<double>(1, 4) << 0.1, 0, 0, 0);
  }
  ExpectReadErrorNames(dir / "no_width.xml", "image_width");
}

// Found by fuzzing: OpenCV allocated rows x cols before counting the data, so a large size in
// the file asked for gigabytes.
TEST(CameraIo, OpenCvMatrixSizeMustMatchItsData) {
  const fs::path dir = MakeTestDirectory("camera_io_opencv_matrix_size");
  const std::string head =
      "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
      "distortion_coefficients: [0.1, 0, 0, 0]\ncamera_matrix: !!opencv-matrix\n";
  const std::string data = "   dt: d\n   data: [500., 0., 320., 0., 500., 240., 0., 0., 1.]\n";
  WriteTextFileAtomically(dir / "huge.yaml", head + "   rows: 1000000\n   cols: 1000000\n" + data);
  ExpectReadErrorNames(dir / "huge.yaml", "camera_matrix");
  try {
    ReadCamera(dir / "huge.yaml");
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("'rows' x 'cols'"), std::string::npos) << error.what();
  }
  WriteTextFileAtomically(dir / "short.yaml", head + "   rows: 3\n   cols: 4\n" + data);
  ExpectReadErrorNames(dir / "short.yaml", "camera_matrix");
  WriteTextFileAtomically(dir / "text.yaml", head + "   rows: three\n   cols: 3\n" + data);
  ExpectReadErrorNames(dir / "text.yaml", "camera_matrix");
  WriteTextFileAtomically(dir / "good.yaml", head + "   rows: 3\n   cols: 3\n" + data);
  EXPECT_EQ(ReadCamera(dir / "good.yaml").Params()[0], 500.0);
}

// Found by fuzzing: OpenCV's parser threw std::length_error for an empty key after another in a
// nested map, asserted (cv::Exception) on a key looked up in a top-level list, and crashed on a
// null pointer for XML that ends after `name=` (a file cut short, or cut at a NUL byte, where
// OpenCV stops reading).
TEST(CameraIo, MalformedOpenCvStorageIsAnInputErrorNamingTheFile) {
  const fs::path dir = MakeTestDirectory("camera_io_opencv_malformed");
  const std::vector<std::pair<std::string, std::string>> files = {
      {"empty_key.yaml", "%YAML:1.0\n---\ncamera_matrix:\n   rows: 3\n   : 4\n"},
      {"top_level_list.yaml", "%YAML:1.0\n---\n- 1\n- 2\n"},
      {"empty.xml", "<?xml version=\"1.0\"?>\n<opencv_storage>\n</opencv_storage>\n"},
      {"cut_after_equals.xml", "<?xml version=\"1.0\"?>\n<opencv_storage>\n<a type_id=  "},
      {"cut_in_header.xml", "<?xml version=\n"},
      {"nul_byte.xml", "<?xml version=" + std::string(1, '\0') + "\"1.0\"?>\n<opencv_storage/>\n"}};
  for (const auto& [name, text] : files) {
    SCOPED_TRACE(name);
    WriteTextFileAtomically(dir / name, text);
    try {
      ReadCamera(dir / name);
      ADD_FAILURE() << "expected InputError";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find((dir / name).string()), std::string::npos)
          << error.what();
    }
  }
}

TEST(CameraIo, ReadsKalibrCamchains) {
  const fs::path dir = MakeTestDirectory("camera_io_kalibr");
  WriteTextFileAtomically(dir / "radtan.yaml", R"(cam0:
  cam_overlaps: []
  camera_model: pinhole
  distortion_coeffs: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
  distortion_model: radtan
  intrinsics: [458.654, 457.296, 367.215, 248.375]
  resolution: [752, 480]
  rostopic: /cam0/image_raw
)");
  const Camera radtan = ReadCamera(dir / "radtan.yaml");
  EXPECT_EQ(radtan.ModelId(), CameraModelId::kPinholeRadtan);
  EXPECT_EQ(radtan.Width(), 752);
  EXPECT_EQ(radtan.Height(), 480);
  EXPECT_EQ(radtan.Params(), (std::vector<double>{458.654, 457.296, 367.215, 248.375, -0.28340811,
                                                  0.07395907, 0.00019359, 1.76187114e-05, 0.0}));

  WriteTextFileAtomically(dir / "equi.yaml", R"(cam0:
  T_cam_imu:
  - [1, 0, 0, 0]
  - [0, 1, 0, 0]
  - [0, 0, 1, 0]
  - [0, 0, 0, 1]
  camera_model: pinhole
  distortion_coeffs: [0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202,
    0.00020293673591811182]
  distortion_model: equidistant
  intrinsics: [190.97847715128717, 190.9733070521226, 254.93170605935475, 256.8974428996504]
  resolution: [512, 512]
cam1:
  camera_model: pinhole
)");
  const Camera equi = ReadCamera(dir / "equi.yaml");
  EXPECT_EQ(equi.ModelId(), CameraModelId::kKannalaBrandt);
  EXPECT_EQ(equi.Width(), 512);
  EXPECT_EQ(equi.Params(),
            (std::vector<double>{190.97847715128717, 190.9733070521226, 254.93170605935475,
                                 256.8974428996504, 0.0034823894022493434, 0.0007150348452162257,
                                 -0.0020532361418706202, 0.00020293673591811182}));

  WriteTextFileAtomically(dir / "no_intrinsics.yaml", R"(cam0:
  camera_model: pinhole
  distortion_model: radtan
  distortion_coeffs: [0, 0, 0, 0]
  resolution: [752, 480]
)");
  ExpectReadErrorNames(dir / "no_intrinsics.yaml", "cam0.intrinsics");
  WriteTextFileAtomically(dir / "fov.yaml", R"(cam0:
  camera_model: pinhole
  distortion_model: fov
  distortion_coeffs: [0.9]
  intrinsics: [458.654, 457.296, 367.215, 248.375]
  resolution: [752, 480]
)");
  ExpectReadErrorNames(dir / "fov.yaml", "cam0.distortion_model");
}

TEST(CameraIo, ReadsRosStyleCameraInfoYaml) {
  const fs::path dir = MakeTestDirectory("camera_io_ros");
  WriteTextFileAtomically(dir / "ost.yaml", R"(image_width: 640
image_height: 480
camera_name: narrow_stereo
camera_matrix:
  rows: 3
  cols: 3
  data: [500.0, 0.0, 320.0, 0.0, 501.0, 240.0, 0.0, 0.0, 1.0]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [-0.3, 0.1, 0.001, -0.002, 0.0]
)");
  const Camera camera = ReadCamera(dir / "ost.yaml");
  EXPECT_EQ(camera.ModelId(), CameraModelId::kPinholeRadtan);
  EXPECT_EQ(camera.Params(),
            (std::vector<double>{500.0, 501.0, 320.0, 240.0, -0.3, 0.1, 0.001, -0.002, 0.0}));
}

TEST(CameraIo, PipescopeYamlErrorsNameFileAndKey) {
  const fs::path dir = MakeTestDirectory("camera_io_errors");
  WriteTextFileAtomically(dir / "no_params.yaml",
                          "model: fisheye-poly\nwidth: 1280\nheight: 960\n");
  ExpectReadErrorNames(dir / "no_params.yaml", "params");

  WriteTextFileAtomically(dir / "count.yaml",
                          "model: kannala-brandt\nwidth: 640\nheight: 480\n"
                          "params: [300, 300, 320, 240, 0, 0, 0]\n");
  ExpectReadErrorNames(dir / "count.yaml", "params");

  WriteTextFileAtomically(dir / "model.yaml",
                          "model: double-sphere\nwidth: 640\nheight: 480\nparams: [1, 2]\n");
  ExpectReadErrorNames(dir / "model.yaml", "model");
  try {
    ReadCamera(dir / "model.yaml");
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("double-sphere"), std::string::npos) << message;
    EXPECT_NE(message.find("fisheye-poly"), std::string::npos) << message;
  }

  WriteTextFileAtomically(dir / "height.yaml",
                          "model: fisheye-poly\nwidth: 1280\nheight: 0\n"
                          "params: [300, 0, 0, 0, 640, 480]\n");
  ExpectReadErrorNames(dir / "height.yaml", "height");

  WriteTextFileAtomically(dir / "number.yaml",
                          "model: fisheye-poly\nwidth: 1280\nheight: 960\n"
                          "params: [300, 0, zero, 0, 640, 480]\n");
  ExpectReadErrorNames(dir / "number.yaml", "params[2]");

  try {
    ReadCamera(dir / "missing.yaml");
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("missing.yaml"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace pipescope

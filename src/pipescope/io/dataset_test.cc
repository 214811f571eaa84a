#include "pipescope/io/dataset.h"

#include <gtest/gtest.h>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

// Expects `call` to throw InputError whose message contains every one of `needles`.
void ExpectInputError(const std::function<void()>& call,
                      std::initializer_list<std::string> needles) {
  const std::string message = InputErrorMessage(call);
  for (const std::string& needle : needles) {
    EXPECT_NE(message.find(needle), std::string::npos)
        << "'" << message << "' does not mention '" << needle << "'";
  }
}

std::filesystem::path MakeDatasetFolder(const std::string& name, const std::string& manifest) {
  const auto dir = MakeTestDirectory(name);
  std::filesystem::create_directories(dir / "images");
  WriteTextFileAtomically(dir / "camera.yaml", "model: pinhole-radtan\n");
  WriteTextFileAtomically(dir / "groundtruth.tum", "# empty\n");
  WriteTextFileAtomically(dir / "dataset.yaml", manifest);
  return dir;
}

TEST(Dataset, ReadsManifestAndResolvesRelativePaths) {
  const auto dir = MakeDatasetFolder("dataset_ok",
                                     "name: pipe1\ncamera: camera.yaml\nimages: images\nfps: 7.5\n"
                                     "pipe:\n  inner_radius_m: 0.07666\n"
                                     "reference_scale_px_per_m: 12345.5\n"
                                     "groundtruth: groundtruth.tum\n");
  const DatasetManifest manifest = OpenDataset(dir);
  EXPECT_EQ(manifest.name, "pipe1");
  EXPECT_EQ(manifest.camera_path, dir / "camera.yaml");
  EXPECT_EQ(manifest.images_dir, dir / "images");
  EXPECT_DOUBLE_EQ(manifest.fps, 7.5);
  ASSERT_TRUE(manifest.inner_radius_m.has_value());
  EXPECT_DOUBLE_EQ(*manifest.inner_radius_m, 0.07666);
  EXPECT_DOUBLE_EQ(*manifest.reference_scale_px_per_m, 12345.5);
  EXPECT_EQ(manifest.groundtruth_path, dir / "groundtruth.tum");
  EXPECT_TRUE(manifest.scene_path.empty());
}

TEST(Dataset, WriteThenReadRoundTrips) {
  const auto dir =
      MakeDatasetFolder("dataset_roundtrip", "camera: camera.yaml\nimages: images\nfps: 30\n");
  DatasetManifest manifest = OpenDataset(dir);
  manifest.name = "written";
  manifest.inner_radius_m = 0.19378;
  manifest.groundtruth_path = dir / "groundtruth.tum";
  manifest.pipe_up = Eigen::Vector3d(0.0, 0.6, -0.8);
  WriteDatasetManifest(dir / "dataset.yaml", manifest);
  const std::string text = ReadTextFile(dir / "dataset.yaml");
  EXPECT_NE(text.find("camera: camera.yaml"), std::string::npos) << text;
  const DatasetManifest again = OpenDataset(dir);
  EXPECT_EQ(again.name, "written");
  EXPECT_DOUBLE_EQ(*again.inner_radius_m, 0.19378);
  EXPECT_EQ(again.groundtruth_path, dir / "groundtruth.tum");
  EXPECT_DOUBLE_EQ(again.fps, 30.0);
  ASSERT_TRUE(again.pipe_up.has_value());
  EXPECT_LT((*again.pipe_up - Eigen::Vector3d(0.0, 0.6, -0.8)).norm(), 1e-12);
}

TEST(Dataset, PipeUpIsNormalisedAndCheckedNamingTheKey) {
  const auto dir = MakeDatasetFolder(
      "dataset_up", "camera: camera.yaml\nimages: images\nfps: 7.5\npipe:\n  up: [0, -2, 0]\n");
  const DatasetManifest manifest = OpenDataset(dir);
  ASSERT_TRUE(manifest.pipe_up.has_value());
  EXPECT_EQ(*manifest.pipe_up, Eigen::Vector3d(0.0, -1.0, 0.0));
  for (const std::string up : {"[0, 0, 0]", "[1, 2]", "[.nan, 1, 0]", "up"}) {
    const auto bad = MakeDatasetFolder(
        "dataset_bad_up",
        "camera: camera.yaml\nimages: images\nfps: 7.5\npipe:\n  up: " + up + "\n");
    ExpectInputError([&] { OpenDataset(bad); }, {"dataset.yaml", "pipe.up"});
  }
}

// Found while fuzzing the manifest (by reading the paths; manifest_fuzzer reproduces it): a path
// the file system refuses to look up (a name longer than 255 bytes) escaped as
// std::filesystem::filesystem_error, naming neither the manifest nor the key.
TEST(Dataset, UnlookupablePathIsAnInputErrorNamingTheKey) {
  const auto dir = MakeDatasetFolder(
      "dataset_long_name", "camera: camera.yaml\nimages: images\nfps: 7.5\ngroundtruth: " +
                               std::string(300, 'g') + "\n");
  ExpectInputError([&] { ReadDatasetManifest(dir / "dataset.yaml"); },
                   {"dataset.yaml", "'groundtruth'", "cannot be looked up"});
}

TEST(Dataset, ErrorsNameFileAndKey) {
  ExpectInputError([] { OpenDataset("/nonexistent/dataset"); }, {"/nonexistent/dataset"});
  const auto missing_camera = MakeDatasetFolder("dataset_nocam", "images: images\nfps: 7.5\n");
  ExpectInputError([&] { OpenDataset(missing_camera); }, {"dataset.yaml", "'camera'"});
  const auto bad_camera =
      MakeDatasetFolder("dataset_badcam", "camera: nothere.yaml\nimages: images\nfps: 7.5\n");
  ExpectInputError([&] { OpenDataset(bad_camera); }, {"'camera'", "nothere.yaml"});
  const auto bad_radius = MakeDatasetFolder(
      "dataset_badradius",
      "camera: camera.yaml\nimages: images\nfps: 7.5\npipe:\n  inner_radius_m: -1\n");
  ExpectInputError([&] { OpenDataset(bad_radius); }, {"pipe.inner_radius_m"});
  const auto no_images = MakeDatasetFolder("dataset_noimages", "camera: camera.yaml\nfps: 7.5\n");
  ExpectInputError([&] { OpenDataset(no_images); }, {"'images'"});
  const auto bad_yaml = MakeDatasetFolder("dataset_badyaml", "camera: [unclosed\n");
  ExpectInputError([&] { OpenDataset(bad_yaml); }, {"dataset.yaml", "YAML"});
}

TEST(Dataset, PlainFolderNeedsCameraFlagAndTakesRadius) {
  const auto dir = MakeTestDirectory("dataset_plain");
  WriteTextFileAtomically(dir / "cam.yaml", "model: pinhole-radtan\n");
  ExpectInputError([&] { OpenDataset(dir); }, {"--camera"});
  const DatasetManifest manifest =
      OpenDataset(dir, {.camera_path = dir / "cam.yaml", .inner_radius_m = 0.2, .fps = 10.0});
  EXPECT_EQ(manifest.images_dir, dir);
  EXPECT_DOUBLE_EQ(*manifest.inner_radius_m, 0.2);
  EXPECT_DOUBLE_EQ(manifest.fps, 10.0);
  ExpectInputError(
      [&] { OpenDataset(dir, {.camera_path = dir / "cam.yaml", .inner_radius_m = 0, .fps = {}}); },
      {"--radius"});
  ExpectInputError(
      [&] {
        RequireInnerRadius(
            OpenDataset(dir, {.camera_path = dir / "cam.yaml", .inner_radius_m = {}, .fps = {}}));
      },
      {"--radius", "pipe.inner_radius_m"});
}

}  // namespace
}  // namespace pipescope

// The standing robustness suite (issue 26): a catalogue of corrupted datasets, bad files and bad
// flags, generated on the fly from small simulated datasets and run through every subcommand.
// Each case asserts the exit status (0: the damage is reported and skipped; 2: bad input; 1: a
// run that failed), that the message names the file, key or flag at fault, that no input was
// changed, and that nothing half-written is left (no hidden staging folder or temporary file).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "pipescope/cli/cli_testing.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

namespace fs = std::filesystem;

// The simulated inputs every case starts from, made once: a wall camera (000's 16-inch pipe,
// 160x120, 12 frames), a forward fisheye (001's network, 160x120, 3 frames) and three views of a
// checkerboard.
fs::path* base = nullptr;

class Robustness : public testing::Environment {
 public:
  void SetUp() override {
    base = new fs::path(MakeTestDirectory("robustness_base"));
    const std::string common = " --set width=160 --set height=120 --set white_card_count=1 -q";
    for (const std::string& arguments :
         {"simulate --preset steel-16in --frames 12 --set out_and_back=false --out " +
              (*base / "wall").string() + common,
          "simulate --preset fiberglass-network --frames 3 --out " + (*base / "fisheye").string() +
              common,
          "simulate --preset checkerboard --frames 1 --set width=480 --set height=360 --out " +
              (*base / "board").string() + " -q"}) {
      const CommandResult result = RunPipescope(arguments);
      ASSERT_EQ(result.exit_status, 0) << arguments << "\n" << result.output;
    }
  }
};

const testing::Environment* const kEnvironment = testing::AddGlobalTestEnvironment(new Robustness);

void WriteFile(const fs::path& path, const std::string& contents) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << contents;
}

void AppendLine(const fs::path& path, const std::string& line) {
  std::ofstream(path, std::ios::app) << line << "\n";
}

// Replaces one value of camera.yaml's params: 0 fx, 1 fy, 2 cx, 3 cy, 4 k1 (pinhole-radtan).
void SetCameraParam(const fs::path& dataset, int index, double value) {
  YAML::Node camera = YAML::LoadFile((dataset / "camera.yaml").string());
  camera["params"][index] = value;
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << camera;
  WriteFile(dataset / "camera.yaml", out.c_str());
}

void SetManifestKey(const fs::path& dataset, const std::string& key, const std::string& value) {
  YAML::Node manifest = YAML::LoadFile((dataset / "dataset.yaml").string());
  const auto dot = key.find('.');
  if (dot == std::string::npos) {
    manifest[key] = YAML::Load(value);
  } else {
    manifest[key.substr(0, dot)][key.substr(dot + 1)] = YAML::Load(value);
  }
  YAML::Emitter out;
  out << manifest;
  WriteFile(dataset / "dataset.yaml", out.c_str());
}

void WriteTimes(const fs::path& dataset, const std::vector<double>& times) {
  std::string text;
  for (double time : times) text += std::to_string(time) + "\n";
  WriteFile(dataset / "timestamps.txt", text);
  SetManifestKey(dataset, "timestamps", "timestamps.txt");
}

std::vector<double> Times(int count, double step = 0.1) {
  std::vector<double> times;
  for (int i = 0; i < count; ++i) times.push_back(i * step);
  return times;
}

// Every file below `dir` with a hash of its contents.
std::map<fs::path, std::size_t> Snapshot(const fs::path& dir) {
  std::map<fs::path, std::size_t> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (entry.is_regular_file()) {
      files[entry.path()] = std::hash<std::string>{}(ReadTextFile(entry.path()));
    }
  }
  return files;
}

struct Case {
  std::string name;
  // Damages the copies of the inputs in the case's folder: wall/, fisheye/, board/.
  std::function<void(const fs::path& dir)> damage;
  // The arguments; {W} {F} {B} are the wall, fisheye and board datasets, {O} the output, {C}
  // the case's folder (also the working directory).
  std::string arguments;
  int exit_status;
  std::vector<std::string> expected;   // in the output, e.g. the file, key or flag at fault
  std::string working_subfolder = "";  // of the case's folder, made empty, to run in
};

std::ostream& operator<<(std::ostream& stream, const Case& c) { return stream << c.name; }

std::string Expand(std::string text, const fs::path& dir) {
  const std::map<std::string, std::string> names = {{"{W}", (dir / "wall").string()},
                                                    {"{F}", (dir / "fisheye").string()},
                                                    {"{B}", (dir / "board").string()},
                                                    {"{O}", (dir / "out").string()},
                                                    {"{C}", dir.string()}};
  for (const auto& [key, value] : names) {
    for (auto at = text.find(key); at != std::string::npos; at = text.find(key)) {
      text.replace(at, key.size(), value);
    }
  }
  return text;
}

void NoDamage(const fs::path&) {}

const std::string kDense = "odometry {W} --method dense-lk --out {O} -q";

std::vector<Case> Catalogue() {
  const auto frame = [](const fs::path& dir) { return dir / "wall" / "images" / "000003.png"; };
  return {
      // Frames that cannot be used are reported and skipped; the run goes on.
      {"zero_byte_frame",
       [&](const fs::path& d) { WriteFile(frame(d), ""); },
       kDense,
       0,
       {"000003.png"}},
      {"truncated_frame",
       [&](const fs::path& d) { WriteFile(frame(d), ReadTextFile(frame(d)).substr(0, 200)); },
       kDense,
       0,
       {"000003.png"}},
      {"black_frame",
       [&](const fs::path& d) { cv::imwrite(frame(d).string(), cv::Mat::zeros(120, 160, CV_8U)); },
       kDense,
       0,
       {"000003.png", "uniform"}},
      {"saturated_frame",
       [&](const fs::path& d) {
         cv::imwrite(frame(d).string(), cv::Mat(120, 160, CV_8U, cv::Scalar(255)));
       },
       kDense,
       0,
       {"000003.png", "uniform"}},
      {"repeated_frame",
       [&](const fs::path& d) {
         fs::copy_file(d / "wall/images/000002.png", frame(d),
                       fs::copy_options::overwrite_existing);
       },
       kDense,
       0,
       {"000003.png", "repeated"}},
      {"wrong_size_frame",
       [&](const fs::path& d) { cv::imwrite(frame(d).string(), cv::Mat(60, 80, CV_8U, 90)); },
       kDense,
       2,
       {"000003.png", "camera.yaml"}},
      {"no_frames",
       [](const fs::path& d) {
         fs::remove_all(d / "wall/images");
         fs::create_directory(d / "wall/images");
       },
       kDense,
       2,
       {"images"}},
      // The manifest.
      {"manifest_not_yaml",
       [](const fs::path& d) { WriteFile(d / "wall/dataset.yaml", "a: [1,"); },
       kDense,
       2,
       {"dataset.yaml"}},
      {"manifest_without_camera",
       [](const fs::path& d) {
         YAML::Node m = YAML::LoadFile((d / "wall/dataset.yaml").string());
         m.remove("camera");
         YAML::Emitter out;
         out << m;
         WriteFile(d / "wall/dataset.yaml", out.c_str());
       },
       kDense,
       2,
       {"dataset.yaml", "camera"}},
      {"radius_huge",
       [](const fs::path& d) { SetManifestKey(d / "wall", "pipe.inner_radius_m", "1e300"); },
       "odometry {W} --method sparse --out {O} -q",
       2,
       {"dataset.yaml", "pipe.inner_radius_m"}},
      {"radius_tiny",
       [](const fs::path& d) { SetManifestKey(d / "wall", "pipe.inner_radius_m", "1e-6"); },
       kDense,
       2,
       {"dataset.yaml", "pipe.inner_radius_m"}},
      {"radius_flag_nan",
       NoDamage,
       "odometry {W} --method dense-lk --radius nan --out {O}",
       2,
       {"--radius"}},
      {"fps_flag_inf",
       NoDamage,
       "odometry {W} --method dense-lk --fps inf --out {O}",
       2,
       {"--fps"}},
      // The calibration.
      {"camera_k1_1e6",
       [](const fs::path& d) { SetCameraParam(d / "wall", 4, 1e6); },
       kDense,
       2,
       {"camera.yaml"}},
      {"camera_principal_point_outside",
       [](const fs::path& d) { SetCameraParam(d / "wall", 2, 1e4); },
       "undistort {W} --out {O}",
       2,
       {"camera.yaml", "principal point"}},
      {"camera_focal_1e12",
       [](const fs::path& d) {
         SetCameraParam(d / "wall", 0, 1e12);
         SetCameraParam(d / "wall", 1, 1e12);
       },
       kDense,
       2,
       {"camera.yaml", "focal length"}},
      {"camera_empty",
       [](const fs::path& d) { WriteFile(d / "wall/camera.yaml", ""); },
       kDense,
       2,
       {"camera.yaml"}},
      // Timestamps.
      {"timestamps_empty",
       [](const fs::path& d) {
         WriteTimes(d / "wall", Times(12));
         WriteFile(d / "wall/timestamps.txt", "");
       },
       kDense,
       2,
       {"timestamps.txt"}},
      {"timestamps_decreasing",
       [](const fs::path& d) {
         std::vector<double> times = Times(12);
         std::swap(times[4], times[5]);
         WriteTimes(d / "wall", times);
       },
       kDense,
       2,
       {"timestamps.txt:6", "increase"}},
      {"timestamps_short",
       [](const fs::path& d) { WriteTimes(d / "wall", Times(11)); },
       kDense,
       2,
       {"timestamps.txt"}},
      // Ground truth that cannot be compared: the run is still written, with a warning.
      {"groundtruth_one_pose",
       [](const fs::path& d) {
         std::istringstream lines(ReadTextFile(d / "wall/groundtruth.tum"));
         std::string kept, line;
         while (std::getline(lines, line)) {
           kept += line + "\n";
           if (!line.empty() && line[0] != '#') break;
         }
         WriteFile(d / "wall/groundtruth.tum", kept);
       },
       kDense,
       0,
       {"no metrics.json", "groundtruth.tum"}},
      {"groundtruth_garbage",
       [](const fs::path& d) { WriteFile(d / "wall/groundtruth.tum", "1 2 3\n"); },
       kDense,
       2,
       {"groundtruth.tum"}},
      // A method given a set-up it cannot measure.
      {"sparse_on_fisheye",
       NoDamage,
       "odometry {F} --method sparse --out {O} -q",
       2,
       {"camera.yaml", "--method sparse"}},
      {"map_on_wall_camera", NoDamage, "map {W} --out {O} -q", 2, {"camera.yaml", "map needs"}},
      {"unknown_method",
       NoDamage,
       "odometry {W} --method dense-foo --out {O}",
       2,
       {"--method", "sparse"}},
      // Config files.
      {"map_config_stages_0",
       [](const fs::path& d) { WriteFile(d / "c.yaml", "stages: 0\n"); },
       "map {F} --config {C}/c.yaml --out {O}",
       2,
       {"c.yaml", "stages"}},
      {"map_config_min_zncc_5",
       [](const fs::path& d) { WriteFile(d / "c.yaml", "min_zncc: 5\n"); },
       "map {F} --config {C}/c.yaml --out {O}",
       2,
       {"c.yaml", "min_zncc"}},
      {"map_config_per_region_negative",
       [](const fs::path& d) { WriteFile(d / "c.yaml", "per_region: -1\n"); },
       "map {F} --config {C}/c.yaml --out {O}",
       2,
       {"c.yaml", "per_region"}},
      {"odometry_config_unknown_key",
       [](const fs::path& d) { WriteFile(d / "c.yaml", "downsampel: 2\n"); },
       "odometry {W} --method dense-lk --config {C}/c.yaml --out {O}",
       2,
       {"c.yaml", "downsampel"}},
      {"odometry_config_not_yaml",
       [](const fs::path& d) { WriteFile(d / "c.yaml", "{{{"); },
       "odometry {W} --method dense-lk --config {C}/c.yaml --out {O}",
       2,
       {"c.yaml"}},
      // Outputs that would overwrite inputs, and outputs that are not where they must go.
      {"undistort_onto_its_dataset", NoDamage, "undistort {W} --out {W}", 2, {"--out", "dataset"}},
      {"odometry_into_its_dataset",
       NoDamage,
       "odometry {W} --method dense-lk --out {W}/run",
       2,
       {"--out", "dataset"}},
      {"odometry_out_working_directory",
       NoDamage,
       "odometry {W} --method dense-lk --out .",
       2,
       {"--out", "working directory"},
       "here"},
      {"map_over_an_odometry_run",
       [](const fs::path& d) {
         fs::create_directories(d / "out");
         WriteFile(d / "out/run.json", R"({"command": "odometry"})");
       },
       "map {F} --out {O}",
       2,
       {"--out", "odometry"}},
      {"evaluate_json_onto_gt",
       NoDamage,
       "evaluate --gt {W}/groundtruth.tum --est {W}/groundtruth.tum --json {W}/groundtruth.tum",
       2,
       {"--json", "--gt"}},
      {"evaluate_max_dt_nan",
       NoDamage,
       "evaluate --gt {W}/groundtruth.tum --est {W}/groundtruth.tum --max-dt nan",
       2,
       {"--max-dt"}},
      {"evaluate_one_pose_gt",
       [](const fs::path& d) { WriteFile(d / "gt.tum", "0 0 0 0 0 0 0 1\n"); },
       "evaluate --gt {C}/gt.tum --est {W}/groundtruth.tum",
       2,
       {"--gt", "--est"}},
      {"mosaic_onto_a_frame",
       NoDamage,
       "mosaic {W} --trajectory {W}/groundtruth.tum --out {W}/images/000000.png",
       2,
       {"--out", "images"}},
      {"mosaic_pixel_tiny",
       NoDamage,
       "mosaic {W} --trajectory {W}/groundtruth.tum --out {C}/m.png --pixel-mm 0.0001",
       2,
       {"--pixel-mm"}},
      {"mosaic_pixel_huge",
       NoDamage,
       "mosaic {W} --trajectory {W}/groundtruth.tum --out {C}/m.png --pixel-mm 500",
       2,
       {"--pixel-mm", "cells around"}},
      {"mosaic_spacing_nan",
       NoDamage,
       "mosaic {W} --trajectory {W}/groundtruth.tum --out {C}/m.png --mode image "
       "--min-spacing-px nan",
       2,
       {"--min-spacing-px"}},
      {"gainmask_sigma_nan",
       NoDamage,
       "gainmask {W}/white_card --out {C}/g.png --sigma-px nan",
       2,
       {"--sigma-px"}},
      {"gainmask_sigma_1e300",
       NoDamage,
       "gainmask {W}/white_card --out {C}/g.png --sigma-px 1e300",
       2,
       {"--sigma-px"}},
      {"gainmask_out_folder",
       NoDamage,
       "gainmask {W}/white_card --out {C}",
       2,
       {"--out", "folder"}},
      {"calibrate_report_is_out",
       NoDamage,
       "calibrate --model pinhole-radtan --board 9x6 --square-m 0.025 {B}/images --out "
       "{C}/cam.yaml "
       "--report {C}/cam.yaml",
       2,
       {"--report", "--out"}},
      {"calibrate_square_nan",
       NoDamage,
       "calibrate --model pinhole-radtan --board 9x6 --square-m nan {B}/images --out {C}/cam.yaml",
       2,
       {"--square-m"}},
      {"calibrate_one_view",
       NoDamage,
       "calibrate --model pinhole-radtan --board 9x6 --square-m 0.025 {B}/images --out "
       "{C}/cam.yaml",
       2,
       {"only 1", "views"}},
      {"refscale_spacing_inf",
       NoDamage,
       "refscale {W}/images/000000.png --camera {W}/camera.yaml --grid 5x4 --spacing-m inf",
       2,
       {"--spacing-m"}},
      {"calibrate_report_folder",
       [](const fs::path& d) { fs::create_directories(d / "rep"); },
       "calibrate --model pinhole-radtan --board 9x6 --square-m 0.025 {B}/images --out "
       "{C}/cam.yaml --report {C}/rep",
       2,
       {"--report", "folder"}},
      {"gainmask_saturated_cards",
       [](const fs::path& d) {
         for (const auto& card : fs::directory_iterator(d / "wall/white_card")) {
           cv::imwrite(card.path().string(), cv::Mat(120, 160, CV_8U, cv::Scalar(255)));
         }
       },
       "gainmask {W}/white_card --out {C}/g.png",
       0,
       {"saturated"}},
      // One frame: the run is written, says it is unreliable, and explains the missing metrics.
      {"one_frame_dataset",
       [](const fs::path& d) {
         for (const auto& image : fs::directory_iterator(d / "wall/images")) {
           if (image.path().filename() != "000000.png") fs::remove(image.path());
         }
       },
       kDense,
       0,
       {"UNRELIABLE", "no metrics.json"}},
      {"unknown_subcommand", NoDamage, "frobnicate", 2, {"frobnicate", "odometry"}},
      // Ranges print short: not 309 digits of the largest double.
      {"simulate_frames_negative",
       NoDamage,
       "simulate --preset steel-6in --frames -5 --out {O}",
       2,
       {"--frames", "[1, 1e+08]"}},
  };
}

class RobustnessCase : public testing::TestWithParam<Case> {};

TEST_P(RobustnessCase, ExitsAsPromisedNamesTheCulpritAndLeavesNoDebris) {
  const Case& c = GetParam();
  const fs::path dir = MakeTestDirectory("robustness_" + c.name);
  for (const char* input : {"wall", "fisheye", "board"}) {
    fs::copy(*base / input, dir / input, fs::copy_options::recursive);
  }
  c.damage(dir);
  if (!c.working_subfolder.empty()) fs::create_directories(dir / c.working_subfolder);
  const std::map<fs::path, std::size_t> before = Snapshot(dir);

  const CommandResult result =
      RunPipescope(Expand(c.arguments, dir), (dir / c.working_subfolder).string());

  EXPECT_EQ(result.exit_status, c.exit_status) << result.output;
  for (const std::string& text : c.expected) {
    EXPECT_NE(result.output.find(Expand(text, dir)), std::string::npos)
        << "expected '" << text << "' in:\n"
        << result.output;
  }
  // No library chatter (libpng, Ceres's glog) on the terminal.
  for (const char* chatter : {"libpng", "Jacobian", "GStreamer"}) {
    EXPECT_EQ(result.output.find(chatter), std::string::npos) << result.output;
  }
  // No input changed or removed.
  for (const auto& [path, hash] : before) {
    ASSERT_TRUE(fs::exists(path)) << path << " was removed";
    EXPECT_EQ(std::hash<std::string>{}(ReadTextFile(path)), hash) << path << " was changed";
  }
  // Nothing half-written: no hidden staging folder or temporary file anywhere.
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    EXPECT_FALSE(name.find(".partial-") != std::string::npos ||
                 name.find(".old-") != std::string::npos || name.find(".tmp") != std::string::npos)
        << entry.path();
  }
  // A refused run writes nothing; a run that went on writes its whole run directory.
  if (c.exit_status != 0) {
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      if (before.count(entry.path()) == 0 && entry.is_regular_file()) {
        ADD_FAILURE() << "left " << entry.path();
      }
    }
  } else if (c.arguments.find("--out {O}") != std::string::npos) {
    EXPECT_TRUE(fs::exists(dir / "out" / "run.json"));
    EXPECT_TRUE(fs::exists(dir / "out" / "trajectory.tum"));
  }
}

INSTANTIATE_TEST_SUITE_P(Catalogue, RobustnessCase, testing::ValuesIn(Catalogue()),
                         [](const testing::TestParamInfo<Case>& info) { return info.param.name; });

TEST(Robustness, SkippedFramesKeepTheirTimesThroughUndistort) {
  const fs::path dir = MakeTestDirectory("robustness_undistort_gap");
  fs::copy(*base / "wall", dir / "wall", fs::copy_options::recursive);
  WriteFile(dir / "wall/images/000004.png", "");
  const CommandResult result =
      RunPipescope("undistort " + (dir / "wall").string() + " --out " + (dir / "u").string());
  ASSERT_EQ(result.exit_status, 0) << result.output;
  std::istringstream lines(ReadTextFile(dir / "u/timestamps.txt"));
  std::vector<double> times;
  for (double time; lines >> time;) times.push_back(time);
  // 11 frames, and the one after the gap keeps its own time: two frame periods after frame 3.
  ASSERT_EQ(times.size(), 11u);
  const double period = times[1] - times[0];
  EXPECT_NEAR(times[4] - times[3], 2.0 * period, 1e-6);
  EXPECT_NEAR(times[10] - times[0], 11.0 * period, 1e-6);
}

// SIGINT, SIGTERM and SIGHUP remove the staging folder, say so, and leave an earlier output
// whole.
TEST(Robustness, InterruptionRemovesTheStagingFolderAndKeepsTheEarlierOutput) {
  const fs::path dir = MakeTestDirectory("robustness_interrupt");
  fs::create_directories(dir / "sim");
  WriteFile(dir / "sim" / "simulation.yaml", "earlier\n");
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    const std::string log = (dir / "log.txt").string();
    const pid_t child = fork();
    if (child == 0) {
      // A long render, interrupted well before it ends.
      const std::string command = std::string(PIPESCOPE_BINARY) +
                                  " simulate --preset steel-16in --frames 2000 -q --out " +
                                  (dir / "sim").string() + " > " + log + " 2>&1";
      execl("/bin/sh", "sh", "-c", ("exec " + command).c_str(), nullptr);
      _exit(127);
    }
    // Wait until the staging folder exists, so the signal arrives mid-run.
    bool staging = false;
    for (int i = 0; i < 200 && !staging; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      for (const auto& entry : fs::directory_iterator(dir)) {
        staging |= entry.path().filename().string().find(".partial-") != std::string::npos;
      }
    }
    ASSERT_TRUE(staging);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    kill(child, signal_number);
    int status = 0;
    waitpid(child, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + signal_number);
    const std::string output = ReadTextFile(log);
    EXPECT_NE(output.find("interrupted"), std::string::npos) << output;
    EXPECT_NE(output.find("removed"), std::string::npos) << output;
    EXPECT_EQ(ReadTextFile(dir / "sim" / "simulation.yaml"), "earlier\n");
    for (const auto& entry : fs::directory_iterator(dir)) {
      EXPECT_EQ(entry.path().filename().string().find(".partial-"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace pipescope

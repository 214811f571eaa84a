// End-to-end tests of `pipescope map` (001 §III A-D): a short simulated straight pass through
// the 400 mm fiberglass pipe with the 190-degree fisheye gives a run directory whose files agree
// with each other; bad input exits 2 naming the culprit and leaves no run directory behind; a
// run through a T-intersection places the junction where the truth has it.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "pipescope/cli/cli_testing.h"
#include "pipescope/io/junctions.h"
#include "pipescope/io/trajectory.h"
#include "pipescope/mapping/dense_appearance_map.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/simulation.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

int CountPoses(const std::string& path) {
  std::ifstream in(path);
  int count = 0;
  for (std::string line; std::getline(in, line);) count += !line.empty() && line[0] != '#';
  return count;
}

// A dense-map piece's cylinder as run.json `dense_map.pieces[]` describes it.
DenseMapCylinder PieceCylinder(const nlohmann::json& report, const nlohmann::json& piece) {
  const auto vector = [](const nlohmann::json& v) {
    return Eigen::Vector3d(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  };
  DenseMapCylinder cylinder;
  cylinder.axis_point = vector(piece["axis_point"]);
  cylinder.axis_direction = vector(piece["axis_direction"]);
  cylinder.radius_m = report["options"]["radius_m"].get<double>();
  cylinder.begin_m = piece["begin_m"].get<double>();
  cylinder.end_m = piece["end_m"].get<double>();
  cylinder.reference_direction = vector(piece["reference_direction"]);
  return cylinder;
}

// The short run's keys: windows and clusters small enough for 24 frames, and the key-frame flows
// halved with the image (640x480 against 001's 1280x960), so that every frame stays a key frame
// as at full size.
constexpr char kShortRunKeys[] =
    "window_interval: 8\nmin_window_keyframes: 8\nmin_cluster_size: 3\nmin_median_flow_px: "
    "5\nmax_median_flow_px: 7.5\n";

class MapCli : public testing::Test {
 protected:
  // 24 frames, 1 cm apart, at 640x480 (half the 001 camera's resolution) in a straight pipe.
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(MakeTestDirectory("map_cli"));
    const CommandResult simulate =
        RunPipescope("simulate --preset fiberglass-network --out " + Path("ds") +
                     " --frames 24 --set layout=straight --set length_m=2 --set speed_m_s=0.075"
                     " --set width=640 --set height=480 --set white_card_count=1 -q");
    ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
    WriteTextFileAtomically(*dir_ / "config.yaml", kShortRunKeys);
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
  }
  static std::string Path(const std::string& name) { return (*dir_ / name).string(); }
  // Maps the data set into Path(name) with the test's short-run keys, Ceres on one thread, and
  // `extra`; returns its keyframes.tum.
  static std::string RunWith(const std::string& name, const std::string& extra) {
    WriteTextFileAtomically(*dir_ / (name + ".yaml"),
                            std::string(kShortRunKeys) + "window_threads: 1\n" + extra);
    const CommandResult result = RunPipescope("map " + Path("ds") + " --out " + Path(name) +
                                              " --config " + Path(name + ".yaml") + " -q");
    EXPECT_EQ(result.exit_status, 0) << result.output;
    return ReadTextFile(Path(name) + "/keyframes.tum");
  }

  static std::filesystem::path* dir_;
};

std::filesystem::path* MapCli::dir_ = nullptr;

TEST_F(MapCli, WritesTheRunDirectory) {
  const std::string run = Path("run");
  const CommandResult result = RunPipescope("map " + Path("ds") + " --out " + run + " --config " +
                                            Path("config.yaml") + " -q");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const nlohmann::json report = nlohmann::json::parse(ReadTextFile(run + "/run.json"));
  EXPECT_EQ(report["command"], "map");
  EXPECT_EQ(report["options"]["window_interval"], 8);
  EXPECT_DOUBLE_EQ(report["options"]["radius_m"].get<double>(), 0.2);
  const long long keyframes = report["counts"]["keyframes"];
  EXPECT_GE(keyframes, 5);
  ASSERT_EQ(report["keyframes"].size(), static_cast<std::size_t>(keyframes));
  // A straight pipe: every key frame is classified straight, one section.
  for (const nlohmann::json& keyframe : report["keyframes"]) {
    EXPECT_EQ(keyframe["class"], "straight");
  }
  ASSERT_EQ(report["sections"].size(), 1u);
  EXPECT_TRUE(report["sections"][0].contains("distance_error_pct"));
  EXPECT_FALSE(report["windows"].empty());
  EXPECT_EQ(CountPoses(run + "/keyframes.tum"), keyframes);
  EXPECT_EQ(CountPoses(run + "/trajectory.tum"), report["counts"]["frames_localised"]);
  EXPECT_EQ(report["counts"]["frames_localised"].get<long long>() +
                report["counts"]["frames_unusable"].get<long long>(),
            24);
  const nlohmann::json metrics = nlohmann::json::parse(ReadTextFile(run + "/metrics.json"));
  EXPECT_EQ(metrics["frames_gt"], 24);
  const std::string ply = ReadTextFile(run + "/points_sparse.ply");
  EXPECT_EQ(ply.rfind("ply\nformat ascii 1.0\n", 0), 0u);
  EXPECT_NE(ply.find("element vertex " +
                     std::to_string(report["counts"]["points_sparse"].get<long long>())),
            std::string::npos);
  const cv::Mat strip = cv::imread(run + "/classification.png", cv::IMREAD_UNCHANGED);
  EXPECT_FALSE(strip.empty());
}

// A run whose window adjustments were all rejected (here by an image RMS limit no window can
// meet) has a scale no window confirmed: unreliable, and it says why (the share allowed is
// tested in pipeline_test, WindowConfirmation).
TEST_F(MapCli, RejectedWindowsMakeTheRunUnreliable) {
  const std::string run = Path("rejected");
  WriteTextFileAtomically(
      *dir_ / "reject.yaml",
      "window_interval: 8\nmin_window_keyframes: 8\nmin_cluster_size: 3\nmax_window_rms_px: 0\n");
  const CommandResult result = RunPipescope("map " + Path("ds") + " --out " + run + " --config " +
                                            Path("reject.yaml") + " -q");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const nlohmann::json report = nlohmann::json::parse(ReadTextFile(run + "/run.json"));
  ASSERT_FALSE(report["windows"].empty());
  EXPECT_EQ(report["quality"]["verdict"], "unreliable");
  const std::string windows = std::to_string(report["windows"].size());
  bool said = false;
  for (const nlohmann::json& reason : report["quality"]["reasons"]) {
    said = said || reason.get<std::string>().find(windows + " of " + windows +
                                                  " window adjustments were rejected (image "
                                                  "rms: " +
                                                  windows) != std::string::npos;
  }
  EXPECT_TRUE(said) << report["quality"].dump();
}

// use_cylinder: false makes the straight windows plain bundle adjustments (it used to be
// overridden by the section's class and change nothing): the windows say so, still count as
// straight, and the poses differ from the default run's.
TEST_F(MapCli, UseCylinderFalseIsHonoured) {
  const std::string with_poses = RunWith("with_cylinder", "");
  const std::string without_poses = RunWith("without_cylinder", "use_cylinder: false\n");
  const nlohmann::json with =
      nlohmann::json::parse(ReadTextFile(Path("with_cylinder") + "/run.json"));
  const nlohmann::json without =
      nlohmann::json::parse(ReadTextFile(Path("without_cylinder") + "/run.json"));
  ASSERT_FALSE(with["windows"].empty());
  ASSERT_FALSE(without["windows"].empty());
  for (const nlohmann::json& window : with["windows"]) {
    EXPECT_TRUE(window["straight"].get<bool>());
    EXPECT_TRUE(window["cylinder"].get<bool>());
  }
  for (const nlohmann::json& window : without["windows"]) {
    EXPECT_TRUE(window["straight"].get<bool>());
    EXPECT_FALSE(window["cylinder"].get<bool>());
    EXPECT_EQ(window["cylinder_rms_m"].get<double>(), 0.0);
  }
  EXPECT_NE(with_poses, without_poses);
}

// The default matcher, lucas-kanade, follows the key frame's features: the run says so, no key
// frame has guided matches (every feature was followed), and the section's length is within 3 %
// of the truth (-1.2 % when this test was written). `matcher: templates` (001) is still there,
// with its guided matches; on these half-size frames its section is 19 % off.
TEST_F(MapCli, TheMatcherIsLucasKanadeUnlessTemplatesAreAskedFor) {
  RunWith("lucas_kanade", "");
  const nlohmann::json report =
      nlohmann::json::parse(ReadTextFile(Path("lucas_kanade") + "/run.json"));
  EXPECT_EQ(report["options"]["matcher"], "lucas-kanade");
  ASSERT_GE(report["keyframes"].size(), 16u);
  int carried = 0;
  for (const nlohmann::json& keyframe : report["keyframes"]) {
    EXPECT_EQ(keyframe["matches_guided"], 0);
    carried += keyframe["matches_cosine"].get<int>();
  }
  EXPECT_GE(carried, 100 * static_cast<int>(report["keyframes"].size() - 1));
  EXPECT_EQ(report["counts"]["frames_unusable"], 0);
  const double error_pct = report["sections"][0]["distance_error_pct"];
  EXPECT_LT(std::abs(error_pct), 3.0);

  RunWith("templates", "matcher: templates\n");
  const nlohmann::json templates =
      nlohmann::json::parse(ReadTextFile(Path("templates") + "/run.json"));
  EXPECT_EQ(templates["options"]["matcher"], "templates");
  int guided = 0;
  for (const nlohmann::json& keyframe : templates["keyframes"]) {
    guided += keyframe["matches_guided"].get<int>();
  }
  EXPECT_GT(guided, 0);
}

// The odometry overlapped with the tracking sees the same key frames and sections in the same
// order as the odometry run after it: the same poses to the last digit (Ceres on one thread,
// whose multi-threaded sums may round differently), and the same on a second overlapped run.
TEST_F(MapCli, OverlappedOdometryGivesTheSequentialPoses) {
  const std::string sequential = RunWith("sequential", "overlap_odometry: false\n");
  const std::string overlapped = RunWith("overlapped", "");
  const std::string again = RunWith("overlapped_again", "");
  ASSERT_GE(CountPoses(Path("sequential") + "/keyframes.tum"), 16);
  EXPECT_EQ(overlapped, sequential);
  EXPECT_EQ(again, sequential);
  const nlohmann::json report =
      nlohmann::json::parse(ReadTextFile(Path("overlapped") + "/run.json"));
  EXPECT_TRUE(report["options"]["overlap_odometry"].get<bool>());
  EXPECT_GE(report["windows"].size(), 2u);
}

// 001 §IV-B: the dense map's grey values follow the simulator's albedo on the straight wall
// (80 frames at full size: the half-size frames of the tests above map 11 % short), scored by
// `pipescope evaluate --dense-map` (eval/dense_map_agreement.h: each row placed in the scene
// through the true and estimated poses of the key frame nearest it, both high-passed at 2 cm, at
// the best whole-cell shift). Issue 23 asks for 0.8 on the straight sections.
TEST(MapCliDense, DenseMapFollowsTheWallsAlbedo) {
  const std::filesystem::path dir = MakeTestDirectory("map_dense");
  const CommandResult simulate = RunPipescope(
      "simulate --preset fiberglass-network --out " + (dir / "ds").string() +
      " --frames 80 --set layout=straight --set length_m=2 --set speed_m_s=0.075 -q");
  ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  WriteTextFileAtomically(dir / "config.yaml", "window_threads: 1\n");
  const std::string run = (dir / "run").string();
  const CommandResult mapped = RunPipescope("map " + (dir / "ds").string() + " --out " + run +
                                            " --config " + (dir / "config.yaml").string() + " -q");
  ASSERT_EQ(mapped.exit_status, 0) << mapped.output;
  const std::string metrics_path = (dir / "dense_metrics.json").string();
  const CommandResult evaluated = RunPipescope(
      "evaluate --gt " + (dir / "ds" / "groundtruth.tum").string() + " --est " + run +
      "/trajectory.tum --dense-map " + run + " --simulation " +
      (dir / "ds" / "simulation.yaml").string() + " --json " + metrics_path + " -q");
  ASSERT_EQ(evaluated.exit_status, 0) << evaluated.output;
  EXPECT_NE(evaluated.output.find("straight pieces: median"), std::string::npos)
      << evaluated.output;
  const nlohmann::json dense = nlohmann::json::parse(ReadTextFile(metrics_path))["dense_map"];
  ASSERT_EQ(dense["pieces"].size(), 1u) << dense.dump();
  const nlohmann::json& piece = dense["pieces"][0];
  EXPECT_EQ(piece["part"], "straight");
  EXPECT_GT(piece["cells"].get<int>(), 10000);
  EXPECT_FALSE(piece["shift_at_limit"].get<bool>()) << piece.dump();
  RecordProperty("correlation", std::to_string(piece["correlation"].get<double>()));
  // Measured 0.90 (0.47 when the map was built, 2026-11-27, before the features were followed by
  // Lucas-Kanade); a map whose cells were misplaced (a mirrored angle, a wrong axis)
  // correlates near 0 (eval_test).
  EXPECT_GE(piece["correlation"].get<double>(), 0.8) << piece.dump();
  EXPECT_DOUBLE_EQ(dense["straight_worst_correlation"].get<double>(),
                   piece["correlation"].get<double>());

  // The flags go together, and the error names them.
  const CommandResult alone = RunPipescope("evaluate --gt " +
                                           (dir / "ds" / "groundtruth.tum").string() + " --est " +
                                           run + "/trajectory.tum --dense-map " + run + " -q");
  EXPECT_EQ(alone.exit_status, 2);
  EXPECT_NE(alone.output.find("--simulation"), std::string::npos) << alone.output;
  std::filesystem::remove_all(dir);
}

TEST_F(MapCli, BadInputExitsTwoAndNamesTheCulprit) {
  struct Case {
    std::string arguments;
    std::string culprit;
  };
  WriteTextFileAtomically(*dir_ / "typo.yaml", "window_intervall: 5\n");
  WriteTextFileAtomically(*dir_ / "value.yaml", "tau: big\n");
  const std::string ds = Path("ds");
  // The same data set with a gain mask of another size than the frames: the dense map would
  // only read it after the odometry, so the run must refuse it before it starts.
  std::filesystem::copy(ds, Path("small_mask"), std::filesystem::copy_options::recursive);
  cv::imwrite(Path("small_mask") + "/gain_mask.png", cv::Mat(10, 10, CV_8U, cv::Scalar(200)));
  const std::vector<Case> cases = {
      {ds + " --out " + Path("bad1") + " --config " + Path("typo.yaml"), "window_intervall"},
      {ds + " --out " + Path("bad2") + " --config " + Path("value.yaml"), "tau"},
      {ds + " --out " + Path("bad3") + " --config " + Path("missing.yaml"), "missing.yaml"},
      {Path("no_such_dataset") + " --out " + Path("bad4"), "no_such_dataset"},
      {ds + "/images --out " + Path("bad5"), "--camera"},
      {Path("small_mask") + " --out " + Path("bad6"), "gain_mask.png"},
  };
  for (const Case& c : cases) {
    const CommandResult result = RunPipescope("map " + c.arguments + " -q");
    EXPECT_EQ(result.exit_status, 2) << c.arguments << "\n" << result.output;
    EXPECT_NE(result.output.find(c.culprit), std::string::npos) << result.output;
  }
  for (const char* bad : {"bad1", "bad2", "bad3", "bad4", "bad5", "bad6"}) {
    EXPECT_FALSE(std::filesystem::exists(Path(bad))) << bad;
  }
}

// Frames of plain noise after the first: no frame matches its key frame, no wall point is
// triangulated, and the run fails (exit 1), writes nothing, and says which frame failed and why.
TEST_F(MapCli, AFailedRunSaysWhichFramesFailedAndWhy) {
  const std::string noise = Path("plain_noise");
  std::filesystem::copy(Path("ds"), noise, std::filesystem::copy_options::recursive);
  ASSERT_TRUE(WritePlainNoiseFrames(noise, 1, 24, 640, 480, 3));
  const CommandResult result = RunPipescope("map " + noise + " --out " + Path("run-noise") +
                                            " --config " + Path("config.yaml") + " -q");
  EXPECT_EQ(result.exit_status, 1) << result.output;
  EXPECT_NE(result.output.find("no point of the wall was triangulated"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("of 24 frames could not be matched to their key frame (the "
                               "first, " +
                               noise + "/images/000001.png: only"),
            std::string::npos)
      << result.output;
  // Said once, in the error: no warning points to a run.json that is not written.
  EXPECT_EQ(result.output.find("see failed_frames"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(Path("run-noise")));
}

// The position at `timestamp` (to 1 ms) of a trajectory.
Eigen::Vector3d PositionAt(const Trajectory& trajectory, double timestamp) {
  for (const StampedPose& pose : trajectory) {
    if (std::abs(pose.timestamp - timestamp) < 1e-3) return pose.position;
  }
  ADD_FAILURE() << "no pose at " << timestamp;
  return Eigen::Vector3d::Zero();
}

// 001 §III-D end to end: 230 frames of the full-size network preset through T1 (0.9 m of the
// start arm, the T, about 1 m of the T1-T2 side; the speed varies by 5 %). The T is adjusted
// with the two-cylinder model; its centre lies as far from the last camera before the T and the
// first after it as the true T1 does (both frame-independent, so no alignment enters), to 2.5 cm
// (measured: 1.9 cm before the T, 3.8 mm after it) and closer than where the end cylinders put
// it on the chained poses (3.5 cm short before the T).
TEST(MapCliNetwork, TheTModelPlacesTheJunction) {
  const std::filesystem::path dir = MakeTestDirectory("map_t");
  const std::string ds = (dir / "ds").string();
  const CommandResult simulate =
      RunPipescope("simulate --preset fiberglass-network --out " + ds +
                   " --frames 230 --set speed_m_s=0.075 --set speed_variation=0.05 -q");
  ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  WriteTextFileAtomically(dir / "config.yaml", "window_threads: 1\n");
  const CommandResult result = RunPipescope("map " + ds + " --out " + (dir / "run").string() +
                                            " --config " + (dir / "config.yaml").string() + " -q");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const nlohmann::json report =
      nlohmann::json::parse(ReadTextFile((dir / "run" / "run.json").string()));
  ASSERT_EQ(report["t_intersections"].size(), 1u) << report["sections"].dump();
  const nlohmann::json& t = report["t_intersections"][0];
  ASSERT_TRUE(t["adjusted"].get<bool>()) << t.dump();
  EXPECT_EQ(report["sections"][t["section"].get<int>()]["class"], "t-intersection");
  // The scene's two pipes meet at 89.6 degrees. The straight windows leave the red section's
  // last half metre turned; held at that section's last key frame (t_red_lead_radii: 0) the T came
  // out at 95.6 degrees, held half a metre before it at 93.3.
  EXPECT_NEAR(t["phi_deg"].get<double>(), 90.0, 4.5);
  // Nothing else in the run checks that angle (no loop), and the run says so: its positions past
  // the turn are unconfirmed, while its distances along the pipe stand.
  const nlohmann::json& quality = report["quality"];
  EXPECT_EQ(quality["verdict"], "unreliable");
  ASSERT_EQ(quality["position_reasons"].size(), 1u) << quality.dump();
  EXPECT_NE(quality["position_reasons"][0].get<std::string>().find(
                "junction J1 (key frames " + std::to_string(t["red_keyframe"].get<int>())),
            std::string::npos)
      << quality["position_reasons"];
  EXPECT_EQ(quality["along_pipe_verdict"], "reliable") << quality["reasons"];
  // The starts: the chained T at seven scales (on the T from the red section's last key frame),
  // then, on the T from P_r, the best of them at the chained phi and with phi turned eight
  // ways; the solution kept is the second stage's start with the least score.
  const nlohmann::json& starts = t["starts"];
  ASSERT_EQ(starts.size(), 16u) << starts.dump();
  double least = 1e300;
  double best_scale = 0.0;
  for (int k = 0; k < 7; ++k) {
    EXPECT_EQ(starts[k]["stage"], "scale");
    EXPECT_EQ(starts[k]["phi_offset_deg"].get<double>(), 0.0);
    if (starts[k]["score"].get<double>() < least) {
      least = starts[k]["score"].get<double>();
      best_scale = starts[k]["scale"].get<double>();
    }
  }
  least = 1e300;
  double chosen_offset = 1e300;
  for (int k = 7; k < 16; ++k) {
    EXPECT_EQ(starts[k]["stage"], "phi");
    EXPECT_EQ(starts[k]["scale"].get<double>(), best_scale);
    EXPECT_EQ(starts[k]["phi_offset_deg"].get<double>() == 0.0, k == 7);
    if (starts[k]["score"].get<double>() < least) {
      least = starts[k]["score"].get<double>();
      chosen_offset = starts[k]["phi_offset_deg"].get<double>();
    }
  }
  EXPECT_EQ(t["start_scale"].get<double>(), best_scale);
  EXPECT_EQ(t["start_phi_offset_deg"].get<double>(), chosen_offset);
  // A kept start at the range's end (+-16 degrees) is flagged, and the run warns of it.
  const bool at_end = std::abs(chosen_offset) == 16.0;
  EXPECT_EQ(t["phi_start_at_range_end"].get<bool>(), at_end);
  EXPECT_EQ(report["warnings"].dump().find("from the last of its starts") != std::string::npos,
            at_end)
      << report["warnings"].dump();
  const nlohmann::json& red_section = report["sections"][t["section"].get<int>() - 1];
  EXPECT_LT(t["red_keyframe"].get<int>(), red_section["last_keyframe"].get<int>());
  const std::vector<Junction> junctions = ReadEstimatedJunctions(dir / "run" / "junctions.yaml");
  ASSERT_EQ(junctions.size(), 1u);
  const Eigen::Vector3d true_t1 = ReadSceneJunctions(dir / "ds" / "scene.yaml").front().center;
  const Trajectory keyframes = ReadTumTrajectory(dir / "run" / "keyframes.tum");
  const Trajectory truth = ReadTumTrajectory(dir / "ds" / "groundtruth.tum");
  // l_r and l_b are the distances of each camera's foot on its axis from the centre; the
  // cameras ride within about 1 cm of the axis, which changes the distance by under 0.5 mm.
  for (const auto& [side, length] :
       {std::pair{"red_keyframe", "l_red_m"}, std::pair{"blue_keyframe", "l_blue_m"}}) {
    const double timestamp = keyframes.at(t[side].get<int>()).timestamp;
    const double expected = (true_t1 - PositionAt(truth, timestamp)).norm();
    const double estimated = (junctions[0].center - PositionAt(keyframes, timestamp)).norm();
    EXPECT_NEAR(estimated, expected, 0.025) << side;
    EXPECT_LT(std::abs(std::abs(t[length].get<double>()) - expected),
              std::abs(std::abs(t["initial"][length].get<double>()) - expected) + 0.002)
        << side;
  }

  // The dense map of the T (001 §IV-B): its red and blue pieces, each cell seen put into the
  // scene by the rigid motion that best aligns the run's key frames from P_r to P_b with the
  // truth's (Umeyama), and compared with where the ray from the true centre of T1 through it
  // meets the simulated wall.
  const int t_section = t["section"].get<int>();
  std::vector<nlohmann::json> t_pieces;
  for (const nlohmann::json& piece : report["dense_map"]["pieces"]) {
    if (piece["section"].get<int>() == t_section) t_pieces.push_back(piece);
  }
  ASSERT_EQ(t_pieces.size(), 2u) << report["dense_map"].dump();
  EXPECT_EQ(t_pieces[0]["part"], "t-red");
  EXPECT_EQ(t_pieces[1]["part"], "t-blue");
  const int red_keyframe = t["red_keyframe"].get<int>();
  const int blue_keyframe = t["blue_keyframe"].get<int>();
  Eigen::Matrix3Xd run_positions(3, blue_keyframe - red_keyframe + 1);
  Eigen::Matrix3Xd true_positions(3, blue_keyframe - red_keyframe + 1);
  for (int k = red_keyframe; k <= blue_keyframe; ++k) {
    run_positions.col(k - red_keyframe) = keyframes.at(k).position;
    true_positions.col(k - red_keyframe) = PositionAt(truth, keyframes.at(k).timestamp);
  }
  const Eigen::Isometry3d scene_from_run(
      Eigen::umeyama(run_positions, true_positions, /*with_scaling=*/false));
  SimulationConfig config = PresetConfig("fiberglass-network");
  SetConfigValue(&config, "frames=230");
  const Simulation simulation(config);
  const cv::Mat mosaic =
      cv::imread((dir / "run" / ("dense_section_" + std::to_string(t_section) + ".png")).string(),
                 cv::IMREAD_GRAYSCALE);
  std::vector<double> errors;
  int row_offset = 0;
  for (const nlohmann::json& piece : t_pieces) {
    const DenseMapGrid grid(PieceCylinder(report, piece),
                            report["dense_map"]["spacing_m"].get<double>());
    ASSERT_LE(row_offset + grid.rows(), mosaic.rows);
    for (int row = 0; row < grid.rows(); row += 2) {
      for (int col = 0; col < grid.cols(); col += 2) {
        if (mosaic.at<uchar>(row_offset + row, col) == 0) continue;  // unseen or open
        const Eigen::Vector3d point = scene_from_run * grid.CellPoint(row, col);
        const Ray ray{true_t1, (point - true_t1).normalized()};
        const std::optional<WallHit> hit = simulation.layout().scene.Intersect(ray);
        if (hit) errors.push_back(std::abs((point - true_t1).norm() - hit->distance));
      }
    }
    row_offset += grid.rows();
  }
  ASSERT_GT(errors.size(), 5000u);
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2];
  const double p90 = errors[errors.size() * 9 / 10];
  RecordProperty("t_wall_median_mm", std::to_string(1000 * median));
  RecordProperty("t_wall_p90_mm", std::to_string(1000 * p90));
  EXPECT_LT(median, 0.01);
  EXPECT_LT(p90, 0.025);
  EXPECT_EQ(t["phi_source"], "measured");

  // The same passage with the fitting's angle given (a 90-degree tee; the scene's pipes meet at
  // 89.6): the T holds phi there and the junction is placed as well as before. The turn is still
  // unconfirmed (no loop), its reason says the angle was given, and its end cylinders agree
  // with it (within 20 degrees).
  WriteTextFileAtomically(dir / "given.yaml", "window_threads: 1\nt_fitting_angle_deg: 90\n");
  const CommandResult given =
      RunPipescope("map " + ds + " --out " + (dir / "given").string() + " --config " +
                   (dir / "given.yaml").string() + " -q --no-report");
  ASSERT_EQ(given.exit_status, 0) << given.output;
  const nlohmann::json given_report =
      nlohmann::json::parse(ReadTextFile((dir / "given" / "run.json").string()));
  ASSERT_EQ(given_report["t_intersections"].size(), 1u);
  const nlohmann::json& given_t = given_report["t_intersections"][0];
  ASSERT_TRUE(given_t["adjusted"].get<bool>()) << given_t.dump();
  EXPECT_EQ(given_t["phi_source"], "given");
  EXPECT_EQ(given_t["starts"].size(), 8u);  // phi held: the scales, then the best on the T from P_r
  EXPECT_NEAR(given_t["phi_deg"].get<double>(), 90.0, 1e-9);
  const nlohmann::json& given_reasons = given_report["quality"]["position_reasons"];
  ASSERT_EQ(given_reasons.size(), 1u) << given_report["quality"].dump();
  const std::string given_reason = given_reasons[0].get<std::string>();
  EXPECT_NE(given_reason.find("held at the given fitting angle (90.0 deg"), std::string::npos)
      << given_reason;
  EXPECT_EQ(given_reason.find("may not be what was given"), std::string::npos) << given_reason;
  const Trajectory given_keyframes = ReadTumTrajectory(dir / "given" / "keyframes.tum");
  const Eigen::Vector3d given_centre =
      ReadEstimatedJunctions(dir / "given" / "junctions.yaml").front().center;
  for (const char* side : {"red_keyframe", "blue_keyframe"}) {
    const double timestamp = given_keyframes.at(given_t[side].get<int>()).timestamp;
    EXPECT_NEAR((given_centre - PositionAt(given_keyframes, timestamp)).norm(),
                (true_t1 - PositionAt(truth, timestamp)).norm(), 0.025)
        << side;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pipescope

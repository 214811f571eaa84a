// End-to-end tests of `pipescope odometry` with the dense methods (000 §4, 003 §2): a short
// simulated pass gives a run directory whose files agree with each other and the ground truth;
// bad input exits 2 naming the culprit and leaves no run directory behind.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "pipescope/cli/cli_testing.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

class OdometryCli : public testing::Test {
 protected:
  // 000's 16-inch pipe at 320x240 registered at 160x120 (downsample 2): 30 frames, 80 mm.
  static void SetUpTestSuite() {
    dir_ = new std::filesystem::path(MakeTestDirectory("odometry_cli"));
    const CommandResult simulate =
        RunPipescope("simulate --preset steel-16in --out " + Path("ds") +
                     " --frames 30 --set width=320 --set height=240 --set white_card_count=2"
                     " --set out_and_back=false -q");
    ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
    WriteTextFileAtomically(*dir_ / "config.yaml", "downsample: 2\n");
  }
  static void TearDownTestSuite() {
    std::filesystem::remove_all(*dir_);
    delete dir_;
  }
  static std::string Path(const std::string& name) { return (*dir_ / name).string(); }
  // Runs sparse on `dataset` into Path(run) with `config` (YAML text) and returns its run.json.
  static nlohmann::json RunSparse(const std::string& dataset, const std::string& run,
                                  const std::string& config) {
    WriteTextFileAtomically(*dir_ / (run + ".yaml"), config);
    const CommandResult result =
        RunPipescope("odometry " + Path(dataset) + " --method sparse --out " + Path(run) +
                     " --config " + Path(run + ".yaml") + " --no-report -q");
    EXPECT_EQ(result.exit_status, 0) << result.output;
    return nlohmann::json::parse(ReadTextFile(Path(run) + "/run.json"));
  }

  static std::filesystem::path* dir_;
};

std::filesystem::path* OdometryCli::dir_ = nullptr;

TEST_F(OdometryCli, WritesTheRunDirectory) {
  for (const std::string method : {"dense-hybrid", "dense-unrolled"}) {
    const std::string run = Path("run-" + method);
    const CommandResult result =
        RunPipescope("odometry " + Path("ds") + " --method " + method + " --out " + run +
                     " --config " + Path("config.yaml") + " -q");
    ASSERT_EQ(result.exit_status, 0) << result.output;
    const nlohmann::json metrics = nlohmann::json::parse(ReadTextFile(run + "/metrics.json"));
    EXPECT_EQ(metrics["frames_est"], 30);
    EXPECT_EQ(metrics["frames_matched"], 30);
    // A sanity bound: 80 mm of travel with the preset's drift and wobble (dense_vo_test has the
    // accuracy tests).
    EXPECT_LT(metrics["distance_error_pct"].get<double>(), 5.0) << method;
    const nlohmann::json report = nlohmann::json::parse(ReadTextFile(run + "/run.json"));
    EXPECT_EQ(report["method"], method);
    EXPECT_EQ(report["options"]["downsample"], 2);
    EXPECT_EQ(report["options"]["unrolled_registration"], "phase");
    EXPECT_EQ(report["options"]["max_departure_from_prediction_px"], 16.0);
    EXPECT_EQ(report["counts"]["pairs_integer_only"], report["integer_only_frames"].size());
    EXPECT_EQ(report["counts"]["frames_localised"], 30);
    EXPECT_EQ(report["quality"]["verdict"], "reliable") << report["quality"].dump();
    EXPECT_EQ(report["quality"]["frames_measured"],
              30 - report["counts"]["pairs_failed"].get<int>());
    EXPECT_EQ(metrics["quality_verdict"], "reliable");
    EXPECT_TRUE(report["failed_frames"].is_array());
    // The dense methods hold the start's wall distance and say so, in run.json and a warning.
    EXPECT_EQ(report["wall_distance"]["measured"], false);
    EXPECT_EQ(report["wall_distance"]["start_from"], "reference_scale_px_per_m");
    bool warned = false;
    for (const auto& warning : report["warnings"]) {
      warned = warned || warning.get<std::string>().find("distance to the wall as fixed") !=
                             std::string::npos;
    }
    EXPECT_TRUE(warned) << report["warnings"].dump();
    const cv::Mat mosaic = cv::imread(run + "/mosaic.png", cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(mosaic.empty()) << method;
    EXPECT_EQ(mosaic.type(), CV_8U);
    EXPECT_TRUE(std::filesystem::exists(run + "/trajectory.tum"));
  }
}

// Without --method the set-up picks it (docs/conditions.md): the 16-inch pipe's 25-degree view
// cannot measure its wall distance, so a dense method; the 6-inch pipe's 70-degree view can, so
// the tubular EKF, which finds the pipe along image x. run.json says which and why.
TEST_F(OdometryCli, WithoutMethodChoosesForTheSetUp) {
  const CommandResult narrow =
      RunPipescope("odometry " + Path("ds") + " --out " + Path("run-auto-narrow") + " --config " +
                   Path("config.yaml") + " -q");
  ASSERT_EQ(narrow.exit_status, 0) << narrow.output;
  const nlohmann::json narrow_report =
      nlohmann::json::parse(ReadTextFile(Path("run-auto-narrow") + "/run.json"));
  EXPECT_EQ(narrow_report["method"], "dense-unrolled");
  EXPECT_EQ(narrow_report["method_choice"]["method"], "dense-unrolled");
  EXPECT_NE(narrow_report["method_choice"]["reason"].get<std::string>().find("cannot measure"),
            std::string::npos);

  const CommandResult simulate =
      RunPipescope("simulate --preset steel-6in --out " + Path("ds6") +
                   " --frames 40 --set speed_m_s=0.03 --set width=512 --set height=384"
                   " --set white_card_count=2 -q");
  ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  const std::string wide = Path("run-auto-wide");
  const CommandResult result =
      RunPipescope("odometry " + Path("ds6") + " --out " + wide + " --no-report -q");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const nlohmann::json report = nlohmann::json::parse(ReadTextFile(wide + "/run.json"));
  EXPECT_EQ(report["method"], "ekf");
  EXPECT_EQ(report["method_choice"]["method"], "ekf");
  EXPECT_NE(report["method_choice"]["reason"].get<std::string>().find("curvature"),
            std::string::npos)
      << report["method_choice"].dump();
  // The filter measured the camera's direction of travel: along image x, across the optical axis.
  EXPECT_EQ(report["options"]["axis_along_tube"], "auto");
  EXPECT_EQ(report["axis_along_tube"], "x") << report["travel_direction"].dump();
  // What "by the view" came to for a wall-looking camera: straight sections, two radii of
  // look-ahead, the frame itself tracked.
  EXPECT_EQ(report["chosen_by_the_view"]["curvature_sigma_radii"], 0.0);
  EXPECT_EQ(report["chosen_by_the_view"]["spawn_lookahead_radii"], 2.0);
  EXPECT_EQ(report["chosen_by_the_view"]["flat_field_sigma_px"], 0.0);
  EXPECT_EQ(report["wall_distance"]["method_measures"], true);
  EXPECT_EQ(report["quality"]["verdict"], "reliable") << report["quality"].dump();
  const nlohmann::json metrics = nlohmann::json::parse(ReadTextFile(wide + "/metrics.json"));
  EXPECT_LT(std::abs(metrics["distance_error_pct"].get<double>()), 1.0)
      << metrics["distance_error_pct"];

  // A run whose camera strays farther across the pipe than the limit is called unreliable.
  const nlohmann::json tight_report =
      RunSparse("ds6", "run-tight", "max_cross_section_excursion: 0.0001\n");
  EXPECT_EQ(tight_report["quality"]["verdict"], "unreliable");
  EXPECT_NE(tight_report["quality"]["reasons"].dump().find("strays"), std::string::npos)
      << tight_report["quality"].dump();
}

// Where the view cannot measure the wall distance (the 16-inch pipe's 25 degrees), a sparse run
// whose camera strays across the pipe by more than the limit's share of that distance is called
// unreliable, since its scale follows an excursion the images could not confirm.
TEST_F(OdometryCli, SparseOnANarrowViewDoubtsAnUnconfirmedExcursion) {
  const CommandResult simulate =
      RunPipescope("simulate --preset steel-16in --out " + Path("ds16-long") +
                   " --frames 90 --set width=320 --set height=240 --set speed_m_s=0.1"
                   " --set white_card_count=2 --set out_and_back=false -q");
  ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  const nlohmann::json report = RunSparse("ds16-long", "run-doubt",
                                          "max_unobserved_excursion: 0.000001\nmosaic: false\n"
                                          "sigma_window_px: 1.5\nsigma_derivative_px: 0.75\n");
  EXPECT_EQ(report["wall_distance"]["measured"], false);
  EXPECT_EQ(report["quality"]["verdict"], "unreliable");
  EXPECT_NE(report["quality"]["reasons"].dump().find("could not confirm"), std::string::npos)
      << report["quality"].dump();
}

// When the chosen ekf run ends unreliable (here most frames are plain noise, so its tracks are
// lost), odometry without --method runs dense-unrolled instead and says why.
TEST_F(OdometryCli, WithoutMethodFallsBackWhenTheFilterIsUnreliable) {
  const std::string data = Path("ds6-plain");
  const CommandResult simulate =
      RunPipescope("simulate --preset steel-6in --out " + data +
                   " --frames 40 --set speed_m_s=0.03 --set width=512 --set height=384"
                   " --set white_card_count=2 -q");
  ASSERT_EQ(simulate.exit_status, 0) << simulate.output;
  ASSERT_TRUE(WritePlainNoiseFrames(data, 8, 40, 512, 384, 5));
  const CommandResult result =
      RunPipescope("odometry " + data + " --out " + Path("run-fallback") + " --no-report");
  ASSERT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("running dense-unrolled instead"), std::string::npos)
      << result.output;
  const nlohmann::json report =
      nlohmann::json::parse(ReadTextFile(Path("run-fallback") + "/run.json"));
  EXPECT_EQ(report["method"], "dense-unrolled");
  const std::string reason = report["method_choice"]["reason"].get<std::string>();
  EXPECT_NE(reason.find("ekf was tried first"), std::string::npos) << reason;
  // The filter updated on every frame; only its tracks' disagreement shows the failure.
  EXPECT_NE(reason.find("the tracks disagree with the filter"), std::string::npos) << reason;
}

TEST_F(OdometryCli, BadInputExitsTwoAndNamesTheCulprit) {
  struct Case {
    std::string arguments;
    std::string culprit;
  };
  WriteTextFileAtomically(*dir_ / "typo.yaml", "downsampel: 2\n");
  WriteTextFileAtomically(*dir_ / "range.yaml", "registration_band: 1.5\n");
  WriteTextFileAtomically(*dir_ / "choice.yaml", "unrolled_registration: lk\n");
  WriteTextFileAtomically(*dir_ / "gate.yaml", "max_departure_from_prediction_px: -1\n");
  const std::string ds = Path("ds");
  const std::vector<Case> cases = {
      {ds + " --method dense-foo --out " + Path("bad1"), "--method"},
      {ds + " --method dense-sad --out " + Path("bad2") + " --config " + Path("typo.yaml"),
       "downsampel"},
      {ds + " --method dense-sad --out " + Path("bad3") + " --config " + Path("range.yaml"),
       "registration_band"},
      {ds + " --method dense-sad --out " + Path("bad4") + " --config " + Path("missing.yaml"),
       "missing.yaml"},
      {Path("nowhere") + " --method dense-sad --out " + Path("bad5"), "nowhere"},
      {ds + " --method dense-unrolled --out " + Path("bad6") + " --config " + Path("choice.yaml"),
       "unrolled_registration"},
      {ds + " --method dense-sad --out " + Path("bad7") + " --config " + Path("gate.yaml"),
       "max_departure_from_prediction_px"},
  };
  for (const Case& c : cases) {
    const CommandResult result = RunPipescope("odometry " + c.arguments + " -q");
    EXPECT_EQ(result.exit_status, 2) << c.arguments << "\n" << result.output;
    EXPECT_NE(result.output.find(c.culprit), std::string::npos) << result.output;
  }
  for (const char* run : {"bad1", "bad2", "bad3", "bad4", "bad5", "bad6", "bad7"}) {
    EXPECT_FALSE(std::filesystem::exists(Path(run))) << run;
  }
}

}  // namespace
}  // namespace pipescope

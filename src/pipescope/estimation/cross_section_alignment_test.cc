// CrossSectionAligner on simulator frames of the 6-inch wall camera (000's pipe 1, 70 degrees),
// where the view sees the wall's curvature: the crawler rides along the axis without wobble, so
// the true motion between a key frame and a later frame is travel and roll only, and the key
// camera's pose is given off by a known amount across the pipe. The alignment must find that
// amount and the true travel.
#include "pipescope/estimation/cross_section_alignment.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipescope/image/dense_frame_preparation.h"
#include "pipescope/image/gain_mask.h"
#include "pipescope/synthetic/presets.h"
#include "pipescope/synthetic/simulation.h"

namespace pipescope {
namespace {

constexpr int kDownsample = 2;

SimulationConfig StraightRideConfig(double contrast = 1.0, double noise_sigma = -1.0) {
  SimulationConfig config = PresetConfig("steel-6in");
  config.width = 512;
  config.height = 384;
  config.frames = 30;
  config.lateral_offset_m = 0.0;
  config.wobble_deg = 0.0;
  config.white_card_count = 1;
  config.texture_contrast = contrast;
  if (noise_sigma >= 0.0) config.noise_sigma = noise_sigma;
  return config;
}

class AlignSimulatedFrames : public testing::Test {
 protected:
  explicit AlignSimulatedFrames(const SimulationConfig& config = StraightRideConfig())
      : simulation_(config),
        preparation_(simulation_.camera(), BuildGainMask({simulation_.RenderWhiteCardRadiance(0)}, 2.0),
                     DenseFrameOptions{kDownsample}) {}

  cv::Mat Prepared(int index) const {
    return Aligner().Normalised(
        preparation_.CorrectAndDownsample(simulation_.RenderFrameRadiance(index)));
  }

  CrossSectionAligner Aligner() const {
    return CrossSectionAligner(simulation_.camera(), simulation_.config().radius_m, kDownsample,
                               options_);
  }

  double TrueTravel(int key, int current) const {
    return simulation_.FramePose(current).translation().z() -
           simulation_.FramePose(key).translation().z();
  }

  // The key camera assumed `error` (X, Y) off its true place across the pipe.
  CrossSectionAlignment AlignWithKeyOff(int key, int current, const Eigen::Vector2d& error,
                                        double travel_guess) const {
    Eigen::Isometry3d assumed = simulation_.FramePose(key);
    assumed.translation().head<2>() += error;
    return Aligner().Align(Prepared(key), Prepared(current), assumed, travel_guess, 0.0);
  }

  Simulation simulation_;
  DenseFramePreparation preparation_;
  CrossSectionAlignmentOptions options_;
};

TEST_F(AlignSimulatedFrames, FromTheTruePoseItStaysThere) {
  const double travel = TrueTravel(0, 7);
  ASSERT_GT(travel, 0.005);
  const CrossSectionAlignment result =
      AlignWithKeyOff(0, 7, Eigen::Vector2d::Zero(), 0.9 * travel);
  ASSERT_TRUE(result.converged);
  EXPECT_GT(result.samples, 3000);  // every 3rd pixel of the 256 x 192 prepared frame that overlaps
  EXPECT_NEAR(result.travel_m, travel, 0.002 * travel);
  EXPECT_LT(result.offset_m.norm(), 0.0002);
}

TEST_F(AlignSimulatedFrames, FindsTheOffsetTheKeyPoseDidNotKnow) {
  const double travel = TrueTravel(0, 7);
  // The crawler 2 mm nearer the wall the camera faces, and 1.5 mm to one side, than assumed:
  // 3 % of the wall distance, which a held pose turns into 3 % of every step.
  const Eigen::Isometry3d key = simulation_.FramePose(0);
  const Eigen::Vector3d optical_axis = key.linear().col(2);
  const Eigen::Vector2d towards_wall = optical_axis.head<2>().normalized();
  const Eigen::Vector2d sideways(-towards_wall.y(), towards_wall.x());
  const Eigen::Vector2d error = -0.002 * towards_wall + 0.0015 * sideways;
  options_.offset_step_sigma_m = 0.0;  // what the two frames alone say
  const CrossSectionAlignment result = AlignWithKeyOff(0, 7, error, travel);
  ASSERT_TRUE(result.converged);
  EXPECT_NEAR((result.offset_m + error).norm(), 0.0, 0.0003)
      << result.offset_m.transpose() << " against " << (-error).transpose();
  EXPECT_NEAR(result.travel_m, travel, 0.003 * travel);
}

TEST_F(AlignSimulatedFrames, ATravelStartedThreePercentLongComesBack) {
  // A start 3 % long (the error a held place 2.3 mm off gives) is far from the solution on
  // this texture: the alignment must still converge to the true step, and explain the frames.
  const double travel = TrueTravel(0, 7);
  const CrossSectionAlignment result =
      AlignWithKeyOff(0, 7, Eigen::Vector2d(0.0, 0.0), 1.03 * travel);
  ASSERT_TRUE(result.converged);
  EXPECT_NEAR(result.travel_m, travel, 0.002 * travel);
  EXPECT_FALSE(result.too_faint);
  EXPECT_LT(result.residual_sigma, 0.5);
}

TEST_F(AlignSimulatedFrames, FramesOfAnotherPlaceAreTooFaintToTrust) {
  // The control for the faintness check: a current frame 15 frames (2 cm) on from where the
  // alignment is started leaves nothing to line up, and its residuals stay at the texture's
  // own spread.
  const CrossSectionAlignment result =
      AlignWithKeyOff(0, 22, Eigen::Vector2d(0.0, 0.0), TrueTravel(0, 7));
  EXPECT_TRUE(result.too_faint) << result.residual_sigma;
}

}  // namespace
}  // namespace pipescope

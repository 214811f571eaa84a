// `pipescope gainmask`: the gain mask of 000 §3.2 from white-card images.
#include <spdlog/spdlog.h>

#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "pipescope/cli/flag_checks.h"
#include "pipescope/cli/subcommand.h"
#include "pipescope/image/gain_mask.h"
#include "pipescope/io/image_source.h"
#include "pipescope/util/error.h"
#include "pipescope/util/output_paths.h"

namespace pipescope {
namespace {

// Smoothing when --sigma-px is not given: 1 % of the image width removes the noise and keeps
// the lighting pattern, whose features span tens of percent of the image.
constexpr double kDefaultSigmaFraction = 0.01;

struct GainmaskFlags {
  std::vector<std::string> inputs;
  std::string out;
  double sigma_px = -1.0;
};

int RunGainmask(const GainmaskFlags& flags) {
  if (std::filesystem::is_directory(flags.out)) {
    throw InputError("--out " + flags.out + " is a folder; name the gain mask's .png file");
  }
  std::vector<cv::Mat> images;
  for (const std::filesystem::path& file : ExpandImageArguments(flags.inputs)) {
    RefuseOutputOverInputs(flags.out, "--out", {{file, "a white-card image"}});
    cv::Mat image = cv::imread(file.string(), cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
    if (image.empty()) throw InputError("cannot read image " + file.string());
    if (!images.empty() && image.size() != images.front().size()) {
      throw InputError("image " + file.string() + " is " + std::to_string(image.cols) + "x" +
                       std::to_string(image.rows) + " but the first is " +
                       std::to_string(images.front().cols) + "x" +
                       std::to_string(images.front().rows));
    }
    images.push_back(std::move(image));
  }
  // A clipped card has lost the lighting pattern where it is brightest: the mask comes out flat
  // there and corrects nothing.
  constexpr double kMaxSaturatedFraction = 0.01;
  for (std::size_t i = 0; i < images.size(); ++i) {
    const double saturated = SaturatedFraction(ToFloatGrey(images[i]), 254.5);
    if (saturated > kMaxSaturatedFraction) {
      spdlog::warn(
          "white card {} of {}: {:.1f} % of its pixels are saturated; the gain mask is flat "
          "there (take the cards with a shorter exposure)",
          i + 1, images.size(), 100.0 * saturated);
    }
  }
  const double sigma =
      flags.sigma_px >= 0 ? flags.sigma_px : kDefaultSigmaFraction * images.front().cols;
  WriteGainMask(flags.out, BuildGainMask(images, sigma));
  spdlog::info("wrote {} from {} images (Gaussian sigma {:.1f} px)", flags.out, images.size(),
               sigma);
  return kExitSuccess;
}

}  // namespace

SubcommandRunner SetupGainmaskCommand(CLI::App* command) {
  auto flags = std::make_shared<GainmaskFlags>();
  command->add_option("images", flags->inputs, "White-card images, or folders of them")->required();
  command->add_option("--out", flags->out, "Gain mask to write (16-bit PNG)")->required();
  command
      ->add_option("--sigma-px", flags->sigma_px,
                   "Gaussian smoothing, pixels (default 1 % of the image width)")
      ->check(FiniteNonNegative(1e4));
  return [flags] { return RunGainmask(*flags); };
}

}  // namespace pipescope

#include "pipescope/synthetic/wall_texture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <thread>
#include <vector>

#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr WallMaterial kMaterials[] = {WallMaterial::kSteel, WallMaterial::kFiberglass,
                                       WallMaterial::kConcrete};
// Inner radii of the presets: 000 pipes 1 and 2, 001's fiberglass, 003's culvert.
constexpr double kRadii[] = {0.07666, 0.19378, 0.2, 0.15};

double Circumference(double radius) { return 2 * kPi * radius; }

WallTextureOptions Options(WallMaterial material) {
  WallTextureOptions options;
  options.material = material;
  options.joint_spacing_m = 1.5;
  options.marking_spacing_m = 2.0;
  return options;
}

struct Stats {
  double mean = 0;
  double stddev = 0;
};

Stats StatsOf(const std::vector<double>& values) {
  Stats stats;
  for (const double v : values) stats.mean += v;
  stats.mean /= static_cast<double>(values.size());
  for (const double v : values) stats.stddev += (v - stats.mean) * (v - stats.mean);
  stats.stddev = std::sqrt(stats.stddev / static_cast<double>(values.size()));
  return stats;
}

// Albedo at `count` random points of section 0, h in [0, 6) m.
std::vector<double> RandomAlbedos(const WallTexture& texture, double circumference,
                                  double footprint, int count, std::uint32_t seed = 5) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<double> values;
  for (int i = 0; i < count; ++i) {
    const double h = 6 * unit(rng);
    const double s = circumference * unit(rng);
    values.push_back(texture.Albedo(0, h, s, circumference, footprint));
  }
  return values;
}

// Standard deviation of A(h + spacing, s) - A(h, s) over random points: the energy the
// footprint filter must remove.
double DifferenceStddev(const WallTexture& texture, double circumference, double footprint,
                        double spacing, int count = 20000) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<double> differences;
  for (int i = 0; i < count; ++i) {
    const double h = 6 * unit(rng);
    const double s = circumference * unit(rng);
    differences.push_back(texture.Albedo(0, h + spacing, s, circumference, footprint) -
                          texture.Albedo(0, h, s, circumference, footprint));
  }
  return StatsOf(differences).stddev;
}

TEST(WallMaterial, ParsesNamesAndRejectsOthersListingTheValidOnes) {
  for (const WallMaterial material : kMaterials) {
    EXPECT_EQ(WallMaterialFromName(WallMaterialName(material)), material);
  }
  EXPECT_EQ(WallMaterialFromName("fiberglass"), WallMaterial::kFiberglass);
  const std::string message = InputErrorMessage([] { WallMaterialFromName("brass"); });
  EXPECT_NE(message.find("brass"), std::string::npos) << message;
  for (const char* valid : {"steel", "fiberglass", "concrete"}) {
    EXPECT_NE(message.find(valid), std::string::npos) << message;
  }
}

TEST(WallTexture, RejectsNegativeOptionsNamingTheKey) {
  WallTextureOptions options;
  options.texture_contrast = -1;
  EXPECT_NE(InputErrorMessage([&] { WallTexture texture(options); }).find("texture_contrast"),
            std::string::npos);
  options = WallTextureOptions();
  options.joint_spacing_m = std::nan("");
  EXPECT_NE(InputErrorMessage([&] { WallTexture texture(options); }).find("joint_spacing_m"),
            std::string::npos);
}

TEST(WallTexture, IsPeriodicAroundTheCircumference) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> unit(0, 1);
  for (const WallMaterial material : kMaterials) {
    const WallTexture texture(Options(material));
    for (const double radius : kRadii) {
      const double c = Circumference(radius);
      for (int i = 0; i < 300; ++i) {
        const double h = 5 * unit(rng);
        const double s = c * unit(rng);
        const double footprint = 5e-5 * std::pow(40.0, unit(rng));  // 0.05 .. 2 mm
        const float albedo = texture.Albedo(i % 3, h, s, c, footprint);
        EXPECT_NEAR(texture.Albedo(i % 3, h, s + c, c, footprint), albedo, 1e-6);
        EXPECT_NEAR(texture.Albedo(i % 3, h, s - 3 * c, c, footprint), albedo, 1e-6);
        EXPECT_NEAR(texture.Specularity(i % 3, h, s + 2 * c, c),
                    texture.Specularity(i % 3, h, s, c), 1e-6);
      }
    }
  }
}

TEST(WallTexture, IsContinuousAcrossTheSeamAtSZero) {
  // Across s = 0 neighbouring values differ no more than across any other s.
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> unit(0, 1);
  constexpr double kStep = 1e-7;
  for (const WallMaterial material : kMaterials) {
    const WallTexture texture(Options(material));
    for (const double radius : kRadii) {
      const double c = Circumference(radius);
      double max_seam = 0;
      double max_elsewhere = 0;
      for (int i = 0; i < 2000; ++i) {
        const double h = 5 * unit(rng);
        const double s = c * unit(rng);
        max_seam =
            std::max<double>(max_seam, std::abs(texture.Albedo(0, h, c - kStep / 2, c, 1e-4) -
                                                texture.Albedo(0, h, kStep / 2, c, 1e-4)));
        max_elsewhere =
            std::max<double>(max_elsewhere, std::abs(texture.Albedo(0, h, s + kStep / 2, c, 1e-4) -
                                                     texture.Albedo(0, h, s - kStep / 2, c, 1e-4)));
      }
      // The steepest features (paint edges, pit rims) change by < 0.01 per micrometre.
      EXPECT_LT(max_seam, 2e-3) << WallMaterialName(material) << " r " << radius;
      EXPECT_LT(max_elsewhere, 2e-3) << WallMaterialName(material) << " r " << radius;
    }
  }
}

TEST(WallTexture, HasNoCellSeams) {
  // Walking 1 micrometre at a time along h and around s, the value never jumps: every lattice
  // layer and hashed cell joins its neighbours continuously. A seam in any of the 8 octaves,
  // pits or scratches would show as a step of 0.01 or more.
  for (const WallMaterial material : kMaterials) {
    const WallTexture texture(Options(material));
    const double c = Circumference(0.2);
    double max_step = 0;
    float previous_h = texture.Albedo(0, 1.0, 0.3, c, 1e-4);
    float previous_s = texture.Albedo(0, 2.2, 0.0, c, 1e-4);
    for (int i = 1; i <= 100000; ++i) {
      const float along_h = texture.Albedo(0, 1.0 + i * 1e-6, 0.3, c, 1e-4);
      const float along_s = texture.Albedo(0, 2.2, i * 1e-6, c, 1e-4);
      max_step = std::max<double>(max_step, std::abs(along_h - previous_h));
      max_step = std::max<double>(max_step, std::abs(along_s - previous_s));
      previous_h = along_h;
      previous_s = along_s;
    }
    EXPECT_LT(max_step, 0.01) << WallMaterialName(material);
  }
}

TEST(WallTexture, ContrastZeroIsUniformAndContrastScalesTheDeviation) {
  const double c = Circumference(0.2);
  for (const WallMaterial material : kMaterials) {
    WallTextureOptions options = Options(material);
    options.texture_contrast = 0;
    const std::vector<double> flat = RandomAlbedos(WallTexture(options), c, 1e-4, 5000);
    for (const double v : flat) ASSERT_EQ(v, flat[0]);
    // The markings and joints are off too.
    const WallTexture flat_texture(options);
    const WallMarking marking = flat_texture.Marking(0, 0, c);
    EXPECT_EQ(flat_texture.Albedo(0, marking.text_h_begin_m + 0.01, marking.s_center_m, c, 1e-4),
              flat[0]);
    EXPECT_EQ(flat_texture.Albedo(0, 1.5, 0.1, c, 1e-4), flat[0]);

    std::vector<double> stddevs;
    for (const double contrast : {0.25, 0.5, 1.0, 2.0}) {
      options.texture_contrast = contrast;
      stddevs.push_back(StatsOf(RandomAlbedos(WallTexture(options), c, 1e-4, 20000)).stddev);
    }
    for (std::size_t i = 1; i < stddevs.size(); ++i) {
      EXPECT_GT(stddevs[i], 1.2 * stddevs[i - 1]) << WallMaterialName(material) << " " << i;
    }
    // Below saturation the deviation is linear in the contrast.
    EXPECT_NEAR(stddevs[1] / stddevs[2], 0.5, 0.05) << WallMaterialName(material);
  }
}

TEST(WallTexture, ValuesStayInTheUnitInterval) {
  const double c = Circumference(0.15);
  for (const WallMaterial material : kMaterials) {
    for (const double contrast : {1.0, 4.0}) {
      WallTextureOptions options = Options(material);
      options.texture_contrast = contrast;
      options.marking_spacing_m = 0.8;
      const WallTexture texture(options);
      std::mt19937 rng(3);
      std::uniform_real_distribution<double> unit(0, 1);
      for (int i = 0; i < 20000; ++i) {
        const double h = 6 * unit(rng);
        const double s = c * unit(rng);
        const WallSample sample = texture.Sample(i % 5, h, s, c, 5e-5 * std::pow(100.0, unit(rng)));
        ASSERT_GE(sample.albedo, 0.0f);
        ASSERT_LE(sample.albedo, 1.0f);
        ASSERT_GE(sample.specularity, 0.0f);
        ASSERT_LE(sample.specularity, 1.0f);
      }
    }
  }
}

TEST(WallTexture, IsDeterministicPerSeedAndDiffersBetweenSeedsAndSections) {
  const double c = Circumference(0.2);
  for (const WallMaterial material : kMaterials) {
    // Without joints and markings, which sit at the same h in every section.
    WallTextureOptions options = Options(material);
    options.joint_spacing_m = 0;
    options.marking_spacing_m = 0;
    options.seed = 42;
    const WallTexture first(options);
    const WallTexture second(options);
    options.seed = 43;
    const WallTexture other_seed(options);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> unit(0, 1);
    int same_as_other_seed = 0;
    int same_as_other_section = 0;
    std::vector<double> section0, section1;
    constexpr int kCount = 5000;
    for (int i = 0; i < kCount; ++i) {
      const double h = 6 * unit(rng);
      const double s = c * unit(rng);
      const float value = first.Albedo(0, h, s, c, 1e-4);
      const float again = second.Albedo(0, h, s, c, 1e-4);
      ASSERT_EQ(std::memcmp(&value, &again, sizeof(float)), 0);
      same_as_other_seed += other_seed.Albedo(0, h, s, c, 1e-4) == value;
      const float next_section = first.Albedo(1, h, s, c, 1e-4);
      same_as_other_section += next_section == value;
      section0.push_back(value);
      section1.push_back(next_section);
    }
    EXPECT_LT(same_as_other_seed, kCount / 100) << WallMaterialName(material);
    EXPECT_LT(same_as_other_section, kCount / 100) << WallMaterialName(material);
    // Not just shifted: the sections' patterns are uncorrelated.
    const Stats a = StatsOf(section0);
    const Stats b = StatsOf(section1);
    double covariance = 0;
    for (int i = 0; i < kCount; ++i) covariance += (section0[i] - a.mean) * (section1[i] - b.mean);
    EXPECT_LT(std::abs(covariance / kCount / (a.stddev * b.stddev)), 0.2)
        << WallMaterialName(material);
  }
}

TEST(WallTexture, GivesTheSameValuesInAnyOrderAndThread) {
  const WallTexture texture(Options(WallMaterial::kSteel));
  const double c = Circumference(0.07666);
  constexpr int kCount = 40000;
  std::vector<float> forward(kCount), threaded(kCount);
  const auto point = [&](int i, double* h, double* s) {
    *h = 1.4 + 1e-4 * (i % 200);
    *s = 0.2 + 1e-4 * (i / 200);
  };
  for (int i = 0; i < kCount; ++i) {
    double h, s;
    point(i, &h, &s);
    forward[i] = texture.Albedo(0, h, s, c, 1e-4);
  }
  // Two threads, each walking its half backwards.
  const auto work = [&](int begin, int end) {
    for (int i = end - 1; i >= begin; --i) {
      double h, s;
      point(i, &h, &s);
      threaded[i] = texture.Albedo(0, h, s, c, 1e-4);
    }
  };
  std::thread one(work, 0, kCount / 2);
  std::thread two(work, kCount / 2, kCount);
  one.join();
  two.join();
  EXPECT_EQ(std::memcmp(forward.data(), threaded.data(), kCount * sizeof(float)), 0);
}

TEST(WallTexture, ScalarAndAvx2PathsGiveIdenticalValues) {
  // Without AVX2 both textures take the scalar path and the test is trivially true.
  const double c = Circumference(0.19378);
  for (const WallMaterial material : kMaterials) {
    const WallTexture fast(Options(material));
    setenv("PIPESCOPE_WALL_TEXTURE_SCALAR", "1", 1);
    const WallTexture scalar(Options(material));
    unsetenv("PIPESCOPE_WALL_TEXTURE_SCALAR");
    std::mt19937 rng(10);
    std::uniform_real_distribution<double> unit(0, 1);
    for (int i = 0; i < 20000; ++i) {
      const double h = 6 * unit(rng);
      const double s = c * unit(rng);
      const double footprint = 2e-5 * std::pow(500.0, unit(rng));
      const WallSample a = fast.Sample(i % 4, h, s, c, footprint);
      const WallSample b = scalar.Sample(i % 4, h, s, c, footprint);
      ASSERT_EQ(std::memcmp(&a, &b, sizeof(WallSample)), 0)
          << WallMaterialName(material) << " h " << h << " s " << s;
    }
  }
}

TEST(WallTexture, FootprintRemovesFineDetail) {
  const double c = Circumference(0.2);
  for (const WallMaterial material : kMaterials) {
    WallTextureOptions options = Options(material);
    options.joint_spacing_m = 0;
    options.marking_spacing_m = 0;
    const WallTexture texture(options);
    // High-passed energy at a fixed 0.1 mm spacing falls as the footprint grows. (At a spacing
    // of one footprint it stays about level instead: wall texture has about as much contrast
    // per octave at every scale.)
    std::vector<double> energies;
    for (const double footprint : {2.5e-5, 1e-4, 4e-4, 1.6e-3, 6.4e-3}) {
      energies.push_back(DifferenceStddev(texture, c, footprint, 1e-4));
    }
    for (std::size_t i = 1; i < energies.size(); ++i) {
      EXPECT_LT(energies[i], 0.8 * energies[i - 1]) << WallMaterialName(material) << " " << i;
    }
    EXPECT_LT(energies.back(), 0.05 * energies.front()) << WallMaterialName(material);
    // Sampled at its own footprint the field is band-limited: neighbours are correlated, so the
    // difference over one footprint is well below that over two (white, aliased noise would give
    // a ratio of 1; a smooth field 0.5).
    for (const double footprint : {1e-4, 1e-3, 5e-3}) {
      const double ratio = DifferenceStddev(texture, c, footprint, footprint) /
                           DifferenceStddev(texture, c, footprint, 2 * footprint);
      EXPECT_LT(ratio, 0.8) << WallMaterialName(material) << " footprint " << footprint;
    }
    // And the detail does reach 0.1 mm where the footprint allows: at a 0.025 mm footprint the
    // field changes over 0.1 mm much more than a 0.4 mm footprint lets it.
    EXPECT_GT(energies[0], 2 * energies[2]) << WallMaterialName(material);
  }
}

TEST(WallTexture, JointsShowAtMultiplesOfTheSpacing) {
  const double c = Circumference(0.15);
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> unit(0, 1);
  for (const WallMaterial material : kMaterials) {
    WallTextureOptions options = Options(material);
    options.joint_spacing_m = 1.0;
    options.marking_spacing_m = 0;
    const WallTexture texture(options);
    options.joint_spacing_m = 0;
    const WallTexture jointless(options);
    // Weld bead +-4 mm; flange and segment gaps +-1 mm.
    const double half_band = material == WallMaterial::kSteel ? 0.004 : 0.001;
    std::vector<double> in_band, outside, jointless_band;
    for (int i = 0; i < 4000; ++i) {
      const double joint = 1.0 + (i % 4);
      const double s = c * unit(rng);
      const double h_in = joint + half_band * (2 * unit(rng) - 1);
      const double h_out = joint + (unit(rng) < 0.5 ? -1 : 1) * (0.06 + 0.3 * unit(rng));
      in_band.push_back(texture.Albedo(0, h_in, s, c, 2e-4));
      outside.push_back(texture.Albedo(0, h_out, s, c, 2e-4));
      jointless_band.push_back(jointless.Albedo(0, h_in, s, c, 2e-4));
    }
    const double band_mean = StatsOf(in_band).mean;
    const double outside_mean = StatsOf(outside).mean;
    if (material == WallMaterial::kSteel) {
      EXPECT_GT(band_mean, outside_mean + 0.04);  // bright bare weld metal
    } else {
      EXPECT_LT(band_mean, outside_mean - 0.2);  // dark gap
    }
    EXPECT_NEAR(StatsOf(jointless_band).mean, outside_mean, 0.03) << WallMaterialName(material);
  }
}

TEST(WallTexture, LetteringIsPaintedAtTheMarkings) {
  const double c = Circumference(0.2);
  for (const WallMaterial material : kMaterials) {
    const WallTexture texture(Options(material));
    const WallMarking marking = texture.Marking(0, 1, c);
    EXPECT_EQ(marking.text, "DN400 A-0001");
    EXPECT_NEAR(marking.text_h_begin_m, 2.0 * 1.3, 1e-9);
    EXPECT_GT(marking.text_h_end_m, marking.text_h_begin_m + 8 * marking.letter_height_m);
    // Variance in the text box against the same box half way round.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<double> text, elsewhere;
    for (int i = 0; i < 5000; ++i) {
      const double h =
          marking.text_h_begin_m + (marking.text_h_end_m - marking.text_h_begin_m) * unit(rng);
      const double ds = marking.letter_height_m * (unit(rng) - 0.5);
      text.push_back(texture.Albedo(0, h, marking.s_center_m + ds, c, 2e-4));
      elsewhere.push_back(texture.Albedo(0, h, marking.s_center_m + 0.5 * c + ds, c, 2e-4));
    }
    const double text_variance = std::pow(StatsOf(text).stddev, 2);
    const double elsewhere_variance = std::pow(StatsOf(elsewhere).stddev, 2);
    EXPECT_GT(text_variance, 2 * elsewhere_variance) << WallMaterialName(material);
    // The ring band before the text is painted all around.
    std::vector<double> ring, beside;
    for (int i = 0; i < 2000; ++i) {
      const double s = c * unit(rng);
      const double t = 0.2 + 0.6 * unit(rng);
      ring.push_back(texture.Albedo(
          0, marking.band_h_begin_m + t * (marking.band_h_end_m - marking.band_h_begin_m), s, c,
          2e-4));
      beside.push_back(
          texture.Albedo(0, marking.band_h_begin_m - 0.1 * unit(rng) - 0.01, s, c, 2e-4));
    }
    EXPECT_GT(std::abs(StatsOf(ring).mean - StatsOf(beside).mean), 0.15)
        << WallMaterialName(material);
  }
}

TEST(WallTexture, ShrinksLettersToFitShortMarkingSpacings) {
  WallTextureOptions options = Options(WallMaterial::kSteel);
  options.marking_spacing_m = 0.3;
  const WallTexture texture(options);
  const double c = Circumference(0.2);
  const WallMarking first = texture.Marking(0, 3, c);
  const WallMarking second = texture.Marking(0, 4, c);
  EXPECT_LT(first.letter_height_m, 0.05);  // 50 mm at the default spacing
  EXPECT_LT(first.arrow_h_end_m, second.band_h_begin_m);
  // Whole markings: the value is continuous everywhere along the text line.
  double max_step = 0;
  float previous = texture.Albedo(0, first.band_h_begin_m - 0.01, first.s_center_m, c, 1e-4);
  for (double h = first.band_h_begin_m - 0.01; h < second.arrow_h_end_m; h += 2e-6) {
    const float value = texture.Albedo(0, h, first.s_center_m, c, 1e-4);
    max_step = std::max<double>(max_step, std::abs(value - previous));
    previous = value;
  }
  EXPECT_LT(max_step, 0.05);
}

TEST(WallTexture, SpecularityFollowsTheMaterial) {
  const double c = Circumference(0.2);
  std::vector<double> means;
  for (const WallMaterial material : kMaterials) {
    const WallTexture texture(Options(material));
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> unit(0, 1);
    std::vector<double> values;
    for (int i = 0; i < 5000; ++i) {
      values.push_back(texture.Specularity(0, 6 * unit(rng), c * unit(rng), c));
    }
    means.push_back(StatsOf(values).mean);
  }
  EXPECT_GT(means[0], 0.15);  // steel, duller where rusty
  EXPECT_GT(means[1], 0.4);   // glossy fiberglass
  EXPECT_LT(means[2], 0.08);  // matte concrete
}

}  // namespace
}  // namespace pipescope

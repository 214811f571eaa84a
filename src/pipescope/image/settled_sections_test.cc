#include "pipescope/image/settled_sections.h"

#include <gtest/gtest.h>

#include <random>

namespace pipescope {
namespace {

using C = PipeViewClass;

// The sections of the whole sequence's filtered classes, key frame by key frame.
std::vector<KeyframeSection> WholeSequenceSections(const std::vector<C>& initial,
                                                   int min_cluster_size) {
  const std::vector<C> filtered = FilterPipeViewClasses(initial, min_cluster_size);
  std::vector<KeyframeSection> sections;
  const int n = static_cast<int>(filtered.size());
  for (int k = 0; k < n; ++k) {
    const bool first = k == 0 || filtered[k] != filtered[k - 1];
    KeyframeSection section;
    section.keyframe = k;
    section.section = first ? (k == 0 ? 0 : sections.back().section + 1) : sections.back().section;
    section.view_class = filtered[k];
    section.first_keyframe = first ? k : sections.back().first_keyframe;
    section.last_in_section = k + 1 == n || filtered[k + 1] != filtered[k];
    sections.push_back(section);
  }
  return sections;
}

void ExpectSame(const std::vector<KeyframeSection>& actual,
                const std::vector<KeyframeSection>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t k = 0; k < actual.size(); ++k) {
    EXPECT_EQ(actual[k].keyframe, expected[k].keyframe) << k;
    EXPECT_EQ(actual[k].section, expected[k].section) << k;
    EXPECT_EQ(actual[k].view_class, expected[k].view_class) << k;
    EXPECT_EQ(actual[k].first_keyframe, expected[k].first_keyframe) << k;
    EXPECT_EQ(actual[k].last_in_section, expected[k].last_in_section) << k;
  }
}

TEST(SettledSectionsTest, GivesOutTheWholeSequencesSectionsOnRandomClassSequences) {
  std::mt19937 generator(11);
  for (const double flip_probability : {0.01, 0.05, 0.2, 0.5}) {
    for (const int min_cluster_size : {1, 3, 10}) {
      for (int trial = 0; trial < 30; ++trial) {
        std::bernoulli_distribution flip(flip_probability);
        std::vector<C> initial;
        C current = trial % 2 ? C::kStraight : C::kTIntersection;
        for (int k = 0; k < 400; ++k) {
          if (flip(generator)) current = current == C::kStraight ? C::kTIntersection : C::kStraight;
          initial.push_back(current);
        }
        SettledSections settled(min_cluster_size);
        std::vector<KeyframeSection> given;
        for (const C view_class : initial) {
          const std::vector<KeyframeSection> now = settled.Add(view_class);
          given.insert(given.end(), now.begin(), now.end());
        }
        const std::vector<KeyframeSection> rest = settled.Finish();
        given.insert(given.end(), rest.begin(), rest.end());
        SCOPED_TRACE(::testing::Message() << "flip " << flip_probability << " min "
                                          << min_cluster_size << " trial " << trial);
        ExpectSame(given, WholeSequenceSections(initial, min_cluster_size));
      }
    }
  }
}

TEST(SettledSectionsTest, StraightKeyFramesAreGivenOutOneBehind) {
  SettledSections settled(10);
  for (int k = 0; k < 9; ++k) EXPECT_TRUE(settled.Add(C::kStraight).empty()) << k;
  // The tenth straight key frame settles the run: all but the newest are out.
  EXPECT_EQ(settled.Add(C::kStraight).size(), 9u);
  for (int k = 10; k < 50; ++k) {
    const std::vector<KeyframeSection> now = settled.Add(C::kStraight);
    ASSERT_EQ(now.size(), 1u);
    EXPECT_EQ(now[0].keyframe, k - 1);
    EXPECT_FALSE(now[0].last_in_section);
  }
  // A T flicker holds the key frames back until the straight run resumes for long enough.
  EXPECT_TRUE(settled.Add(C::kTIntersection).empty());
  for (int k = 0; k < 9; ++k) EXPECT_TRUE(settled.Add(C::kStraight).empty()) << k;
  EXPECT_EQ(settled.Add(C::kStraight).size(), 11u);
  const std::vector<KeyframeSection> rest = settled.Finish();
  ASSERT_EQ(rest.size(), 1u);
  EXPECT_EQ(rest[0].keyframe, 60);
  EXPECT_EQ(rest[0].section, 0);
  EXPECT_TRUE(rest[0].last_in_section);
}

}  // namespace
}  // namespace pipescope

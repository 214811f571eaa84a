#include "pipescope/io/point_cloud_ply.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"
#include "pipescope/util/testing.h"

namespace pipescope {
namespace {

TEST(WritePlyPoints, WritesAHeaderAndOneVertexALine) {
  const auto dir = MakeTestDirectory("ply");
  WritePlyPoints(dir / "points.ply", {{1.0, -2.5, 0.125}, {0.0, 0.0, 3.0}});
  std::ifstream in(dir / "points.ply");
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  EXPECT_EQ(s.rfind("ply\nformat ascii 1.0\n", 0), 0u);
  EXPECT_NE(s.find("element vertex 2\n"), std::string::npos);
  EXPECT_NE(s.find("end_header\n1 -2.5 0.125\n0 0 3\n"), std::string::npos);
}

TEST(WritePlyPoints, WritesColoursAfterThePositions) {
  const auto dir = MakeTestDirectory("ply_colour");
  WritePlyPoints(dir / "points.ply", {{1.0, 2.0, 3.0}}, {PlyColour{220, 40, 7}}, "sections");
  std::ifstream in(dir / "points.ply");
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  EXPECT_NE(s.find("comment sections\n"), std::string::npos);
  EXPECT_NE(s.find("property uchar blue\nend_header\n1 2 3 220 40 7\n"), std::string::npos);
  EXPECT_THROW(WritePlyPoints(dir / "bad.ply", {{1.0, 2.0, 3.0}}, {PlyColour{}, PlyColour{}}),
               std::invalid_argument);
}

TEST(ReadPlyPoints, ReadsBackWhatWasWritten) {
  const auto dir = MakeTestDirectory("ply_read");
  const std::vector<Eigen::Vector3d> points = {{1.0, -2.5, 0.125}, {0.1, 0.2, 3.0}};
  WritePlyPoints(dir / "plain.ply", points);
  PlyPoints plain = ReadPlyPoints(dir / "plain.ply");
  ASSERT_EQ(plain.points.size(), 2u);
  EXPECT_TRUE(plain.points[1].isApprox(points[1], 1e-9));
  EXPECT_TRUE(plain.colours.empty());
  WritePlyPoints(dir / "colour.ply", points, {PlyColour{1, 2, 3}, PlyColour{250, 0, 9}});
  PlyPoints coloured = ReadPlyPoints(dir / "colour.ply");
  ASSERT_EQ(coloured.colours.size(), 2u);
  EXPECT_EQ(coloured.colours[1], (PlyColour{250, 0, 9}));
}

TEST(ReadPlyPoints, RefusesOtherFormatsNamingTheFile) {
  const auto dir = MakeTestDirectory("ply_bad");
  WriteTextFileAtomically(dir / "binary.ply",
                          "ply\nformat binary_little_endian 1.0\nelement vertex 1\nend_header\n");
  EXPECT_NE(InputErrorMessage([&] { ReadPlyPoints(dir / "binary.ply"); }).find("binary.ply"),
            std::string::npos);
  WriteTextFileAtomically(dir / "short.ply",
                          "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                          "property float y\nproperty float z\nend_header\n1 2 3\n");
  EXPECT_NE(InputErrorMessage([&] { ReadPlyPoints(dir / "short.ply"); }).find("ends after 1"),
            std::string::npos);
}

}  // namespace
}  // namespace pipescope

#include "pipescope/io/point_cloud_ply.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

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

}  // namespace
}  // namespace pipescope

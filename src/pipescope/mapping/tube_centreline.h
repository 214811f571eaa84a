#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "pipescope/geometry/tube_section.h"

namespace pipescope {

// The centreline of a chain of cylinder sections (004: a tube as straight sections): a polyline
// from the first camera's foot on the first axis, through the junctions of consecutive sections,
// to the last camera's foot on the last axis, with the radius along it and a phi = 0 direction
// carried along by parallel transport (so clock angles stay continuous through a bend).
struct TubeCentreline {
  std::vector<Eigen::Vector3d> points;   // vertices
  std::vector<double> arc_m;             // arc length of each vertex from the first
  std::vector<double> radius_m;          // radius of the section leaving each vertex
  std::vector<int> section;              // index of the section leaving each vertex
  std::vector<Eigen::Vector3d> normals;  // phi = 0 direction of each segment (vertices - 1)
  // The sections' own tangents at each vertex, arriving and leaving: they differ where
  // consecutive sections meet at an angle, and both differ from a segment's direction where a
  // section's start lies off the end of the one before (the filter moves starts across the
  // axis), which the short segment between them bridges.
  std::vector<Eigen::Vector3d> tangents_in, tangents_out;

  double Length() const { return arc_m.empty() ? 0.0 : arc_m.back(); }
};

// Builds the centreline. `phi_zero`: the direction of phi = 0 at the start (projected across the
// first axis; the pipe's up, say).
TubeCentreline BuildTubeCentreline(const std::vector<TubeSection>& sections,
                                   const Eigen::Vector3d& first_position,
                                   const Eigen::Vector3d& last_position,
                                   const Eigen::Vector3d& phi_zero);

// Arc length of the point's foot on the nearest segment; before the start and past the end the
// end segments are extended.
double ArcLengthAlong(const TubeCentreline& centreline, const Eigen::Vector3d& point);

// The centreline frame at arc length `arc_m` (extended past the ends along the end segments).
// The point runs along the polyline; the tangent is the sections' (turning along a bending
// section's chords as along its arc), and within a radius of a vertex where the sections meet at
// an angle it turns to the angle's bisector, so that the rings of wall across the tube (the
// mosaic's columns) never fold back over each other there.
struct CentrelineFrame {
  Eigen::Vector3d point;
  Eigen::Vector3d tangent;
  Eigen::Vector3d normal;    // phi = 0
  Eigen::Vector3d binormal;  // phi = 90 deg: tangent x normal
  double radius_m = 0.0;
};
CentrelineFrame CentrelineFrameAt(const TubeCentreline& centreline, double arc_m);

// centreline.csv: arc_m, x_m, y_m, z_m, radius_m, section; a header line, one vertex a line.
void WriteCentrelineCsv(const std::filesystem::path& path, const TubeCentreline& centreline);
// centreline.ply (ASCII): the vertices with a radius property and the edges between them, which
// CAD and GIS tools read as a polyline.
void WriteCentrelinePly(const std::filesystem::path& path, const TubeCentreline& centreline);

}  // namespace pipescope

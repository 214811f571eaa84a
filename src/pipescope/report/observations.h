#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "pipescope/report/wall_location.h"

namespace pipescope {

// What an inspector saw in a frame: a point (u, v) or a box, with a code (e.g. a PACP defect
// code) and a remark. `locate --observations` reads them, places each on the wall and writes
// observations_located.csv (docs/formats.md).
struct Observation {
  int frame = 0;
  bool box = false;
  double u_min = 0, v_min = 0, u_max = 0, v_max = 0;  // a point has min == max
  std::string code;
  std::string remark;
  double u() const { return 0.5 * (u_min + u_max); }
  double v() const { return 0.5 * (v_min + v_max); }
};

struct LocatedObservation {
  Observation observation;
  bool located = false;
  std::string why_not;  // when not located: no pose for the frame, or no ray to the wall
  WallLocation centre;
  double distance_from_m = 0, distance_to_m = 0;  // a box's extent; the centre's for a point
  double clock_from_deg = 0, clock_to_deg = 0;    // read clockwise (ClockSpan)
  std::string clock_from, clock_to;               // as read back from the file ("h:mm")
};

// Reads obs.csv: a header naming the columns, `frame` and either `u,v` or
// `u_min,v_min,u_max,v_max`, optionally `code` and `remark` (any order; quoted fields allowed).
// Throws InputError naming the file, line and column at fault.
std::vector<Observation> ReadObservationsCsv(const std::filesystem::path& path);

// observations_located.csv: the observation's columns, then distance_m, distance_from_m,
// distance_to_m, clock, clock_angle_deg, clock_from, clock_to, section, x_m, y_m, z_m, note.
void WriteLocatedObservationsCsv(const std::filesystem::path& path,
                                 const std::vector<LocatedObservation>& located);
std::vector<LocatedObservation> ReadLocatedObservationsCsv(const std::filesystem::path& path);

}  // namespace pipescope

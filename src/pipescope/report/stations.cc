#include "pipescope/report/stations.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "pipescope/geometry/clock_position.h"
#include "pipescope/io/image_source.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

// The crawler's first move that counts for the survey direction: shorter moves are jitter.
constexpr double kFirstMoveM = 0.01;

// +Z or -Z: the direction along the axis in which the camera first moved more than kFirstMoveM,
// or (never that far) the sign of its farthest excursion.
Eigen::Vector3d StraightSurveyDirection(const Trajectory& trajectory) {
  double farthest = 0.0;
  for (const StampedPose& pose : trajectory) {
    const double along = pose.position.z() - trajectory.front().position.z();
    if (std::abs(along) > kFirstMoveM) return Eigen::Vector3d(0.0, 0.0, along > 0.0 ? 1.0 : -1.0);
    if (std::abs(along) > std::abs(farthest)) farthest = along;
  }
  return Eigen::Vector3d(0.0, 0.0, farthest < 0.0 ? -1.0 : 1.0);
}

// The position at path length `s` along the polyline (lengths `arc`), clamped to its ends.
Eigen::Vector3d PositionAtArcLength(const Trajectory& trajectory, const std::vector<double>& arc,
                                    double s) {
  if (s <= arc.front()) return trajectory.front().position;
  if (s >= arc.back()) return trajectory.back().position;
  const std::size_t j = std::upper_bound(arc.begin(), arc.end(), s) - arc.begin();
  const double span = arc[j] - arc[j - 1];
  const double w = span > 0.0 ? (s - arc[j - 1]) / span : 0.0;
  return (1.0 - w) * trajectory[j - 1].position + w * trajectory[j].position;
}

// Each pose's local direction of travel: the chord of the path over `window_m` either side.
std::vector<Eigen::Vector3d> PathDirections(const Trajectory& trajectory, double window_m) {
  std::vector<double> arc(trajectory.size(), 0.0);
  for (std::size_t i = 1; i < trajectory.size(); ++i) {
    arc[i] = arc[i - 1] + (trajectory[i].position - trajectory[i - 1].position).norm();
  }
  std::vector<Eigen::Vector3d> directions(trajectory.size(), Eigen::Vector3d::UnitZ());
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    const Eigen::Vector3d chord = PositionAtArcLength(trajectory, arc, arc[i] + window_m) -
                                  PositionAtArcLength(trajectory, arc, arc[i] - window_m);
    // A crawler standing still has no direction of its own: it keeps the last one.
    directions[i] = chord.norm() > 1e-9 ? chord.normalized() : previous;
    previous = directions[i];
  }
  // Leading frames before the first move take the first direction there is.
  const auto first = std::find_if(directions.begin(), directions.end(),
                                  [](const Eigen::Vector3d& d) { return d.norm() > 0.5; });
  const Eigen::Vector3d fill = first == directions.end() ? Eigen::Vector3d::UnitZ() : *first;
  for (Eigen::Vector3d& d : directions) {
    if (d.norm() < 0.5) d = fill;
  }
  return directions;
}

}  // namespace

std::vector<Station> ComputeStations(const Trajectory& trajectory, const std::vector<int>& frames,
                                     const StationOptions& options) {
  if (frames.size() != trajectory.size()) {
    throw std::invalid_argument("ComputeStations: one frame index per pose");
  }
  std::vector<Station> stations(trajectory.size());
  if (trajectory.empty()) return stations;
  std::vector<Eigen::Vector3d> travel;
  if (options.line == SurveyLine::kStraightAxis) {
    travel.assign(trajectory.size(), StraightSurveyDirection(trajectory));
  } else {
    travel = PathDirections(trajectory, options.path_window_m);
  }
  for (std::size_t i = 0; i < trajectory.size(); ++i) {
    Station& station = stations[i];
    station.frame = frames[i];
    station.timestamp = trajectory[i].timestamp;
    station.position = trajectory[i].position;
    station.travel = travel[i];
    const Eigen::Vector3d step =
        i == 0 ? Eigen::Vector3d::Zero()
               : Eigen::Vector3d(trajectory[i].position - trajectory[i - 1].position);
    if (options.line == SurveyLine::kStraightAxis) {
      station.distance_m = (trajectory[i].position - trajectory.front().position).dot(travel[i]);
    } else if (i > 0) {
      const Eigen::Vector3d mean_direction = (travel[i] + travel[i - 1]).normalized();
      station.distance_m = stations[i - 1].distance_m + step.dot(mean_direction);
    }
    station.roll_clock_deg = ClockAngleDeg(CameraUpright(trajectory[i].rotation.toRotationMatrix()),
                                           travel[i], options.up)
                                 .value_or(std::numeric_limits<double>::quiet_NaN());
  }
  // Speed along the pipe: central differences, one-sided at the ends.
  for (std::size_t i = 0; i < stations.size() && stations.size() > 1; ++i) {
    const std::size_t a = i == 0 ? 0 : i - 1;
    const std::size_t b = std::min(i + 1, stations.size() - 1);
    const double dt = stations[b].timestamp - stations[a].timestamp;
    stations[i].speed_m_s = dt > 0.0 ? (stations[b].distance_m - stations[a].distance_m) / dt : 0.0;
  }
  return stations;
}

std::vector<int> FrameIndicesByTime(const Trajectory& trajectory, const DatasetManifest& manifest) {
  std::vector<int> frames(trajectory.size(), -1);
  if (!manifest.timestamps_path.empty()) {
    const std::vector<double> times = ReadTimestampsFile(manifest.timestamps_path);
    for (std::size_t i = 0; i < trajectory.size(); ++i) {
      const double t = trajectory[i].timestamp;
      const auto above = std::lower_bound(times.begin(), times.end(), t);
      std::size_t best = times.size();
      if (above != times.end()) best = above - times.begin();
      if (above != times.begin() && (best == times.size() || t - *(above - 1) < times[best] - t)) {
        best = (above - times.begin()) - 1;
      }
      if (best == times.size()) continue;
      // Within a third of the gap to the neighbouring frame.
      const double gap = times.size() > 1
                             ? (best + 1 < times.size() ? times[best + 1] - times[best]
                                                        : times[best] - times[best - 1])
                             : 1.0;
      if (std::abs(times[best] - t) <= gap / 3.0) frames[i] = static_cast<int>(best);
    }
  } else if (manifest.fps > 0.0) {
    for (std::size_t i = 0; i < trajectory.size(); ++i) {
      const double position = trajectory[i].timestamp * manifest.fps;
      const double nearest = std::round(position);
      if (std::abs(position - nearest) <= 1.0 / 3.0 && nearest >= 0.0) {
        frames[i] = static_cast<int>(nearest);
      }
    }
  }
  return frames;
}

void WriteStationsCsv(const std::filesystem::path& path, const std::vector<Station>& stations) {
  std::ostringstream csv;
  csv.precision(10);
  csv << "frame,timestamp_s,distance_m,roll_clock_deg,roll_clock,speed_m_s\n";
  for (const Station& station : stations) {
    csv << station.frame << ',' << station.timestamp << ',' << station.distance_m << ',';
    if (std::isfinite(station.roll_clock_deg)) {
      csv << station.roll_clock_deg << ',' << ClockString(station.roll_clock_deg);
    } else {
      csv << ',';
    }
    csv << ',' << station.speed_m_s << '\n';
  }
  WriteTextFileAtomically(path, csv.str());
}

std::vector<Station> ReadStationsCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read " + path.string());
  std::string line;
  std::vector<Station> stations;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line_number == 1 || line.empty()) continue;  // the header
    std::vector<std::string> fields;
    std::istringstream row(line);
    for (std::string field; std::getline(row, field, ',');) fields.push_back(field);
    Station station;
    try {
      if (fields.size() != 6) throw std::invalid_argument("columns");
      station.frame = std::stoi(fields[0]);
      station.timestamp = std::stod(fields[1]);
      station.distance_m = std::stod(fields[2]);
      station.roll_clock_deg =
          fields[3].empty() ? std::numeric_limits<double>::quiet_NaN() : std::stod(fields[3]);
      station.speed_m_s = std::stod(fields[5]);
    } catch (const std::exception&) {
      throw InputError(path.string() + ":" + std::to_string(line_number) +
                       ": expected frame,timestamp_s,distance_m,roll_clock_deg,roll_clock,"
                       "speed_m_s");
    }
    stations.push_back(station);
  }
  return stations;
}

const char* SurveyLineName(SurveyLine line) {
  return line == SurveyLine::kStraightAxis ? "straight-axis" : "travelled-path";
}

SurveyLine ParseSurveyLine(const std::string& name, const std::string& context) {
  if (name == "straight-axis") return SurveyLine::kStraightAxis;
  if (name == "travelled-path") return SurveyLine::kTravelledPath;
  throw InputError(context + ": unknown survey line '" + name +
                   "' (straight-axis or travelled-path)");
}

}  // namespace pipescope

#include "pipescope/report/observations.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "pipescope/geometry/clock_position.h"
#include "pipescope/io/csv_fields.h"
#include "pipescope/util/atomic_file.h"
#include "pipescope/util/error.h"

namespace pipescope {
namespace {

constexpr char kLocatedHeader[] =
    "frame,u,v,u_min,v_min,u_max,v_max,code,remark,distance_m,distance_from_m,distance_to_m,"
    "clock,clock_angle_deg,clock_from,clock_to,section,x_m,y_m,z_m,note";

// A CSV file as rows of named fields; InputError naming the file for a ragged or unreadable one.
std::vector<std::map<std::string, std::string>> ReadNamedRows(const std::filesystem::path& path,
                                                              std::vector<int>* line_numbers) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read " + path.string());
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line == "\r") continue;
    std::vector<std::string> fields;
    try {
      fields = SplitCsvLine(line);
    } catch (const std::invalid_argument&) {
      throw InputError(path.string() + ":" + std::to_string(number) + ": unclosed quote");
    }
    if (header.empty()) {
      header = fields;
      continue;
    }
    if (fields.size() != header.size()) {
      throw InputError(path.string() + ":" + std::to_string(number) + ": " +
                       std::to_string(fields.size()) + " fields, the header has " +
                       std::to_string(header.size()));
    }
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < header.size(); ++i) row[header[i]] = fields[i];
    rows.push_back(std::move(row));
    line_numbers->push_back(number);
  }
  if (header.empty()) throw InputError(path.string() + ": empty file (expected a header line)");
  return rows;
}

double Number(const std::map<std::string, std::string>& row, const std::string& column,
              const std::filesystem::path& path, int line) {
  const auto found = row.find(column);
  if (found == row.end()) {
    throw InputError(path.string() + ": no column '" + column + "'");
  }
  try {
    std::size_t used = 0;
    const double value = std::stod(found->second, &used);
    if (used == found->second.size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  throw InputError(path.string() + ":" + std::to_string(line) + ": column '" + column +
                   "' must be a finite number, not '" + found->second + "'");
}

std::string Text(const std::map<std::string, std::string>& row, const std::string& column) {
  const auto found = row.find(column);
  return found == row.end() ? "" : found->second;
}

std::string Format(double value) {
  if (!std::isfinite(value)) return "";
  std::ostringstream out;
  out.precision(9);
  out << value;
  return out.str();
}

}  // namespace

std::vector<Observation> ReadObservationsCsv(const std::filesystem::path& path) {
  std::vector<int> lines;
  const auto rows = ReadNamedRows(path, &lines);
  std::vector<Observation> observations;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    Observation observation;
    const double frame = Number(row, "frame", path, lines[i]);
    if (frame < 0 || frame != std::floor(frame)) {
      throw InputError(path.string() + ":" + std::to_string(lines[i]) +
                       ": column 'frame' must be a frame number (0, 1, 2, ...)");
    }
    observation.frame = static_cast<int>(frame);
    observation.box = row.count("u_min") > 0;
    if (observation.box) {
      observation.u_min = Number(row, "u_min", path, lines[i]);
      observation.v_min = Number(row, "v_min", path, lines[i]);
      observation.u_max = Number(row, "u_max", path, lines[i]);
      observation.v_max = Number(row, "v_max", path, lines[i]);
      if (observation.u_max < observation.u_min || observation.v_max < observation.v_min) {
        throw InputError(path.string() + ":" + std::to_string(lines[i]) +
                         ": the box's u_max, v_max must not be below its u_min, v_min");
      }
    } else {
      observation.u_min = observation.u_max = Number(row, "u", path, lines[i]);
      observation.v_min = observation.v_max = Number(row, "v", path, lines[i]);
    }
    observation.code = Text(row, "code");
    observation.remark = Text(row, "remark");
    observations.push_back(observation);
  }
  return observations;
}

void WriteLocatedObservationsCsv(const std::filesystem::path& path,
                                 const std::vector<LocatedObservation>& located) {
  std::string csv = std::string(kLocatedHeader) + "\n";
  for (const LocatedObservation& entry : located) {
    const Observation& o = entry.observation;
    const bool clocked = entry.located && std::isfinite(entry.centre.clock_angle_deg);
    const std::vector<std::string> fields = {
        std::to_string(o.frame),
        Format(o.u()),
        Format(o.v()),
        Format(o.u_min),
        Format(o.v_min),
        Format(o.u_max),
        Format(o.v_max),
        CsvField(o.code),
        CsvField(o.remark),
        entry.located ? Format(entry.centre.distance_m) : "",
        entry.located ? Format(entry.distance_from_m) : "",
        entry.located ? Format(entry.distance_to_m) : "",
        clocked ? entry.centre.clock : "",
        clocked ? Format(entry.centre.clock_angle_deg) : "",
        clocked ? ClockString(entry.clock_from_deg) : "",
        clocked ? ClockString(entry.clock_to_deg) : "",
        entry.located ? std::to_string(entry.centre.section) : "",
        entry.located ? Format(entry.centre.point.x()) : "",
        entry.located ? Format(entry.centre.point.y()) : "",
        entry.located ? Format(entry.centre.point.z()) : "",
        CsvField(entry.why_not)};
    for (std::size_t i = 0; i < fields.size(); ++i) csv += (i ? "," : "") + fields[i];
    csv += "\n";
  }
  WriteTextFileAtomically(path, csv);
}

std::vector<LocatedObservation> ReadLocatedObservationsCsv(const std::filesystem::path& path) {
  std::vector<int> lines;
  const auto rows = ReadNamedRows(path, &lines);
  std::vector<LocatedObservation> located;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    const auto optional_number = [&](const std::string& column) {
      return Text(row, column).empty() ? nan : Number(row, column, path, lines[i]);
    };
    LocatedObservation entry;
    Observation& o = entry.observation;
    o.frame = static_cast<int>(Number(row, "frame", path, lines[i]));
    o.u_min = Number(row, "u_min", path, lines[i]);
    o.v_min = Number(row, "v_min", path, lines[i]);
    o.u_max = Number(row, "u_max", path, lines[i]);
    o.v_max = Number(row, "v_max", path, lines[i]);
    o.box = o.u_min != o.u_max || o.v_min != o.v_max;
    o.code = Text(row, "code");
    o.remark = Text(row, "remark");
    entry.located = !Text(row, "distance_m").empty();
    entry.why_not = Text(row, "note");
    entry.centre.distance_m = optional_number("distance_m");
    entry.distance_from_m = optional_number("distance_from_m");
    entry.distance_to_m = optional_number("distance_to_m");
    entry.centre.clock = Text(row, "clock");
    entry.centre.clock_angle_deg = optional_number("clock_angle_deg");
    entry.clock_from = Text(row, "clock_from");
    entry.clock_to = Text(row, "clock_to");
    entry.centre.section = entry.located ? static_cast<int>(optional_number("section")) : 0;
    entry.centre.point = {optional_number("x_m"), optional_number("y_m"), optional_number("z_m")};
    located.push_back(entry);
  }
  return located;
}

}  // namespace pipescope

#include "pipescope/eval/metrics_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>
#include <vector>

namespace pipescope {
namespace {

nlohmann::json OptionalToJson(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

std::string Format(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

std::string FormatOptional(const char* format, const std::optional<double>& value,
                           const std::string& absent) {
  return value ? Format(format, *value) : absent;
}

std::string PadRight(const std::string& text, std::size_t width) {
  return text + std::string(width > text.size() ? width - text.size() : 0, ' ');
}

std::string PadLeft(const std::string& text, std::size_t width) {
  return std::string(width > text.size() ? width - text.size() : 0, ' ') + text;
}

// `cells`' rows as lines, each column as wide as its widest cell, the first `left_aligned`
// columns (names) left-aligned and the rest (numbers) right-aligned.
std::string AlignedRows(const std::vector<std::vector<std::string>>& cells,
                        std::size_t left_aligned) {
  std::vector<std::size_t> widths;
  for (const auto& row : cells) {
    widths.resize(std::max(widths.size(), row.size()), 0);
    for (std::size_t c = 0; c < row.size(); ++c) widths[c] = std::max(widths[c], row[c].size());
  }
  std::string text;
  for (const auto& row : cells) {
    std::string line;
    for (std::size_t c = 0; c < row.size(); ++c) {
      line += "  " + (c < left_aligned ? PadRight(row[c], widths[c]) : PadLeft(row[c], widths[c]));
    }
    text += line + "\n";
  }
  return text;
}

// The straight pieces' correlations: their median and the worst (lowest); NaN without any.
std::pair<double, double> StraightMedianAndWorst(const std::vector<DensePieceAgreement>& pieces) {
  std::vector<double> values;
  for (const DensePieceAgreement& piece : pieces) {
    if (piece.part == "straight" && !std::isnan(piece.agreement.correlation)) {
      values.push_back(piece.agreement.correlation);
    }
  }
  if (values.empty()) {
    return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  }
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  const double median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  return {median, values.front()};
}

nlohmann::json NumberOrNull(double value) {
  return std::isnan(value) ? nlohmann::json(nullptr) : nlohmann::json(value);
}

}  // namespace

nlohmann::json MetricsToJson(const Metrics& metrics) {
  nlohmann::json json;
  json["frames_gt"] = metrics.frames_gt;
  json["frames_est"] = metrics.frames_est;
  json["frames_matched"] = metrics.frames_matched;
  json["distance_gt_m"] = metrics.distance_gt_m;
  json["distance_est_m"] = metrics.distance_est_m;
  json["distance_error_pct"] = OptionalToJson(metrics.distance_error_pct);
  json["forward_error_pct"] = OptionalToJson(metrics.forward_error_pct);
  json["reverse_error_pct"] = OptionalToJson(metrics.reverse_error_pct);
  json["return_error_pct"] = OptionalToJson(metrics.return_error_pct);
  json["path_gt_m"] = metrics.path_gt_m;
  json["path_est_m"] = metrics.path_est_m;
  json["path_error_pct"] = OptionalToJson(metrics.path_error_pct);
  json["ate_rmse_m"] = metrics.ate_rmse_m;
  json["ate_max_m"] = metrics.ate_max_m;
  json["rot_rmse_deg"] = metrics.rot_rmse_deg;
  json["rot_max_deg"] = metrics.rot_max_deg;
  json["alignment"] = AlignmentName(metrics.alignment);
  json["scale"] = OptionalToJson(metrics.scale);
  json["rpe_1m_pct"] = OptionalToJson(metrics.rpe_1m_pct);
  json["junction_distances"] = nullptr;
  if (metrics.junction_distances) {
    json["junction_distances"] = nlohmann::json::array();
    for (const JunctionDistance& distance : *metrics.junction_distances) {
      json["junction_distances"].push_back({{"from", distance.from},
                                            {"to", distance.to},
                                            {"gt_m", distance.gt_m},
                                            {"est_m", distance.est_m},
                                            {"error_m", distance.error_m},
                                            {"error_pct", distance.error_pct}});
    }
  }
  json["dense_map"] = nullptr;
  if (metrics.dense_map) {
    nlohmann::json pieces = nlohmann::json::array();
    for (const DensePieceAgreement& piece : *metrics.dense_map) {
      const DenseMapAgreement& a = piece.agreement;
      pieces.push_back({{"piece", piece.piece},
                        {"section", piece.section},
                        {"part", piece.part},
                        {"keyframes_used", piece.keyframes_used},
                        {"correlation", NumberOrNull(a.correlation)},
                        {"cells", a.cells},
                        {"shift_rows", a.shift_rows},
                        {"shift_cols", a.shift_cols},
                        {"shift_at_limit", a.shift_at_limit}});
    }
    const auto [median, worst] = StraightMedianAndWorst(*metrics.dense_map);
    json["dense_map"] = {{"pieces", pieces},
                         {"straight_median_correlation", NumberOrNull(median)},
                         {"straight_worst_correlation", NumberOrNull(worst)}};
  }
  return json;
}

std::string MetricsToTable(const Metrics& metrics) {
  const std::string kNotApplicable = "-";
  std::vector<std::pair<std::string, std::string>> rows = {
      {"frames_gt", std::to_string(metrics.frames_gt)},
      {"frames_est", std::to_string(metrics.frames_est)},
      {"frames_matched", std::to_string(metrics.frames_matched)},
      {"run", metrics.out_and_back ? "out-and-back" : "one-way"},
      {"distance_gt_m", Format("%.4f m", metrics.distance_gt_m)},
      {"distance_est_m", Format("%.4f m", metrics.distance_est_m)},
      {"distance_error_pct", FormatOptional("%.3f %%", metrics.distance_error_pct, kNotApplicable)},
  };
  if (metrics.out_and_back) {
    rows.push_back({"forward_error_pct",
                    FormatOptional("%.3f %%", metrics.forward_error_pct, kNotApplicable)});
    rows.push_back({"reverse_error_pct",
                    FormatOptional("%.3f %%", metrics.reverse_error_pct, kNotApplicable)});
    rows.push_back(
        {"return_error_pct", FormatOptional("%.3f %%", metrics.return_error_pct, kNotApplicable)});
  }
  rows.push_back({"path_gt_m", Format("%.4f m", metrics.path_gt_m)});
  rows.push_back({"path_est_m", Format("%.4f m", metrics.path_est_m)});
  rows.push_back(
      {"path_error_pct", FormatOptional("%.3f %%", metrics.path_error_pct, kNotApplicable)});
  rows.push_back({"alignment", AlignmentName(metrics.alignment)});
  if (metrics.scale) rows.push_back({"scale", Format("%.6f", *metrics.scale)});
  rows.push_back({"ate_rmse_m", Format("%.4f m", metrics.ate_rmse_m)});
  rows.push_back({"ate_max_m", Format("%.4f m", metrics.ate_max_m)});
  rows.push_back({"rot_rmse_deg", Format("%.2f deg", metrics.rot_rmse_deg)});
  rows.push_back({"rot_max_deg", Format("%.2f deg", metrics.rot_max_deg)});
  rows.push_back({"rpe_1m_pct",
                  FormatOptional("%.3f %%", metrics.rpe_1m_pct, "- (run shorter than a segment)")});

  std::size_t label_width = 0;
  for (const auto& row : rows) label_width = std::max(label_width, row.first.size());
  std::string table;
  for (const auto& [label, value] : rows) table += PadRight(label, label_width + 2) + value + "\n";

  if (metrics.junction_distances) {
    const std::vector<std::string> header = {"from", "to", "gt_m", "est_m", "error_m", "error_pct"};
    std::vector<std::vector<std::string>> cells = {header};
    for (const JunctionDistance& distance : *metrics.junction_distances) {
      cells.push_back({distance.from, distance.to, Format("%.4f", distance.gt_m),
                       Format("%.4f", distance.est_m), Format("%+.4f", distance.error_m),
                       Format("%.3f", distance.error_pct)});
    }
    table += "junction_distances";
    table += metrics.junction_distances->empty() ? ": none\n" : "\n";
    if (!metrics.junction_distances->empty()) table += AlignedRows(cells, 2);
  }
  if (metrics.dense_map) {
    std::vector<std::vector<std::string>> cells = {
        {"piece", "part", "section", "key_frames", "correlation", "cells", "shift"}};
    for (const DensePieceAgreement& piece : *metrics.dense_map) {
      const DenseMapAgreement& a = piece.agreement;
      cells.push_back({std::to_string(piece.piece), piece.part, std::to_string(piece.section),
                       std::to_string(piece.keyframes_used),
                       std::isnan(a.correlation) ? "-" : Format("%.3f", a.correlation),
                       std::to_string(a.cells),
                       std::to_string(a.shift_rows) + "," + std::to_string(a.shift_cols) +
                           (a.shift_at_limit ? " (at the search's edge)" : "")});
    }
    const auto [median, worst] = StraightMedianAndWorst(*metrics.dense_map);
    table += "dense_map (correlation with the simulated albedo after a high-pass)";
    table += metrics.dense_map->empty() ? ": no pieces\n" : "\n";
    if (!metrics.dense_map->empty()) table += AlignedRows(cells, 2);
    if (!std::isnan(median)) {
      table += "  straight pieces: median " + Format("%.3f", median) + ", worst " +
               Format("%.3f", worst) + "\n";
    }
  }
  return table;
}

}  // namespace pipescope

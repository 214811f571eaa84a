#include "pipescope/eval/metrics_report.h"

#include <gtest/gtest.h>

#include <set>

namespace pipescope {
namespace {

const std::set<std::string> kMetricsKeys = {
    "frames_gt",         "frames_est",         "frames_matched",
    "distance_gt_m",     "distance_est_m",     "distance_error_pct",
    "forward_error_pct", "reverse_error_pct",  "return_error_pct",
    "ate_rmse_m",        "ate_max_m",          "rot_rmse_deg",
    "rot_max_deg",       "alignment",          "scale",
    "rpe_1m_pct",        "junction_distances", "path_gt_m",
    "path_est_m",        "path_error_pct",     "dense_map"};

std::set<std::string> Keys(const nlohmann::json& json) {
  std::set<std::string> keys;
  for (const auto& item : json.items()) keys.insert(item.key());
  return keys;
}

Metrics OneWay() {
  Metrics metrics;
  metrics.frames_gt = 100;
  metrics.frames_est = 98;
  metrics.frames_matched = 97;
  metrics.distance_gt_m = 5.0;
  metrics.distance_est_m = 5.05;
  metrics.distance_error_pct = 1.0;
  metrics.ate_rmse_m = 0.012;
  metrics.ate_max_m = 0.03;
  metrics.rpe_1m_pct = 0.75;
  return metrics;
}

TEST(MetricsReport, OneWayJsonHasAllKeysWithNullsWhereNotApplicable) {
  const nlohmann::json json = MetricsToJson(OneWay());
  EXPECT_EQ(Keys(json), kMetricsKeys);
  EXPECT_EQ(json["frames_gt"], 100);
  EXPECT_EQ(json["frames_matched"], 97);
  EXPECT_DOUBLE_EQ(json["distance_est_m"].get<double>(), 5.05);
  EXPECT_DOUBLE_EQ(json["distance_error_pct"].get<double>(), 1.0);
  EXPECT_EQ(json["alignment"], "se3");
  EXPECT_DOUBLE_EQ(json["rpe_1m_pct"].get<double>(), 0.75);
  for (const char* key : {"forward_error_pct", "reverse_error_pct", "return_error_pct", "scale",
                          "junction_distances", "dense_map"}) {
    EXPECT_TRUE(json[key].is_null()) << key;
  }
}

TEST(MetricsReport, OutAndBackSim3WithJunctions) {
  Metrics metrics = OneWay();
  metrics.out_and_back = true;
  metrics.forward_error_pct = 1.0;
  metrics.reverse_error_pct = 2.0;
  metrics.return_error_pct = 0.5;
  metrics.alignment = Alignment::kSim3;
  metrics.scale = 0.99;
  metrics.rpe_1m_pct.reset();
  metrics.junction_distances = std::vector<JunctionDistance>{{"A", "B", 2.0, 2.1, 0.1, 5.0}};
  const nlohmann::json json = MetricsToJson(metrics);
  EXPECT_EQ(Keys(json), kMetricsKeys);
  EXPECT_EQ(json["alignment"], "sim3");
  EXPECT_DOUBLE_EQ(json["scale"].get<double>(), 0.99);
  EXPECT_DOUBLE_EQ(json["reverse_error_pct"].get<double>(), 2.0);
  EXPECT_TRUE(json["rpe_1m_pct"].is_null());
  ASSERT_EQ(json["junction_distances"].size(), 1u);
  const nlohmann::json& pair = json["junction_distances"][0];
  EXPECT_EQ(Keys(pair),
            (std::set<std::string>{"from", "to", "gt_m", "est_m", "error_m", "error_pct"}));
  EXPECT_EQ(pair["from"], "A");
  EXPECT_DOUBLE_EQ(pair["error_m"].get<double>(), 0.1);

  const std::string table = MetricsToTable(metrics);
  EXPECT_NE(table.find("out-and-back"), std::string::npos) << table;
  EXPECT_NE(table.find("reverse_error_pct   2.000 %"), std::string::npos) << table;
  EXPECT_NE(table.find("scale               0.990000"), std::string::npos) << table;
  EXPECT_NE(table.find("rpe_1m_pct          - (run shorter"), std::string::npos) << table;
  EXPECT_NE(table.find("  A     B   2.0000  2.1000  +0.1000      5.000"), std::string::npos)
      << table;
}

TEST(MetricsReport, OneWayTableLeavesOutLegErrors) {
  const std::string table = MetricsToTable(OneWay());
  EXPECT_NE(table.find("distance_error_pct  1.000 %"), std::string::npos) << table;
  EXPECT_NE(table.find("ate_rmse_m          0.0120 m"), std::string::npos) << table;
  EXPECT_EQ(table.find("forward_error_pct"), std::string::npos) << table;
  EXPECT_EQ(table.find("junction_distances"), std::string::npos) << table;
  EXPECT_EQ(table.find("dense_map"), std::string::npos) << table;
}

// A dense map's pieces: each with its agreement, a piece without enough cells null, and the
// straight pieces' median and worst (the T's piece is not among them).
TEST(MetricsReport, DenseMapPiecesAndTheirStraightSummary) {
  Metrics metrics = OneWay();
  DenseMapAgreement good{0.9, 5000, 1, -2, false}, fair{0.7, 4000, 0, 0, false},
      at_edge{0.5, 3000, 8, 0, true};
  metrics.dense_map = std::vector<DensePieceAgreement>{
      {0, 0, "straight", 40, good}, {1, 0, "straight", 38, fair}, {2, 1, "t-red", 9, at_edge},
      {3, 2, "straight", 2, DenseMapAgreement{}}};
  const nlohmann::json json = MetricsToJson(metrics);
  EXPECT_EQ(Keys(json), kMetricsKeys);
  const nlohmann::json& dense = json["dense_map"];
  ASSERT_EQ(dense["pieces"].size(), 4u);
  EXPECT_EQ(dense["pieces"][1]["part"], "straight");
  EXPECT_DOUBLE_EQ(dense["pieces"][1]["correlation"].get<double>(), 0.7);
  EXPECT_EQ(dense["pieces"][0]["shift_cols"], -2);
  EXPECT_TRUE(dense["pieces"][2]["shift_at_limit"].get<bool>());
  EXPECT_TRUE(dense["pieces"][3]["correlation"].is_null());
  EXPECT_DOUBLE_EQ(dense["straight_median_correlation"].get<double>(), 0.8);
  EXPECT_DOUBLE_EQ(dense["straight_worst_correlation"].get<double>(), 0.7);
  const std::string table = MetricsToTable(metrics);
  EXPECT_NE(table.find("straight pieces: median 0.800, worst 0.700"), std::string::npos) << table;
  EXPECT_NE(table.find("8,0 (at the search's edge)"), std::string::npos) << table;
}

}  // namespace
}  // namespace pipescope

#include "pipescope/io/csv_fields.h"

#include <gtest/gtest.h>

namespace pipescope {
namespace {

TEST(CsvFields, SplitsPlainAndQuotedFields) {
  EXPECT_EQ(SplitCsvLine("12,320.5,,CR"), (std::vector<std::string>{"12", "320.5", "", "CR"}));
  EXPECT_EQ(SplitCsvLine("1,\"crack, 3 cm\",\"say \"\"hi\"\"\"\r"),
            (std::vector<std::string>{"1", "crack, 3 cm", "say \"hi\""}));
  EXPECT_THROW(SplitCsvLine("1,\"open"), std::invalid_argument);
}

TEST(CsvFields, QuotesOnlyWhereNeededAndRoundTrips) {
  EXPECT_EQ(CsvField("plain"), "plain");
  const std::string awkward = "a, \"b\"";
  EXPECT_EQ(CsvField(awkward), "\"a, \"\"b\"\"\"");
  EXPECT_EQ(SplitCsvLine("x," + CsvField(awkward)), (std::vector<std::string>{"x", awkward}));
}

}  // namespace
}  // namespace pipescope

// splitCsvFields (io/fixed_width.h): the CSV field splitting shared by the truth
// CSV (replay_report) and trajectory CSV (flight_trajectory) readers.
#include <gtest/gtest.h>

#include "ppp_bayes_tree/io/fixed_width.h"

TEST(CsvFields, FieldsAreTrimmedAndEmptyFieldsKept) {
  using V = std::vector<std::string>;
  EXPECT_EQ(ppp::splitCsvFields(" time_s , x_m,y_m "), (V{"time_s", "x_m", "y_m"}));
  EXPECT_EQ(ppp::splitCsvFields("1,,3"), (V{"1", "", "3"}));
  EXPECT_EQ(ppp::splitCsvFields("1,2,"), (V{"1", "2", ""}));  // a trailing comma: an empty last field
  EXPECT_EQ(ppp::splitCsvFields("1,2\r"), (V{"1", "2"}));      // a CRLF line end
  EXPECT_EQ(ppp::splitCsvFields("\t7\t"), (V{"7"}));
}

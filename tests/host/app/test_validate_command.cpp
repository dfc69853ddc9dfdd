// `perifrac validate`'s options: a traction only where a problem takes one, and only a positive one.
#include "host/app/validate_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace pd {
namespace {

int validate_with_traction(const std::string& problem, double traction_mpa, std::string* message) {
  ValidateOptions o;
  o.problem = problem;
  o.resolutions = {4};
  o.traction_mpa = traction_mpa;
  o.quiet = true;
  testing::internal::CaptureStderr();
  const int status = validate_command(o);
  *message = testing::internal::GetCapturedStderr();
  return status;
}

TEST(ValidateCommand, RefusesATractionForAProblemWithoutOne) {
  std::string message;
  EXPECT_EQ(validate_with_traction("tension_bar_pmb", 3.04, &message), 2);
  EXPECT_NE(message.find("--traction: problem 'tension_bar_pmb' takes no traction"), std::string::npos)
      << message;
  EXPECT_NE(message.find("allowed: --problem crack_branching"), std::string::npos) << message;
  EXPECT_EQ(validate_with_traction("all", 3.04, &message), 2);  // "all" holds other problems
}

TEST(ValidateCommand, RefusesATractionThatIsNotPositive) {
  std::string message;
  for (double bad : {0.0, -1.0, 1e9}) {
    EXPECT_EQ(validate_with_traction("crack_branching", bad, &message), 2) << bad;
    EXPECT_NE(message.find("--traction"), std::string::npos) << message;
    EXPECT_NE(message.find("allowed: a traction in MPa, > 0 and < 1e6"), std::string::npos) << message;
  }
}

// The CSV records the traction a crack-branching run was given (two loads' rows were alike but
// for their step counts), and is not appended to where its columns are an older perifrac's.
TEST(ValidateCommand, TheCsvRecordsTheTractionAndKeepsItsColumns) {
  const std::string dir = testing::TempDir() + "/perifrac-validate-csv";
  std::filesystem::create_directories(dir);
  const std::string csv = dir + "/a.csv";
  std::filesystem::remove(csv);
  ValidateOptions o;
  o.problem = "tension_bar_pmb";
  o.resolutions = {2};
  o.csv = csv;
  o.quiet = true;
  ASSERT_EQ(validate_command(o), 0);
  std::ifstream in(csv);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  EXPECT_EQ(header, kValidationCsvHeader);
  EXPECT_EQ(header.substr(header.rfind(',') + 1), "traction_mpa");
  EXPECT_EQ(row.back(), ',') << row;  // no --traction: the column empty
  const std::string old = dir + "/old.csv";
  std::ofstream(old) << "problem,backend,precision,resolution\n";
  o.csv = old;
  testing::internal::CaptureStderr();
  EXPECT_EQ(validate_command(o), 2);
  const std::string message = testing::internal::GetCapturedStderr();
  EXPECT_NE(message.find("--csv '" + old + "': its first line is not this perifrac's header"),
            std::string::npos)
      << message;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pd

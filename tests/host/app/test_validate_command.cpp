// `perifrac validate`'s options: a traction only where a problem takes one, and only a positive one.
#include "host/app/validate_command.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace pd

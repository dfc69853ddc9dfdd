// When and from what a measured result came: the UTC time and the git revision (or the
// PERIFRAC_GIT_REV environment variable where the tree has no .git, e.g. a copied tree).
#pragma once

#include <string>

namespace pd {

// strftime of the current UTC time, e.g. utc_now("%Y-%m-%dT%H:%M:%SZ").
std::string utc_now(const char* format);
std::string git_revision();

}  // namespace pd

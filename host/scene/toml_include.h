// toml++ as every scene file includes it. toml++ 3.3 asserts on some malformed input that it goes
// on to report as a parse error (a table header "[[[a]]", a control character in a key): an abort
// in debug builds and, with NDEBUG, an optimiser assumption (__builtin_assume under clang) that the
// input is well formed. Both are turned off here so that every input ends in a result or a
// toml::parse_error; one header, so that every file sees the same toml++.
#pragma once

#pragma push_macro("NDEBUG")
#undef NDEBUG
#define TOML_ASSERT(expr) static_cast<void>(0)
#include <toml++/toml.h>
#pragma pop_macro("NDEBUG")

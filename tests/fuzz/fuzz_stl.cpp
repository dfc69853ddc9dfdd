// libFuzzer target: the input bytes as an STL file, ascii or binary (parse_stl, then check_solid).
// A broken contract escapes as an exception, which libFuzzer reports as a crash.
#include <cstddef>
#include <cstdint>
#include <string>

#include "tests/fuzz/fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  pd::fuzz::mesh_entry(pd::fuzz::MeshFormat::stl, bytes);
  return 0;
}

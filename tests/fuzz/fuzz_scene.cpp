// libFuzzer target: the input bytes as a TOML scene file (parse_scene and its validation).
// A broken contract escapes as an exception, which libFuzzer reports as a crash.
#include <cstddef>
#include <cstdint>
#include <string>

#include "tests/fuzz/fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  pd::fuzz::scene_entry(bytes);
  return 0;
}

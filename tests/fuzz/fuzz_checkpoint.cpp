// libFuzzer target: the input bytes as a checkpoint file, its checksum made right (read_checkpoint).
// A broken contract escapes as an exception, which libFuzzer reports as a crash.
#include <cstddef>
#include <cstdint>
#include <string>

#include "tests/fuzz/fuzz_run_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  pd::fuzz::checkpoint_entry(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}

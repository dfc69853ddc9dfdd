// FNV-1a, 64 bit: a fast checksum for detecting corrupted or truncated files and for
// fingerprinting inputs (not a cryptographic hash).
#pragma once

#include <cstdint>
#include <string_view>

namespace pd {

constexpr uint64_t kFnvOffset = 0xcbf29ce484222325ull;

inline uint64_t fnv1a(std::string_view bytes, uint64_t hash = kFnvOffset) {
  for (unsigned char c : bytes) {
    hash ^= c;
    hash *= 0x100000001b3ull;
  }
  return hash;
}

}  // namespace pd

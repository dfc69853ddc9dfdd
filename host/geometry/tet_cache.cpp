#include "host/geometry/tet_cache.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <utility>
#include <vector>

#include "host/io/byte_file.h"
#include "host/io/checksum.h"

namespace pd {

namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'P', 'F', 'T', 'E', 'T', 'S', '0', '2'};
constexpr uint64_t kSecondBasis = 0x84222325cbf29ce4ull;  // the second hash's start (another basis)
constexpr size_t kCounts = 3;                             // vertices, tets, neighbours
constexpr size_t kHeaderBytes = sizeof kMagic + 8 * (2 + kCounts);

template <class T>
void put_all(std::string& out, const std::vector<T>& v) {
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <class T>
T get(const std::string& in, size_t& at) {
  T v;
  std::memcpy(&v, in.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}

template <class T>
void get_all(const std::string& in, size_t& at, std::vector<T>& v) {
  std::memcpy(v.data(), in.data() + at, v.size() * sizeof(T));
  at += v.size() * sizeof(T);
}

std::string hex(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// Removes the entries used longest ago (never `keep`) until the folder holds at most `bound` bytes.
void trim(const std::string& folder, const std::string& keep, uint64_t bound) {
  struct Entry {
    fs::path path;
    fs::file_time_type used;
    uintmax_t bytes;
  };
  std::vector<Entry> entries;
  uintmax_t total = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("tets-", 0) != 0 || e.path().extension() != ".bin") continue;
    std::error_code size_ec, time_ec;
    const uintmax_t bytes = e.file_size(size_ec);
    const fs::file_time_type used = e.last_write_time(time_ec);
    if (size_ec || time_ec) continue;
    entries.push_back({e.path(), used, bytes});
    total += bytes;
  }
  if (total <= bound) return;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.used < b.used; });
  for (const Entry& e : entries) {
    if (total <= bound) break;
    if (e.path == keep) continue;
    if (fs::remove(e.path, ec)) total -= e.bytes;
  }
}

}  // namespace

std::string tet_cache_folder() {
  if (const char* given = std::getenv("PERIFRAC_TET_CACHE"); given && *given)
    return std::string(given) == "off" ? std::string() : std::string(given);
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return std::string(xdg) + "/perifrac/tets";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::string(home) + "/.cache/perifrac/tets";
  return {};
}

TetCache::TetCache(std::string folder, std::string_view input, uint64_t bound)
    : folder_(std::move(folder)), bound_(bound) {
  const uint64_t key = fnv1a(input);
  check_ = fnv1a(input, kSecondBasis);
  path_ = (fs::path(folder_) / ("tets-" + hex(key) + ".bin")).string();
}

std::optional<TetMesh> TetCache::load() const {
  // (A file past the folder's bound is no entry of its own making: not read.)
  std::error_code size_ec;
  const uintmax_t size = fs::file_size(path_, size_ec);
  if (size_ec || size > bound_) return std::nullopt;
  std::ifstream in(path_, std::ios::binary);
  if (!in) return std::nullopt;
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < kHeaderBytes + 8 || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    return std::nullopt;
  size_t at = sizeof kMagic;
  if (get<uint64_t>(bytes, at) != check_) return std::nullopt;
  const uint64_t payload_sum = get<uint64_t>(bytes, at);
  uint64_t count[kCounts];
  for (uint64_t& c : count) c = get<uint64_t>(bytes, at);
  const uint64_t payload = count[0] * sizeof(Vec3d) + count[1] * sizeof(std::array<int32_t, 4>) +
                           count[2] * sizeof(std::array<int32_t, 4>);
  // (Counts past the file's size are refused before any allocation.)
  if (count[0] > bytes.size() || count[1] > bytes.size() || count[2] > bytes.size() ||
      bytes.size() != kHeaderBytes + payload)
    return std::nullopt;
  if (fnv1a(std::string_view(bytes).substr(kHeaderBytes)) != payload_sum) return std::nullopt;
  TetMesh mesh;
  mesh.vertices.resize(count[0]);
  mesh.tets.resize(count[1]);
  mesh.neighbors.resize(count[2]);
  get_all(bytes, at, mesh.vertices);
  get_all(bytes, at, mesh.tets);
  get_all(bytes, at, mesh.neighbors);
  std::error_code ec;
  fs::last_write_time(path_, fs::file_time_type::clock::now(), ec);  // used now: trimmed last
  return mesh;
}

void TetCache::store(const TetMesh& mesh) const {
  std::string payload;
  put_all(payload, mesh.vertices);
  put_all(payload, mesh.tets);
  put_all(payload, mesh.neighbors);
  std::string bytes(kMagic, sizeof kMagic);
  put_bytes(bytes, check_);
  put_bytes(bytes, fnv1a(payload));
  for (uint64_t c :
       {uint64_t(mesh.vertices.size()), uint64_t(mesh.tets.size()), uint64_t(mesh.neighbors.size())})
    put_bytes(bytes, c);
  bytes += payload;
  // Written beside the entry and renamed into place: a reader sees the whole entry or none.
  const std::string tmp = path_ + ".tmp." + std::to_string(::getpid());
  std::error_code ec;
  fs::create_directories(folder_, ec);
  bool written = false;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    written = out && out.write(bytes.data(), std::streamsize(bytes.size())) && out.flush();
  }
  if (written) {
    fs::rename(tmp, path_, ec);
    written = !ec;
  }
  if (!written) {
    fs::remove(tmp, ec);
    static std::atomic<bool> said{false};
    if (!said.exchange(true))
      std::fprintf(stderr,
                   "warning: cannot write TetGen's tets to the cache %s (set PERIFRAC_TET_CACHE to another "
                   "folder, or to off); runs go on without it\n",
                   path_.c_str());
    return;
  }
  trim(folder_, path_, bound_);
}

}  // namespace pd

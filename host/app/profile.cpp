#include "host/app/profile.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "cuda/engine/engine.h"
#include "host/app/backend_choice.h"
#include "host/app/provenance.h"
#include "host/app/shards_pattern.h"
#include "host/io/atomic_file.h"
#include "host/scene/scene.h"
#include "host/scene/scene_setup.h"

namespace pd {

namespace {

// Per-kernel seconds and launches of the step kernels ("pd/") since the last reset, the
// instantiations of a kernel ("springforces[state,lattice]") summed under its name (Levine's
// Table 2 has one row a kernel); registers and occupancy are those of the instantiation that
// took the most time (`perifrac bench` lists each).
std::map<std::string, KernelStat> step_kernels(const KernelStats& stats) {
  std::map<std::string, KernelStat> out;
  std::map<std::string, double> longest;
  for (const auto& [name, s] : stats.table()) {
    if (name.rfind("pd/", 0) != 0 || s.launches == 0) continue;
    const std::string kernel =
        name.substr(3, name.find('[') == std::string::npos ? std::string::npos : name.find('[') - 3);
    KernelStat& k = out[kernel];
    k.seconds += s.seconds;
    k.launches += s.launches;
    if (s.seconds >= longest[kernel]) {
      longest[kernel] = s.seconds;
      k.registers = s.registers;
      k.occupancy = s.occupancy;
      k.block_size = s.block_size;
    }
  }
  return out;
}

struct RangeResult {
  int64_t begin = 0, end = 0;
  std::map<std::string, KernelStat> kernels;  // summed over the range
  double broken = 0;                          // broken-bond fraction at the end
};

}  // namespace

constexpr long long kMaxProfileSteps = 1LL << 40;  // --steps's bound
constexpr int64_t kMaxTimelineRows = 100000;

std::vector<std::pair<int64_t, int64_t>> parse_step_ranges(const std::string& text) {
  std::vector<std::pair<int64_t, int64_t>> ranges;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    // A:B, each a step count up to 2^40 (--steps's bound), nothing after.
    const auto step = [](const char* text, char** end) {
      errno = 0;
      const long long v = std::strtoll(text, end, 10);
      return errno == ERANGE || *end == text || v < 0 || v > kMaxProfileSteps ? -1LL : v;
    };
    char* end = nullptr;
    const long long a = step(item.c_str(), &end);
    const bool colon = a >= 0 && *end == ':';
    const long long b = colon ? step(end + 1, &end) : -1;
    if (!colon || b <= a || *end != '\0')
      throw std::invalid_argument(
          "--ranges: '" + item +
          "' is not a step range A:B with 0 <= A < B <= 2^40 (e.g. 0:1000,50000:51000)");
    ranges.emplace_back(a, b);
  }
  if (ranges.empty()) throw std::invalid_argument("--ranges: no range given (e.g. 0:1000,50000:51000)");
  std::sort(ranges.begin(), ranges.end());
  for (size_t k = 1; k < ranges.size(); ++k)
    if (ranges[k].first < ranges[k - 1].second)
      throw std::invalid_argument(
          "--ranges: " + std::to_string(ranges[k - 1].first) + ":" + std::to_string(ranges[k - 1].second) +
          " and " + std::to_string(ranges[k].first) + ":" + std::to_string(ranges[k].second) + " overlap");
  return ranges;
}

namespace {

// The ranges asked for (or the run cut into 5) and the run's length, checked against each other.
std::vector<std::pair<int64_t, int64_t>> profile_ranges(const ProfileOptions& opt, int64_t scene_steps,
                                                        int64_t* steps) {
  std::vector<std::pair<int64_t, int64_t>> ranges;
  if (!opt.ranges.empty()) ranges = parse_step_ranges(opt.ranges);
  *steps = opt.steps > 0 ? opt.steps : (ranges.empty() ? scene_steps : ranges.back().second);
  if (ranges.empty())
    for (int k = 0; k < 5; ++k) ranges.emplace_back(*steps * k / 5, *steps * (k + 1) / 5);
  if (ranges.back().second > *steps)
    throw std::invalid_argument("--ranges: the last range ends at step " +
                                std::to_string(ranges.back().second) + ", after the run's " +
                                std::to_string(*steps) + " steps (raise --steps)");
  return ranges;
}

// Chunk boundaries: the timeline's and the ranges' ends, so every chunk is inside or outside
// each range.
std::set<int64_t> chunk_ends(const std::vector<std::pair<int64_t, int64_t>>& ranges, int64_t steps,
                             int64_t chunk) {
  std::set<int64_t> cuts;
  for (int64_t s = chunk; s < steps; s += chunk) cuts.insert(s);
  for (const auto& [a, b] : ranges) {
    cuts.insert(a);
    cuts.insert(b);
  }
  cuts.insert(steps);
  cuts.erase(0);
  return cuts;
}

// Runs the engine chunk by chunk to `steps`: the kernel times of each chunk go to the timeline
// and, inside a range, to that range's sums (an NVTX range around it); the broken-bond fraction
// is taken at each range's end.
std::vector<RangeResult> run_ranges(Engine& engine, const std::vector<std::pair<int64_t, int64_t>>& ranges,
                                    int64_t steps, int64_t chunk, std::ostringstream& timeline) {
  const int64_t bonds = engine.family_stats().bonds;
  std::vector<RangeResult> results;
  for (const auto& [a, b] : ranges) results.push_back({a, b, {}, 0});
  timeline << "step_begin,step_end,kernel,ms_per_step\n";
  int64_t at = 0;
  size_t open = ranges.size();  // index of the range being profiled, or ranges.size()
  for (int64_t cut : chunk_ends(ranges, steps, chunk)) {
    for (size_t k = 0; k < ranges.size(); ++k)
      if (ranges[k].first == at) {
        profiler_range_push(
            ("pd-range-" + std::to_string(ranges[k].first) + "-" + std::to_string(ranges[k].second)).c_str());
        open = k;
      }
    engine.stats().reset_times();
    engine.advance(cut - at);
    for (const auto& [name, s] : step_kernels(engine.stats())) {
      timeline << at << "," << cut << "," << name << "," << 1e3 * s.seconds / double(cut - at) << "\n";
      if (open < ranges.size()) {
        KernelStat& r = results[open].kernels[name];
        r.seconds += s.seconds;
        r.launches += s.launches;
        r.registers = s.registers;
        r.occupancy = s.occupancy;
      }
    }
    at = cut;
    if (open < ranges.size() && ranges[open].second == at) {
      profiler_range_pop();
      results[open].broken = bonds > 0 ? double(engine.broken_bonds()) / double(bonds) : 0;
      open = ranges.size();
    }
    if (engine.first_non_finite() >= 0)
      throw std::runtime_error("profile: the run blew up by step " + std::to_string(at) +
                               " (run it with `perifrac run` for the watchdog's diagnosis)");
  }
  return results;
}

double range_seconds(const RangeResult& r) {
  double total = 0;
  for (const auto& [k, s] : r.kernels) total += s.seconds;
  return total;
}

// Prints the table (ms per step per kernel and range, Levine Table 2 layout, with registers and
// theoretical occupancy) and returns the same figures as CSV.
std::string print_range_table(const std::vector<RangeResult>& results, int64_t bonds) {
  std::set<std::string> names;
  for (const RangeResult& r : results)
    for (const auto& [name, s] : r.kernels) names.insert(name);
  std::printf("\n%-20s", "ms per step");
  for (const RangeResult& r : results)
    std::printf(" %15s", (std::to_string(r.begin) + ":" + std::to_string(r.end)).c_str());
  std::printf("  regs  occupancy\n");
  std::ostringstream csv;
  csv << "range_begin,range_end,kernel,launches,ms_per_step,share,bond_updates_per_s,registers,"
         "theoretical_occupancy,broken_fraction\n";
  for (const std::string& name : names) {
    std::printf("%-20s", name.c_str());
    int regs = -1;
    double occupancy = -1;
    for (const RangeResult& r : results) {
      const auto it = r.kernels.find(name);
      const double n = double(r.end - r.begin);
      const double total = range_seconds(r);
      if (it == r.kernels.end()) {
        std::printf(" %15s", "-");
        continue;
      }
      const KernelStat& s = it->second;
      regs = s.registers;
      occupancy = s.occupancy;
      std::printf(" %15.4f", 1e3 * s.seconds / n);
      csv << r.begin << "," << r.end << "," << name << "," << s.launches << "," << 1e3 * s.seconds / n << ","
          << (total > 0 ? s.seconds / total : 0) << "," << (s.seconds > 0 ? double(bonds) * n / s.seconds : 0)
          << "," << s.registers << "," << s.occupancy << "," << r.broken << "\n";
    }
    if (regs >= 0)
      std::printf("  %4d  %9.2f\n", regs, occupancy);
    else
      std::printf("  %4s  %9s\n", "-", "-");
  }
  std::printf("%-20s", "step");
  for (const RangeResult& r : results)
    std::printf(" %15.4f", 1e3 * range_seconds(r) / double(r.end - r.begin));
  std::printf("\n%-20s", "broken bonds %");
  for (const RangeResult& r : results) std::printf(" %15.3f", 100 * r.broken);
  std::printf("\n");
  return csv.str();
}

}  // namespace

int profile_command(const ProfileOptions& opt) {
  Scene scene = load_scene(opt.scene);
  std::string note;
  const Backend backend = choose_backend(opt.backend, &note);
  const SetupResult setup = setup_scene_with_patterns(scene, opt.scale, backend);
  int64_t steps = 0;
  const auto ranges = profile_ranges(opt, scene.frames * scene.steps_per_frame, &steps);
  const int64_t chunk = opt.timeline > 0 ? opt.timeline : std::max<int64_t>(1, steps / 100);
  if (steps / chunk > kMaxTimelineRows)  // (each row a kernel's line of the timeline, held in memory)
    throw std::invalid_argument("--timeline " + std::to_string(chunk) + ": " + std::to_string(steps / chunk) +
                                " points over " + std::to_string(steps) + " steps (allowed: at most " +
                                std::to_string(kMaxTimelineRows) + " points, --timeline " +
                                std::to_string((steps + kMaxTimelineRows - 1) / kMaxTimelineRows) +
                                " or more)");

  auto engine = make_engine(backend, setup.input);
  const int64_t bonds = engine->family_stats().bonds;
  if (!note.empty()) std::printf("backend    %s\n", note.c_str());
  std::printf("profile    %s on %s [%s]: %zu particles, %lld bonds, %lld steps, dt %.4g s\n",
              scene.path.c_str(), engine->device_name().c_str(), backend_name(backend),
              setup.input.particles.size(), (long long)bonds, (long long)steps, setup.dt);
  std::ostringstream timeline;
  const std::vector<RangeResult> results = run_ranges(*engine, ranges, steps, chunk, timeline);
  const std::string csv = print_range_table(results, bonds);

  ensure_directory(opt.out);
  const std::string stem = opt.out + "/" + utc_now("%Y%m%d-%H%M%S") + "_" + backend_name(backend) + "_" +
                           std::filesystem::path(scene.path).stem().string();
  const std::string header = "# " + engine->device_name() + ", " + utc_now("%Y-%m-%dT%H:%M:%SZ") + ", git " +
                             git_revision() + ", scale " + std::to_string(opt.scale) + "\n";
  write_file_atomic(stem + "_profile.csv", header + csv);
  write_file_atomic(stem + "_timeline.csv", header + timeline.str());
  std::printf("results    %s_profile.csv, %s_timeline.csv\n", stem.c_str(), stem.c_str());
  return 0;
}

}  // namespace pd

#include "host/app/compare.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/app/run_folder.h"
#include "host/io/frame_file.h"

namespace pd {

namespace {

// The complete frame files of the run in `dir` (run_folder.h), by frame number; a folder that is
// not a run's output is the user's mistake.
std::map<int64_t, std::string> run_frames(const std::string& dir) {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    throw std::invalid_argument("compare: '" + dir + "' is " +
                                (std::filesystem::exists(dir, ec) ? "not a folder" : "not there") +
                                " (allowed: output folders of `perifrac run`)");
  if (!std::filesystem::exists(std::filesystem::path(dir) / kRestFileName, ec))
    throw std::invalid_argument("compare: '" + dir + "' holds no " + std::string(kRestFileName) +
                                " (allowed: output folders of `perifrac run` with output.binary = true, "
                                "the default)");
  std::vector<int64_t> partial;
  return complete_frame_files(dir, read_run_contents(dir), &partial);
}

// How far frame B is from frame A: the relative L2 norm of the displacement difference (0 where
// both stay at rest, infinite where only B moved) and the mean absolute damage difference.
struct FrameDifference {
  double displacement = 0, damage = 0;
};

FrameDifference difference(const RestData& rest, const FrameData& fa, const FrameData& fb) {
  double num = 0, den = 0, damage = 0;
  for (size_t i = 0; i < fa.position.size(); ++i) {
    const Vec3 ua = fa.position[i] - rest.position[i], ub = fb.position[i] - rest.position[i];
    num += double(length_squared(ua - ub));
    den += double(length_squared(ua));
    damage += std::fabs(double(fa.damage[i]) - double(fb.damage[i]));
  }
  FrameDifference d;
  d.displacement = den > 0 ? std::sqrt(num / den) : num > 0 ? std::numeric_limits<double>::infinity() : 0;
  d.damage = fa.position.empty() ? 0 : damage / double(fa.position.size());
  return d;
}

}  // namespace

int compare_command(const CompareOptions& opt) {
  const std::map<int64_t, std::string> frames_a = run_frames(opt.a), frames_b = run_frames(opt.b);
  const RestData rest = read_rest_file(opt.a + "/" + kRestFileName);
  std::set<int64_t> numbers;
  for (const auto& [f, file] : frames_a) numbers.insert(f);
  for (const auto& [f, file] : frames_b) numbers.insert(f);
  if (numbers.empty())
    throw std::invalid_argument("compare: neither '" + opt.a + "' nor '" + opt.b +
                                "' holds a complete frame (allowed: runs that wrote frame 0 at least)");
  int compared = 0, missing = 0;
  bool ok = true;
  std::printf("%-18s %14s %14s %8s\n", "frame", "disp rel L2", "damage |diff|", "verdict");
  for (int64_t f : numbers) {
    const std::string name = frame_file_name(f, "pfr");
    const auto a = frames_a.find(f), b = frames_b.find(f);
    if (a == frames_a.end() || b == frames_b.end()) {
      ++missing;
      ok = false;
      std::printf("%-18s %14s %14s %8s (only in %s)\n", name.c_str(), "-", "-", "MISSING",
                  (a == frames_a.end() ? opt.b : opt.a).c_str());
      continue;
    }
    const FrameData fa = read_frame_file(a->second), fb = read_frame_file(b->second);
    if (fa.position.size() != fb.position.size() || fa.position.size() != rest.position.size())
      throw std::invalid_argument("compare: " + name + " has different particle counts in the two folders");
    const FrameDifference d = difference(rest, fa, fb);
    // The same step, and the same time but for rounding: a dt = "auto" measured on a GPU may
    // differ from the CPU's in its last float digits.
    const bool same_time = fa.step == fb.step && std::fabs(fa.time - fb.time) <= 1e-6 * std::fabs(fa.time);
    const bool frame_ok =
        same_time && d.displacement <= opt.position_tolerance && d.damage <= opt.damage_tolerance;
    ok = ok && frame_ok;
    ++compared;
    std::string note;
    if (!same_time) {
      char buf[160];
      std::snprintf(buf, sizeof buf, " (step %lld against %lld, time %.9g against %.9g s)",
                    (long long)fa.step, (long long)fb.step, fa.time, fb.time);
      note = buf;
    }
    std::printf("%-18s %14.3e %14.3e %8s%s\n", name.c_str(), d.displacement, d.damage,
                frame_ok ? "ok" : "DIFFERS", note.c_str());
  }
  std::printf(
      "compare: %d frames compared, %d in one folder only: %s (tolerances: displacement %.1e relative L2, "
      "damage %.1e mean)\n",
      compared, missing, ok ? "agree" : "DIFFER", opt.position_tolerance, opt.damage_tolerance);
  return ok ? 0 : 1;
}

}  // namespace pd

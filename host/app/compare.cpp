#include "host/app/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "host/io/frame_file.h"

namespace pd {

namespace {

std::vector<std::string> frame_files(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string n = e.path().filename().string();
    if (n.rfind("frame_", 0) == 0 && e.path().extension() == ".pfr") names.push_back(n);
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

int compare_command(const CompareOptions& opt) {
  for (const auto& d : {opt.a, opt.b})
    if (!std::filesystem::is_directory(d))
      throw std::invalid_argument("compare: '" + d + "' is not a folder");
  const RestData rest = read_rest_file(opt.a + "/" + kRestFileName);
  const auto names = frame_files(opt.a);
  int frames = 0;
  bool ok = true;
  std::printf("%-18s %14s %14s %8s\n", "frame", "disp rel L2", "damage |diff|", "verdict");
  for (const auto& name : names) {
    if (!std::filesystem::exists(opt.b + "/" + name)) continue;
    const FrameData fa = read_frame_file(opt.a + "/" + name), fb = read_frame_file(opt.b + "/" + name);
    if (fa.position.size() != fb.position.size() || fa.position.size() != rest.position.size())
      throw std::invalid_argument("compare: " + name + " has different particle counts in the two folders");
    double num = 0, den = 0, dmg = 0;
    for (size_t i = 0; i < fa.position.size(); ++i) {
      const Vec3 ua = fa.position[i] - rest.position[i], ub = fb.position[i] - rest.position[i];
      num += double(length_squared(ua - ub));
      den += double(length_squared(ua));
      dmg += std::fabs(double(fa.damage[i]) - double(fb.damage[i]));
    }
    const double rel = den > 0 ? std::sqrt(num / den) : std::sqrt(num);
    dmg /= double(fa.position.size());
    const bool frame_ok = rel <= opt.position_tolerance && dmg <= opt.damage_tolerance;
    ok = ok && frame_ok;
    ++frames;
    std::printf("%-18s %14.3e %14.3e %8s\n", name.c_str(), rel, dmg, frame_ok ? "ok" : "DIFFERS");
  }
  if (frames == 0)
    throw std::invalid_argument("compare: no common frame files in '" + opt.a + "' and '" + opt.b + "'");
  std::printf("compare: %d frames, %s (tolerances: displacement %.1e relative L2, damage %.1e mean)\n",
              frames, ok ? "agree" : "DIFFER", opt.position_tolerance, opt.damage_tolerance);
  return ok ? 0 : 1;
}

}  // namespace pd

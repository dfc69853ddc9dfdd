#include "host/app/validate_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "host/app/backend_choice.h"
#include "host/geometry/tri_mesh.h"
#include "host/io/atomic_file.h"
#include "host/validation/validation.h"

namespace pd {

const char* const kValidationCsvHeader =
    "problem,backend,precision,resolution,delta_over_lambda,dt_fraction,particles,steps,wall_s,measured,"
    "reference,rel_error,surface_correction,traction_mpa";

namespace {

// The most particles across a problem takes (the crack plate runs 160; the wave bar at 400 across
// holds 64 million particles, past any backend's memory).
constexpr int kMaxResolution = 400;

const char* surface_name(const ValidationCase& c) {
  if (c.surface_ghosts) return "ghosts";
  return !c.surface_correction ? "default" : *c.surface_correction ? "on" : "off";
}

const char* precision_name() {
  return sizeof(real) == 8 ? "double" : "float";
}

std::string csv_row(const ValidationResult& r, const ValidationCase& c) {
  char line[512], traction[32] = "";  // the --traction given, in MPa (empty: the problem's own load)
  if (c.traction > 0) std::snprintf(traction, sizeof traction, "%.9g", c.traction / 1e6);
  std::snprintf(line, sizeof line, "%s,%s,%s,%d,%g,%g,%lld,%lld,%.4f,%.9g,%.9g,%.6g,%s,%s\n",
                r.problem.c_str(), backend_name(c.backend), precision_name(), c.resolution,
                c.delta_over_lambda, c.dt_fraction, (long long)r.particles, (long long)r.steps, r.wall_s,
                r.measured, r.reference, r.rel_error, surface_name(c), traction);
  return line;
}

// Appends rows to the CSV, rewriting it atomically (header first when it is new or empty). A file
// whose header is another (an older perifrac's columns) is not appended to: false.
bool append_csv(const std::string& path, const std::string& rows) {
  std::string text;
  if (std::filesystem::exists(path)) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream old;
    old << in.rdbuf();
    text = old.str();
  }
  if (text.empty()) text = std::string(kValidationCsvHeader) + "\n";
  if (text.compare(0, text.find('\n'), kValidationCsvHeader) != 0) return false;
  write_file_atomic(path, text + rows);
  return true;
}

}  // namespace

int validate_command(const ValidateOptions& o) {
  std::vector<const ValidationProblem*> selected;
  for (const auto& p : validation_problems())
    if ((o.problem == "all" && (o.particles == "grid" || p.scattered)) || o.problem == p.name)
      selected.push_back(&p);
  if (selected.empty()) {
    std::string names;
    for (const auto& p : validation_problems()) names += std::string(", ") + p.name;
    std::fprintf(stderr, "error: validate: unknown problem '%s' (allowed: all%s)\n", o.problem.c_str(),
                 names.c_str());
    return 2;
  }
  if (o.particles != "grid") {
    std::string scattered;
    for (const auto& p : validation_problems())
      if (p.scattered) scattered += std::string(scattered.empty() ? "" : ", ") + p.name;
    for (const ValidationProblem* p : selected)
      if (!p->scattered) {
        std::fprintf(stderr,
                     "error: validate: --particles %s: problem '%s' runs on a grid only (allowed: %s)\n",
                     o.particles.c_str(), p->name, scattered.c_str());
        return 2;
      }
  }
  if (o.traction_mpa) {
    if (!(*o.traction_mpa > 0 && *o.traction_mpa < 1e6)) {
      std::fprintf(stderr, "error: validate: --traction %g (allowed: a traction in MPa, > 0 and < 1e6)\n",
                   *o.traction_mpa);
      return 2;
    }
    for (const ValidationProblem* p : selected)
      if (std::string(p->name) != "crack_branching") {
        std::fprintf(stderr,
                     "error: validate: --traction: problem '%s' takes no traction (allowed: --problem "
                     "crack_branching)\n",
                     p->name);
        return 2;
      }
  }
  if (!(o.delta_over_lambda >= 1) || !(o.dt_fraction >= 0)) {
    std::fprintf(stderr, "error: validate: need --delta-over-lambda >= 1 and --dt-fraction > 0\n");
    return 2;
  }
  for (int r : o.resolutions)
    if (r < 2 || r > kMaxResolution) {
      std::fprintf(stderr, "error: validate: resolution %d (allowed: 2 to %d particles across)\n", r,
                   kMaxResolution);
      return 2;
    }
  // The header now: an unwritable path, or a file of other columns, fails before the work.
  if (!o.csv.empty() && !append_csv(o.csv, "")) {
    std::fprintf(
        stderr,
        "error: validate: --csv '%s': its first line is not this perifrac's header (allowed: a new file, "
        "or one this perifrac wrote, whose columns are %s)\n",
        o.csv.c_str(), kValidationCsvHeader);
    return 2;
  }
  std::string note;
  ValidationCase c;
  try {
    c.backend = choose_backend(o.backend, &note);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: validate: %s\n", e.what());
    return 2;
  }
  if (!note.empty() && !o.quiet) std::printf("backend    %s\n", note.c_str());
  c.delta_over_lambda = o.delta_over_lambda;
  c.particles = o.particles;
  c.traction = o.traction_mpa.value_or(0) * 1e6;
  c.dt_fraction = o.dt_fraction > 0 ? o.dt_fraction : o.surface == "ghosts" ? kGhostDtFraction : 0.5;
  if (o.surface == "ghosts") {
    c.surface_correction = false;
    c.surface_ghosts = true;
  } else if (o.surface != "default") {
    c.surface_correction = o.surface == "on";
  }

  int status = 0;
  for (const ValidationProblem* p : selected) {
    for (int res : o.resolutions.empty() ? p->resolutions : o.resolutions) {
      c.resolution = res;
      std::string rows;
      std::vector<ValidationResult> results;
      try {
        results = p->run(c);
      } catch (const MeshError& e) {
        std::fprintf(stderr, "error: validate: %s: %s\n", p->name, e.what());
        return 2;
      } catch (const std::invalid_argument& e) {  // a --dt-fraction past the measured stable step
        std::fprintf(stderr, "error: validate: %s at resolution %d: --dt-fraction: %s\n", p->name, res,
                     e.what());
        return 2;
      }
      for (const ValidationResult& r : results) {
        rows += csv_row(r, c);
        if (!std::isfinite(r.measured)) status = 3;
        if (!o.quiet)
          std::printf(
              "%-32s %-4s %-6s res %3d  d/l %g  dt %.2f dt_c  surface %-7s  %8lld particles %7lld steps "
              "%8.2f s  measured %-12.6g reference %-12.6g error %6.2f%%  (%s)\n",
              r.problem.c_str(), backend_name(c.backend), precision_name(), res, c.delta_over_lambda,
              c.dt_fraction, surface_name(c), (long long)r.particles, (long long)r.steps, r.wall_s,
              r.measured, r.reference, 100 * r.rel_error, r.note.c_str());
      }
      std::fflush(stdout);
      if (!o.csv.empty()) append_csv(o.csv, rows);
    }
  }
  return status;
}

}  // namespace pd

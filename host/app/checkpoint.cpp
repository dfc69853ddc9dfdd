#include "host/app/checkpoint.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "host/io/checksum.h"
#include "host/io/exact_number.h"
#include "host/io/record_file.h"
#include "host/scene/scene.h"

namespace pd {

namespace {

constexpr char kMagic[8] = {'P', 'F', 'C', 'K', 'P', 'T', '\0', '\0'};

// The scalar fields as "key value" lines.
std::string meta_text(const RunCheckpoint& c) {
  std::ostringstream m;
  m << "real_bytes " << sizeof(real) << "\n"
    << "scene_path " << c.scene_path << "\n"
    << "scene_relative " << c.scene_relative << "\n"
    << "overrides " << c.overrides.size() << "\n"
    << "scene_hash " << c.scene_hash << "\n"
    << "setup_hash " << c.setup_hash << "\n"
    << "scale " << exact_number(c.scale) << "\n"
    << "steps_per_frame " << c.steps_per_frame << "\n"
    << "frames " << c.frames << "\n"
    << "blend_frames " << c.blend_frames << "\n"
    << "allow_unstable_dt " << int(c.allow_unstable_dt) << "\n"
    << "explicit_families " << int(c.explicit_families) << "\n"
    << "checkpoint_every " << c.checkpoint_every << "\n"
    << "checkpoint_minutes " << exact_number(c.checkpoint_minutes) << "\n"
    << "backend " << c.backend << "\n"
    << "frame " << c.frame << "\n"
    << "step " << c.engine.step << "\n"
    << "time " << exact_number(c.engine.time) << "\n";
  for (size_t k = 0; k < c.overrides.size(); ++k) m << "override_" << k << " " << c.overrides[k] << "\n";
  return m.str();
}

// Reads the "key value" lines back; every key must be there.
void parse_meta(const RecordReader& r, std::string_view text, RunCheckpoint& c) {
  std::map<std::string, std::string> kv;
  std::istringstream in{std::string(text)};
  for (std::string line; std::getline(in, line);) {
    const size_t space = line.find(' ');
    if (space == std::string::npos) r.fail("malformed meta line '" + line + "'");
    kv[line.substr(0, space)] = line.substr(space + 1);
  }
  auto get = [&](const char* key) -> const std::string& {
    const auto it = kv.find(key);
    if (it == kv.end()) r.fail(std::string("meta key '") + key + "' is missing");
    return it->second;
  };
  // A finite number at least `min`.
  auto number = [&](const char* key, double min) {
    const std::string& v = get(key);
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || !std::isfinite(x) || x < min)
      r.fail(std::string("meta key '") + key + "' is not a finite number >= " + std::to_string(min));
    return x;
  };
  // A whole number in [min, max] (digits only: no sign, no overflow).
  auto integer = [&](const char* key, uint64_t min, uint64_t max) {
    const std::string& v = get(key);
    char* end = nullptr;
    errno = 0;
    const unsigned long long x = std::strtoull(v.c_str(), &end, 10);
    if (v.empty() || !std::isdigit(static_cast<unsigned char>(v[0])) || *end != '\0' || errno == ERANGE ||
        x < min || x > max)
      r.fail(std::string("meta key '") + key + "' is not an integer from " + std::to_string(min) + " to " +
             std::to_string(max));
    return uint64_t(x);
  };
  const uint64_t any = std::numeric_limits<uint64_t>::max();
  if (const uint64_t bytes = integer("real_bytes", 4, 8); bytes != sizeof(real))
    r.fail("written by a " + std::string(bytes == 8 ? "double" : "float") +
           "-precision build; this build is " + (sizeof(real) == 8 ? "double" : "float"));
  c.scene_path = get("scene_path");
  if (kv.count("scene_relative")) c.scene_relative = get("scene_relative");  // (added later)
  c.overrides.resize(size_t(integer("overrides", 0, kv.size())));
  for (size_t k = 0; k < c.overrides.size(); ++k)
    c.overrides[k] = get(("override_" + std::to_string(k)).c_str());
  c.scene_hash = integer("scene_hash", 0, any);
  c.setup_hash = integer("setup_hash", 0, any);
  c.scale = number("scale", 0);
  c.steps_per_frame = int64_t(integer("steps_per_frame", 1, kMaxStepsPerFrame));
  c.frames = int64_t(integer("frames", 0, kMaxFrames));
  c.blend_frames = int(integer("blend_frames", 0, std::numeric_limits<int>::max()));
  c.allow_unstable_dt = integer("allow_unstable_dt", 0, 1) != 0;
  c.explicit_families =
      kv.count("explicit_families") && integer("explicit_families", 0, 1) != 0;  // (added later)
  if (kv.count("checkpoint_every"))
    c.checkpoint_every = int64_t(integer("checkpoint_every", 0, kMaxFrames));  // (added later)
  if (kv.count("checkpoint_minutes")) c.checkpoint_minutes = number("checkpoint_minutes", 0);
  c.backend = get("backend");
  c.frame = int64_t(integer("frame", 0, uint64_t(c.frames)));
  // A checkpoint after `frame` (at its end, or inside the next frame when a signal stopped it).
  c.engine.step = int64_t(
      integer("step", uint64_t(c.frame * c.steps_per_frame), uint64_t((c.frame + 1) * c.steps_per_frame)));
  c.engine.time = number("time", 0);
}

// The PVD index as "time file" lines (time exact).
std::string series_text(const std::vector<PvdSeries::Entry>& series) {
  std::string s;
  for (const auto& e : series) s += exact_number(e.time) + " " + e.file + "\n";
  return s;
}

std::vector<PvdSeries::Entry> parse_series(const RecordReader& r, std::string_view text) {
  std::vector<PvdSeries::Entry> out;
  std::istringstream in{std::string(text)};
  for (std::string line; std::getline(in, line);) {
    const size_t space = line.find(' ');
    if (space == std::string::npos) r.fail("malformed series line '" + line + "'");
    const double time = std::strtod(line.substr(0, space).c_str(), nullptr);
    if (!std::isfinite(time)) r.fail("series line '" + line + "' has no finite time");
    out.push_back({time, line.substr(space + 1)});
  }
  return out;
}

// Smoother corrections as 9 doubles each: particles, quaternion (w, x, y, z), offset, age.
std::vector<double> pack_corrections(const std::vector<FragmentSmoother::Correction>& cs) {
  std::vector<double> v;
  v.reserve(cs.size() * 9);
  for (const auto& c : cs) {
    const auto& q = c.rotation;
    for (double x : {double(c.particles), q.w(), q.x(), q.y(), q.z(), c.offset.x(), c.offset.y(),
                     c.offset.z(), double(c.age)})
      v.push_back(x);
  }
  return v;
}

std::vector<FragmentSmoother::Correction> unpack_corrections(const RecordReader& r,
                                                             const std::vector<double>& v) {
  if (v.size() % 9 != 0) r.fail("record 'corrections' is not whole corrections");
  std::vector<FragmentSmoother::Correction> cs(v.size() / 9);
  for (size_t k = 0; k < cs.size(); ++k) {
    const double* d = &v[9 * k];
    for (int j = 0; j < 9; ++j)
      if (!std::isfinite(d[j])) r.fail("record 'corrections' holds a number that is not finite");
    if (d[0] < 0 || d[0] > std::numeric_limits<int32_t>::max() || d[8] < -1 ||
        d[8] > std::numeric_limits<int>::max())  // (age -1: none)
      r.fail("record 'corrections' holds a particle count or age out of range");
    cs[k].particles = int32_t(d[0]);
    cs[k].rotation = Eigen::Quaterniond(d[1], d[2], d[3], d[4]);
    cs[k].offset = Eigen::Vector3d(d[5], d[6], d[7]);
    cs[k].age = int(d[8]);
  }
  return cs;
}

template <class T>
uint64_t hash_array(const std::vector<T>& v, uint64_t h) {
  return fnv1a(bytes_of(v), h);
}

}  // namespace

uint64_t setup_fingerprint(const SimulationInput& in) {
  const ParticleSet& ps = in.particles;
  uint64_t h = kFnvOffset;
  h = hash_array(ps.rest, h);
  h = hash_array(ps.volume, h);
  h = hash_array(ps.mass, h);
  h = hash_array(ps.strain_limit0, h);
  h = hash_array(ps.material, h);
  h = hash_array(ps.body, h);
  h = hash_array(ps.flags, h);
  h = hash_array(ps.anchor, h);
  h = hash_array(ps.velocity, h);
  if (!ps.shard.empty()) h = hash_array(ps.shard_strength, hash_array(ps.shard, h));  // [[shards]]
  if (!in.face_bonds.empty()) h = hash_array(in.face_bonds, h);                       // a pattern's
  // Cut triangles field by field (the struct has padding).
  std::vector<double> cuts;
  for (const CutTriangle& t : in.cuts) {
    for (const auto& c : t.corner) cuts.insert(cuts.end(), c.begin(), c.end());
    cuts.push_back(t.strength);
    cuts.push_back(double(t.body));
  }
  return hash_array(cuts, h);
}

uint64_t scene_fingerprint(const std::string& path, const std::vector<std::string>& overrides) {
  uint64_t h = file_fingerprint(path);
  for (const std::string& o : overrides) h = fnv1a(o + "\n", h);
  return h;
}

uint64_t file_fingerprint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error_errno("read", path, errno);
  std::ostringstream all;
  all << in.rdbuf();
  return fnv1a(all.str());
}

void write_checkpoint(const std::string& path, const RunCheckpoint& c) {
  RecordWriter w;
  w.add_owned("meta", meta_text(c));
  for_each_snapshot_field(c.engine, [&](const char* name, const auto& v) { w.add_array(name, v); });
  w.add_array("free_bodies", c.engine.free_bodies);
  w.add_owned("energy0", std::string(reinterpret_cast<const char*>(&c.energy0), sizeof c.energy0));
  w.add("energy_log", c.energy_log);
  w.add("fragment_log", c.fragment_log);
  w.add_owned("series", series_text(c.series));
  w.add_array("smooth_index", c.smoother.previous_index);
  w.add_owned("corrections", std::string(bytes_of(pack_corrections(c.smoother.previous))));
  w.write(path, kMagic, kCheckpointVersion);
}

RunCheckpoint read_checkpoint(const std::string& path) {
  const RecordReader r(path, kMagic, kCheckpointVersion);
  RunCheckpoint c;
  parse_meta(r, r.get("meta"), c);
  for_each_snapshot_field(c.engine, [&](const char* name, auto& v) {
    v = r.get_array<typename std::decay_t<decltype(v)>::value_type>(name);
  });
  if (r.has("free_bodies")) c.engine.free_bodies = r.get_array<double>("free_bodies");
  const std::vector<Energy> energy0 = r.get_array<Energy>("energy0");
  if (energy0.size() != 1) r.fail("record 'energy0' has the wrong size");
  c.energy0 = energy0[0];
  c.energy_log = std::string(r.get("energy_log"));
  if (r.has("fragment_log")) c.fragment_log = std::string(r.get("fragment_log"));  // (added later)
  c.series = parse_series(r, r.get("series"));
  c.smoother.previous_index = r.get_array<int32_t>("smooth_index");
  c.smoother.previous = unpack_corrections(r, r.get_array<double>("corrections"));
  return c;
}

}  // namespace pd

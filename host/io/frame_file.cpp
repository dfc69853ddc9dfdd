#include "host/io/frame_file.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <ostream>
#include <string_view>
#include <variant>
#include <vector>

#include "host/io/atomic_file.h"

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, ".pfr files are little endian");

namespace pd {

namespace {

constexpr size_t kNameBytes = 16;

// The fixed header after the magic and version.
struct PfrHeader {
  uint32_t kind = 0;
  uint64_t count = 0;
  int64_t frame = 0, step = 0;
  double time = 0;
};

// ---- Writing ----------------------------------------------------------------------------------

struct ArrayOut {
  const char* name;
  uint32_t type;
  uint32_t components;
  std::string_view bytes;
};

template <class T>
void put(std::ostream& out, T value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof value);
}

void write_pfr(const std::string& path, const PfrHeader& h, const std::vector<ArrayOut>& arrays) {
  write_file_atomic(path, [&](std::ostream& out) {
    // Header.
    out.write(kPfrMagic, sizeof kPfrMagic);
    put(out, kPfrVersion);
    put(out, h.kind);
    put(out, h.count);
    put(out, h.frame);
    put(out, h.step);
    put(out, h.time);
    put(out, uint32_t(arrays.size()));
    // Arrays: NUL-padded name, type, components, values.
    for (const ArrayOut& a : arrays) {
      char name[kNameBytes] = {};
      std::memcpy(name, a.name, std::min(std::strlen(a.name), kNameBytes));
      out.write(name, kNameBytes);
      put(out, a.type);
      put(out, a.components);
      out.write(a.bytes.data(), std::streamsize(a.bytes.size()));
    }
  });
}

// ---- Reading ----------------------------------------------------------------------------------

// Sequential reader that knows how many bytes are left, so no size read from the file is
// trusted (or allocated) before it is checked against the file length.
class PfrReader {
 public:
  explicit PfrReader(const std::string& path)
      : path_(path), file_(std::fopen(path.c_str(), "rb"), &std::fclose) {
    if (!file_) throw io_error_errno("read", path_, errno);
    struct stat st;
    if (::fstat(fileno(file_.get()), &st) != 0) fail_errno();
    if (!S_ISREG(st.st_mode)) fail("not a regular file");
    remaining_ = uint64_t(st.st_size);
  }

  uint64_t remaining() const { return remaining_; }

  // Reads `n` bytes of `what`; a short file is reported as truncated.
  void read(void* dst, uint64_t n, const std::string& what) {
    require(n, what);
    if (n == 0) return;
    if (std::fread(dst, 1, n, file_.get()) != n) {
      if (std::ferror(file_.get())) fail_errno();
      fail("file shrank while reading");
    }
    remaining_ -= n;
  }

  template <class T>
  T get(const std::string& what) {
    T value;
    read(&value, sizeof value, what);
    return value;
  }

  void skip(uint64_t n, const std::string& what) {
    require(n, what);
    if (::fseeko(file_.get(), off_t(n), SEEK_CUR) != 0) fail_errno();
    remaining_ -= n;
  }

  // Throws "truncated" unless `n` more bytes are there.
  void require(uint64_t n, const std::string& what) const {
    if (n > remaining_) {
      fail("truncated: " + what + " needs " + std::to_string(n) + " bytes, " + std::to_string(remaining_) +
           " left");
    }
  }

  [[noreturn]] void fail(const std::string& reason) const { throw io_error("read", path_, reason); }
  [[noreturn]] void fail_errno() const { throw io_error_errno("read", path_, errno); }

 private:
  std::string path_;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file_;
  uint64_t remaining_ = 0;
};

const char* kind_name(uint32_t kind) {
  return kind == kPfrKindRest ? "rest" : "frame";
}
const char* type_name(uint32_t type) {
  return type == kPfrFloat32 ? "float32" : "int32";
}

// An array the caller wants, and the vector its values go to.
struct ArraySpec {
  const char* name;
  uint32_t components;
  bool required;
  std::variant<std::vector<float>*, std::vector<int32_t>*> target;
  bool found = false;

  uint32_t type() const { return target.index() == 0 ? kPfrFloat32 : kPfrInt32; }
};

// Magic, version and kind; then the rest of the header.
PfrHeader read_header(PfrReader& in, uint32_t expected_kind) {
  char magic[sizeof kPfrMagic];
  in.read(magic, sizeof magic, "the magic");
  if (std::memcmp(magic, kPfrMagic, sizeof magic) != 0) in.fail("not a .pfr file (wrong magic)");
  uint32_t version = in.get<uint32_t>("the version");
  if (version != kPfrVersion) {
    in.fail("unknown version " + std::to_string(version) + " (this build reads version " +
            std::to_string(kPfrVersion) + ")");
  }
  PfrHeader h;
  h.kind = in.get<uint32_t>("the kind");
  if (h.kind != kPfrKindRest && h.kind != kPfrKindFrame) in.fail("unknown kind " + std::to_string(h.kind));
  if (h.kind != expected_kind) {
    in.fail(std::string("is a ") + kind_name(h.kind) + " file, expected a " + kind_name(expected_kind) +
            " file");
  }
  h.count = in.get<uint64_t>("the particle count");
  h.frame = in.get<int64_t>("the frame");
  h.step = in.get<int64_t>("the step");
  h.time = in.get<double>("the time");
  return h;
}

// Printable form of a name read from the file, for messages.
std::string printable(const char* raw) {
  std::string s(raw, strnlen(raw, kNameBytes));
  for (char& c : s) {
    if (c < 0x20 || c > 0x7e) c = '?';
  }
  return s;
}

// Reads one array's values into its spec's vector, after checking its type and shape.
void read_values(PfrReader& in, ArraySpec& spec, uint32_t type, uint32_t components, uint64_t values) {
  std::string what = std::string("array '") + spec.name + "'";
  if (spec.found) in.fail(what + " appears twice");
  if (type != spec.type() || components != spec.components) {
    in.fail(what + " is " + type_name(type) + " x" + std::to_string(components) + ", expected " +
            type_name(spec.type()) + " x" + std::to_string(spec.components));
  }
  spec.found = true;
  std::visit(
      [&](auto* v) {
        v->resize(values);
        in.read(v->data(), values * 4, what);
      },
      spec.target);
}

// Reads the array table: wanted arrays into their specs, unknown ones skipped.
void read_arrays(PfrReader& in, uint64_t count, std::vector<ArraySpec>& specs) {
  uint32_t n_arrays = in.get<uint32_t>("the array count");
  for (uint32_t i = 0; i < n_arrays; ++i) {
    std::string entry = "array entry " + std::to_string(i);
    char raw_name[kNameBytes];
    in.read(raw_name, kNameBytes, entry);
    std::string name = printable(raw_name);
    uint32_t type = in.get<uint32_t>(entry);
    uint32_t components = in.get<uint32_t>(entry);
    if (type != kPfrFloat32 && type != kPfrInt32) {
      in.fail("array '" + name + "' has unknown type " + std::to_string(type));
    }
    if (components == 0) in.fail("array '" + name + "' has 0 components");

    // Size check by division: count * components * 4 could overflow.
    uint64_t value_bytes = uint64_t(components) * 4;
    if (count > in.remaining() / value_bytes) {
      in.fail("truncated: array '" + name + "' needs " + std::to_string(count) + " x " +
              std::to_string(value_bytes) + " bytes, " + std::to_string(in.remaining()) + " left");
    }
    uint64_t values = count * components;
    auto spec = std::find_if(specs.begin(), specs.end(), [&](const ArraySpec& s) { return name == s.name; });
    if (spec == specs.end()) {
      in.skip(values * 4, "array '" + name + "'");
    } else {
      read_values(in, *spec, type, components, values);
    }
  }
  if (in.remaining() != 0) in.fail(std::to_string(in.remaining()) + " unexpected bytes after the last array");
  for (const ArraySpec& s : specs) {
    if (s.required && !s.found) in.fail(std::string("missing array '") + s.name + "'");
  }
}

PfrHeader read_pfr(const std::string& path, uint32_t kind, std::vector<ArraySpec> specs) {
  PfrReader in(path);
  PfrHeader h = read_header(in, kind);
  read_arrays(in, h.count, specs);
  return h;
}

}  // namespace

void write_frame_file(const std::string& path, const FrameData& f) {
  check_sizes(f);
  std::vector<float> position = to_float32(f.position), velocity = to_float32(f.velocity);
  std::vector<ArrayOut> arrays = {{"position", kPfrFloat32, 3, bytes_of(position)},
                                  {"velocity", kPfrFloat32, 3, bytes_of(velocity)},
                                  {"damage", kPfrFloat32, 1, bytes_of(f.damage)},
                                  {"body", kPfrInt32, 1, bytes_of(f.body)}};
  if (!f.component.empty()) arrays.push_back({"component", kPfrInt32, 1, bytes_of(f.component)});
  write_pfr(path, {kPfrKindFrame, f.size(), f.frame, f.step, f.time}, arrays);
}

void write_rest_file(const std::string& path, const RestData& r) {
  check_sizes(r);
  std::vector<float> position = to_float32(r.position);
  write_pfr(path, {kPfrKindRest, r.size(), 0, 0, 0},
            {{"position", kPfrFloat32, 3, bytes_of(position)},
             {"volume", kPfrFloat32, 1, bytes_of(r.volume)},
             {"body", kPfrInt32, 1, bytes_of(r.body)},
             {"material", kPfrInt32, 1, bytes_of(r.material)}});
}

namespace {

bool all_finite(const std::vector<float>& values) {
  return std::all_of(values.begin(), values.end(), [](float x) { return std::isfinite(x); });
}

}  // namespace

FrameData read_frame_file(const std::string& path) {
  FrameData f;
  std::vector<float> position, velocity;
  PfrHeader h = read_pfr(path, kPfrKindFrame,
                         {{"position", 3, true, &position},
                          {"velocity", 3, true, &velocity},
                          {"damage", 1, true, &f.damage},
                          {"body", 1, true, &f.body},
                          {"component", 1, false, &f.component}});
  for (const auto& [name, values] :
       {std::pair{"position", &position}, std::pair{"velocity", &velocity}, std::pair{"damage", &f.damage}})
    if (!all_finite(*values)) throw io_error("read", path, std::string("a ") + name + " is not finite");
  f.frame = h.frame;
  f.step = h.step;
  f.time = h.time;
  f.position = from_float32(position);
  f.velocity = from_float32(velocity);
  return f;
}

RestData read_rest_file(const std::string& path) {
  RestData r;
  std::vector<float> position;
  read_pfr(path, kPfrKindRest,
           {{"position", 3, true, &position},
            {"volume", 1, true, &r.volume},
            {"body", 1, true, &r.body},
            {"material", 1, true, &r.material}});
  if (!all_finite(position) || !all_finite(r.volume))
    throw io_error("read", path, "a position or volume is not finite");
  r.position = from_float32(position);
  return r;
}

}  // namespace pd

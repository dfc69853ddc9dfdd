#include "embedded_mesh.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "../geometry/mesh_io.h"
#include "../geometry/tri_mesh.h"
#include "../io/atomic_file.h"

namespace pd {

namespace {

// Corners of the face opposite corner k of a positively oriented tet, counter-clockwise seen from
// outside the tet.
constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

double orientation(const std::vector<Vec3d>& x, const std::array<int32_t, 4>& t) {
  return dot(cross(x[size_t(t[1])] - x[size_t(t[0])], x[size_t(t[2])] - x[size_t(t[0])]),
             x[size_t(t[3])] - x[size_t(t[0])]);
}

// Slot of the bond to j in i's family; -1 when there is none.
int64_t bond_slot(const BondsView& v, int32_t i, int32_t j) {
  for (int32_t k = 0; k < v.count[i]; ++k)
    if (bond_partner(v.neighbor[v.slot(i, k)]) == j) return v.slot(i, k);
  return -1;
}

int32_t find_root(std::vector<int32_t>& parent, int32_t i) {
  while (parent[size_t(i)] != i) i = parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
  return i;
}

}  // namespace

void EmbeddedTets::append(const TetMesh& mesh, int32_t first_particle) {
  const int32_t base = int32_t(vertices.size());
  vertices.insert(vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& c = mesh.tets[t];
    tets.push_back({base + c[0], base + c[1], base + c[2], base + c[3]});
    particle.push_back(first_particle + int32_t(t));
  }
}

size_t CrackSurface::crack_count() const {
  return size_t(std::count(crack.begin(), crack.end(), uint8_t(1)));
}

EmbeddedTetMesh::EmbeddedTetMesh(EmbeddedTets tets, const BondLists& bonds, std::vector<Vec3> rest,
                                 std::vector<real> mass)
    : tet_(std::move(tets.tets)),
      particle_(std::move(tets.particle)),
      mass_(std::move(mass)),
      previous_(std::move(rest)),
      position_(std::move(tets.vertices)) {
  const size_t nt = tet_.size(), nv = position_.size(), np = bonds.count.size();
  if (particle_.size() != nt || previous_.size() != np || mass_.size() != np)
    throw std::invalid_argument("EmbeddedTetMesh: " + std::to_string(nt) + " tets, " +
                                std::to_string(particle_.size()) + " tet particles, " + std::to_string(np) +
                                " particles in the families, " + std::to_string(previous_.size()) +
                                " positions and " + std::to_string(mass_.size()) + " masses");

  // Tets: indices in range, corners 2 and 3 swapped where the orientation is negative so that
  // kFace gives outward triangles.
  for (size_t t = 0; t < nt; ++t) {
    for (int32_t v : tet_[t])
      if (v < 0 || size_t(v) >= nv)
        throw std::invalid_argument("tet " + std::to_string(t) + " has vertex " + std::to_string(v) +
                                    " (allowed: 0.." + std::to_string(nv) + ")");
    if (particle_[t] < 0 || size_t(particle_[t]) >= np)
      throw std::invalid_argument("tet " + std::to_string(t) + " stands for particle " +
                                  std::to_string(particle_[t]) + " (allowed: 0.." + std::to_string(np) + ")");
    if (orientation(position_, tet_[t]) < 0) std::swap(tet_[t][2], tet_[t][3]);
  }

  // Interior faces: each tet face keyed by its sorted vertex triple; equal keys pair up. A key
  // found once is on the original surface, more than twice is not a tet mesh.
  struct Entry {
    std::array<int32_t, 3> key;
    int64_t corner;
    bool operator<(const Entry& o) const { return key != o.key ? key < o.key : corner < o.corner; }
  };
  std::vector<Entry> entry(4 * nt);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) {
      Entry& e = entry[4 * t + size_t(k)];
      for (int i = 0; i < 3; ++i) e.key[size_t(i)] = tet_[t][size_t(kFace[k][i])];
      std::sort(e.key.begin(), e.key.end());
      e.corner = int64_t(4 * t) + k;
    }
  std::sort(entry.begin(), entry.end());
  corner_face_.assign(4 * nt, -1);
  for (size_t i = 0; i < entry.size();) {
    size_t j = i + 1;
    while (j < entry.size() && entry[j].key == entry[i].key) ++j;
    if (j - i > 2)
      throw std::invalid_argument("a face is shared by " + std::to_string(j - i) + " tets (allowed: 2)");
    if (j - i == 2) {
      const int64_t a = entry[i].corner, b = entry[i + 1].corner;
      if (particle_[size_t(a / 4)] == particle_[size_t(b / 4)])
        throw std::invalid_argument("tets " + std::to_string(a / 4) + " and " + std::to_string(b / 4) +
                                    " share a face and stand for the same particle");
      corner_face_[size_t(a)] = corner_face_[size_t(b)] = int64_t(face_corner_.size());
      face_corner_.push_back({a, b});
    }
    i = j;
  }

  // The bond of each pair of face neighbours in both families.
  const BondsView view = bonds.view();
  face_slot_.resize(face_corner_.size());
#pragma omp parallel for schedule(static)
  for (int64_t f = 0; f < int64_t(face_corner_.size()); ++f) {
    const int32_t p = particle_[size_t(face_corner_[size_t(f)][0] / 4)];
    const int32_t q = particle_[size_t(face_corner_[size_t(f)][1] / 4)];
    face_slot_[size_t(f)] = {bond_slot(view, p, q), bond_slot(view, q, p)};
  }
  for (size_t f = 0; f < face_corner_.size(); ++f)
    if (face_slot_[f][0] < 0 || face_slot_[f][1] < 0)
      throw std::invalid_argument(
          "tets " + std::to_string(face_corner_[f][0] / 4) + " and " +
          std::to_string(face_corner_[f][1] / 4) +
          " share a face but their particles share no family bond in both directions");
  face_state_.assign(face_corner_.size(), 0);
  slots_ = bonds.neighbor.size();

  // Corners at each vertex (counting sort), and one vertex copy per vertex, used by all of them.
  incident_start_.assign(nv + 1, 0);
  for (const auto& t : tet_)
    for (int32_t v : t) ++incident_start_[size_t(v) + 1];
  std::partial_sum(incident_start_.begin(), incident_start_.end(), incident_start_.begin());
  incident_.resize(4 * nt);
  std::vector<int64_t> fill(incident_start_.begin(), incident_start_.end() - 1);
  corner_vertex_.resize(4 * nt);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) {
      const int32_t v = tet_[t][size_t(k)];
      incident_[size_t(fill[size_t(v)]++)] = int64_t(4 * t) + k;
      corner_vertex_[4 * t + size_t(k)] = v;
    }
  original_.resize(nv);
  std::iota(original_.begin(), original_.end(), 0);
  int64_t most = 0;
  for (size_t v = 0; v < nv; ++v) most = std::max(most, incident_start_[v + 1] - incident_start_[v]);
  is_dirty_.assign(nv, 0);
  local_.assign(nt, -1);
  group_parent_.resize(size_t(most));
  group_copy_.resize(size_t(most));
}

void EmbeddedTetMesh::update(const BondLists& bonds, const std::vector<Vec3>& position) {
  if (position.size() != previous_.size() || bonds.count.size() != previous_.size() ||
      bonds.neighbor.size() != slots_)
    throw std::invalid_argument("EmbeddedTetMesh::update: " + std::to_string(position.size()) +
                                " positions and families of " + std::to_string(bonds.count.size()) +
                                " particles, the mesh was built for " + std::to_string(previous_.size()));

  // Crack-face set (Chen sec. 5.2): a face between two tets joins it once their bond is broken in
  // either family, and stays (bonds never heal). Only the vertices of faces that joined now can
  // have their tets separated, so only they are examined.
  for (size_t f = 0; f < face_state_.size(); ++f) {
    if (face_state_[f] != 0) continue;
    if (bonds.neighbor[size_t(face_slot_[f][0])] >= 0 && bonds.neighbor[size_t(face_slot_[f][1])] >= 0)
      continue;
    face_state_[f] = 1;
    ++crack_faces_;
    const int64_t c = face_corner_[f][0];
    for (int i = 0; i < 3; ++i) {
      const int32_t v = tet_[size_t(c / 4)][size_t(kFace[c % 4][i])];
      if (!is_dirty_[size_t(v)]) dirty_.push_back(v);
      is_dirty_[size_t(v)] = 1;
    }
  }
  for (int32_t v : dirty_) {
    split(v);
    is_dirty_[size_t(v)] = 0;
  }
  dirty_.clear();

  // Vertex motion, eqs. 19-21: w_v = sum_p m_p / 4 and v_v = (1 / w_v) sum_p (m_p / 4) v_p over the
  // particles p of the tets that use vertex v (after splitting: the tets of its group only), and
  // x_v += dt v_v. Chen applies eq. 21 every simulation step with the particles' velocities of that
  // step; the particles themselves move by dt v_p per step, so summed over the steps of a frame
  // (the groups change only between frames) eq. 21 moves the vertex by the mass-weighted mean of
  // its particles' displacements since the last frame. That is what is applied here: exact for the
  // steps between frames, with no drift from integrating frame-sampled velocities. (Read this way,
  // a vertex moves with the centroid of its particles: a rigid translation stays rigid exactly; a
  // rigid rotation R moves a vertex by (R - I) applied to its particles' centroid, off its own
  // rotation by at most the centroid's distance, about a tet size.)
  // Each vertex copy belongs to one original vertex, so the loop over original vertices writes
  // disjoint copies.
  const int64_t nv = int64_t(original_vertex_count());
  weight_.resize(position_.size());
  shift_.resize(position_.size());
#pragma omp parallel for schedule(static)
  for (int64_t v = 0; v < nv; ++v) {
    const int64_t begin = incident_start_[size_t(v)], end = incident_start_[size_t(v) + 1];
    for (int64_t i = begin; i < end; ++i) {
      const size_t copy = size_t(corner_vertex_[size_t(incident_[size_t(i)])]);
      weight_[copy] = 0;
      shift_[copy] = {0, 0, 0};
    }
    for (int64_t i = begin; i < end; ++i) {
      const int64_t c = incident_[size_t(i)];
      const size_t copy = size_t(corner_vertex_[size_t(c)]);
      const size_t p = size_t(particle_[size_t(c / 4)]);
      const double w = 0.25 * double(mass_[p]);
      const Vec3d d{double(position[p].x) - double(previous_[p].x),
                    double(position[p].y) - double(previous_[p].y),
                    double(position[p].z) - double(previous_[p].z)};
      weight_[copy] += w;
      shift_[copy] = shift_[copy] + w * d;
    }
    for (int64_t i = begin; i < end; ++i) {
      const size_t copy = size_t(corner_vertex_[size_t(incident_[size_t(i)])]);
      if (weight_[copy] > 0) {
        position_[copy] = position_[copy] + (1 / weight_[copy]) * shift_[copy];
        weight_[copy] = 0;  // applied once
      }
    }
  }
  previous_ = position;
}

// Splits vertex v into one copy per group of its tets: tets sharing a face that is not a crack
// face are in one group (a face shared by two tets at v always contains v). Groups only refine
// from frame to frame, as crack faces are never removed from the set, so the tets of a group all
// use one copy already: the first group of a copy keeps it, the others get new copies at its
// position (several groups: several copies, Chen's "multiple copies"). Crack faces at v that now
// separate their two tets are the ones this split opened: they leave the crack-face set and
// become surface.
void EmbeddedTetMesh::split(int32_t v) {
  const int64_t begin = incident_start_[size_t(v)];
  const int32_t m = int32_t(incident_start_[size_t(v) + 1] - begin);
  for (int32_t i = 0; i < m; ++i) {
    local_[size_t(incident_[size_t(begin + i)] / 4)] = i;
    group_parent_[size_t(i)] = i;
    group_copy_[size_t(i)] = -1;
  }
  // Groups: union-find over the intact faces at v.
  for (int32_t i = 0; i < m; ++i) {
    const int64_t c = incident_[size_t(begin + i)];
    for (int j = 0; j < 4; ++j) {
      if (j == c % 4) continue;
      const int64_t f = corner_face_[size_t(c - c % 4 + j)];
      if (f < 0 || face_state_[size_t(f)] != 0) continue;
      const auto& fc = face_corner_[size_t(f)];
      const int64_t other = fc[0] / 4 == c / 4 ? fc[1] : fc[0];
      const int32_t a = find_root(group_parent_, i), b = find_root(group_parent_, local_[size_t(other / 4)]);
      if (a != b) group_parent_[size_t(std::max(a, b))] = std::min(a, b);
    }
  }
  // Copies: one per group.
  claimed_.clear();
  bool split_now = false;
  for (int32_t i = 0; i < m; ++i) {
    const int64_t c = incident_[size_t(begin + i)];
    int32_t& copy = group_copy_[size_t(find_root(group_parent_, i))];
    if (copy < 0) {
      const int32_t old = corner_vertex_[size_t(c)];
      if (std::find(claimed_.begin(), claimed_.end(), old) == claimed_.end()) {
        claimed_.push_back(old);
        copy = old;
      } else {
        copy = int32_t(position_.size());
        position_.push_back(position_[size_t(old)]);
        original_.push_back(v);
        split_now = true;
      }
    }
    corner_vertex_[size_t(c)] = copy;
  }
  // Crack faces at v that the split opened.
  if (split_now)
    for (int32_t i = 0; i < m; ++i) {
      const int64_t c = incident_[size_t(begin + i)];
      for (int j = 0; j < 4; ++j) {
        const int64_t f = j == c % 4 ? -1 : corner_face_[size_t(c - c % 4 + j)];
        if (f >= 0 && face_state_[size_t(f)] == 1 && open(f)) {
          face_state_[size_t(f)] = 2;
          ++open_faces_;
        }
      }
    }
  for (int32_t i = 0; i < m; ++i) local_[size_t(incident_[size_t(begin + i)] / 4)] = -1;
}

// True when the two tets of face f use different copies of one of its vertices.
bool EmbeddedTetMesh::open(int64_t f) const {
  const int64_t a = face_corner_[size_t(f)][0], b = face_corner_[size_t(f)][1];
  const size_t ta = size_t(a / 4), tb = size_t(b / 4);
  for (int i = 0; i < 3; ++i) {
    const int ka = kFace[a % 4][i];
    const int32_t v = tet_[ta][size_t(ka)];
    for (int kb = 0; kb < 4; ++kb)
      if (tet_[tb][size_t(kb)] == v &&
          corner_vertex_[4 * tb + size_t(kb)] != corner_vertex_[4 * ta + size_t(ka)])
        return true;
  }
  return false;
}

void EmbeddedTetMesh::surface(CrackSurface& out) const {
  out.vertices.clear();
  out.triangles.clear();
  out.crack.clear();
  // Faces of the original surface, then opened crack faces (each side as its own triangle),
  // outward from their tet; vertices numbered in order of first use.
  std::vector<int32_t> index(position_.size(), -1);
  for (uint8_t crack = 0; crack < 2; ++crack)
    for (size_t t = 0; t < tet_.size(); ++t)
      for (int k = 0; k < 4; ++k) {
        const int64_t f = corner_face_[4 * t + size_t(k)];
        if (crack ? f < 0 || face_state_[size_t(f)] != 2 : f >= 0) continue;
        std::array<int32_t, 3> tri;
        for (int i = 0; i < 3; ++i) {
          const size_t copy = size_t(corner_vertex_[4 * t + size_t(kFace[k][i])]);
          if (index[copy] < 0) {
            index[copy] = int32_t(out.vertices.size());
            out.vertices.push_back(position_[copy]);
          }
          tri[size_t(i)] = index[copy];
        }
        out.triangles.push_back(tri);
        out.crack.push_back(crack);
      }
}

CrackSurface EmbeddedTetMesh::surface() const {
  CrackSurface s;
  surface(s);
  return s;
}

std::string crack_mesh_file_name(int64_t frame, std::string_view extension) {
  char digits[32];
  std::snprintf(digits, sizeof digits, "%05lld", static_cast<long long>(frame));
  return "crack_mesh_" + std::string(digits) + "." + std::string(extension);
}

void write_crack_obj(const std::string& path, const CrackSurface& s, const std::string& comment) {
  write_file_atomic(path, [&](std::ostream& out) {
    out << "# perifrac crack mesh: " << comment
        << "\n# the original surface (g surface) and the crack surfaces (g crack), docs/fragments.md\n";
    char line[128];
    for (const Vec3d& p : s.vertices) {
      std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p[0], p[1], p[2]);
      out << line;
    }
    // The original surface, then the cracks, each under its group and material name.
    for (uint8_t crack = 0; crack < 2; ++crack) {
      out << (crack ? "g crack\nusemtl crack\n" : "g surface\nusemtl surface\n");
      for (size_t f = 0; f < s.triangles.size(); ++f) {
        if (s.crack[f] != crack) continue;
        const auto& t = s.triangles[f];
        std::snprintf(line, sizeof line, "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
        out << line;
      }
    }
  });
}

// Binary output copies floats and ints as they are in memory.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__,
              "the binary PLY writer assumes a little-endian host");

void write_crack_ply(const std::string& path, const CrackSurface& s, const std::string& comment) {
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\ncomment perifrac crack mesh: " << comment
         << "\nelement vertex " << s.vertices.size()
         << "\nproperty float x\nproperty float y\nproperty float z\nelement face " << s.triangles.size()
         << "\nproperty list uchar int vertex_indices\nproperty uchar crack\nend_header\n";
  std::string bytes = header.str();
  const size_t start = bytes.size();
  bytes.resize(start + 12 * s.vertices.size() + 14 * s.triangles.size());
  char* p = &bytes[start];
  for (const Vec3d& v : s.vertices) {
    const float x[3] = {float(v[0]), float(v[1]), float(v[2])};
    std::memcpy(p, x, 12);
    p += 12;
  }
  for (size_t f = 0; f < s.triangles.size(); ++f) {
    *p++ = char(3);
    std::memcpy(p, s.triangles[f].data(), 12);
    p += 12;
    *p++ = char(s.crack[f]);
  }
  write_file_atomic(path, bytes);
}

namespace {

CrackSurface read_crack_obj(const std::string& path, const std::string& text) {
  CrackSurface s;
  std::istringstream in(text);
  std::string line, word;
  uint8_t crack = 0;
  size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream l(line);
    auto fail = [&](const std::string& what) {
      throw MeshError(path, "line " + std::to_string(line_no) + ": " + what +
                                " (allowed: the crack mesh OBJ layout of docs/fragments.md)");
    };
    if (!(l >> word) || word[0] == '#') continue;
    if (word == "v") {
      Vec3d v;
      if (!(l >> v[0] >> v[1] >> v[2])) fail("a vertex needs 3 coordinates");
      s.vertices.push_back(v);
    } else if (word == "g" || word == "usemtl") {
      if (!(l >> word) || (word != "surface" && word != "crack")) fail("unknown group");
      crack = word == "crack";
    } else if (word == "f") {
      std::array<int32_t, 3> t;
      for (int32_t& i : t) {
        if (!(l >> i) || i < 1 || size_t(i) > s.vertices.size()) fail("bad vertex index");
        --i;
      }
      s.triangles.push_back(t);
      s.crack.push_back(crack);
    } else {
      fail("unexpected '" + detail::printable(word) + "'");
    }
  }
  return s;
}

CrackSurface read_crack_ply(const std::string& path, const std::string& bytes) {
  auto fail = [&](const std::string& what) {
    throw MeshError(path, what + " (allowed: the crack mesh PLY layout of docs/fragments.md)");
  };
  const size_t end = bytes.find("end_header\n");
  if (end == std::string::npos) fail("no end_header");
  std::istringstream header(bytes.substr(0, end));
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(header, line))
    if (line.rfind("comment", 0) != 0) lines.push_back(line);
  size_t nv = 0, nf = 0;
  if (lines.size() != 9 || lines[0] != "ply" || lines[1] != "format binary_little_endian 1.0" ||
      std::sscanf(lines[2].c_str(), "element vertex %zu", &nv) != 1 || lines[3] != "property float x" ||
      lines[4] != "property float y" || lines[5] != "property float z" ||
      std::sscanf(lines[6].c_str(), "element face %zu", &nf) != 1 ||
      lines[7] != "property list uchar int vertex_indices" || lines[8] != "property uchar crack")
    fail("unexpected header");
  const size_t start = end + std::strlen("end_header\n");
  if (bytes.size() != start + 12 * nv + 14 * nf)
    fail("the body is not " + std::to_string(nv) + " vertices and " + std::to_string(nf) + " faces long");
  CrackSurface s;
  const char* p = bytes.data() + start;
  for (size_t v = 0; v < nv; ++v, p += 12) {
    float x[3];
    std::memcpy(x, p, 12);
    s.vertices.push_back({x[0], x[1], x[2]});
  }
  for (size_t f = 0; f < nf; ++f, p += 14) {
    std::array<int32_t, 3> t;
    std::memcpy(t.data(), p + 1, 12);
    if (p[0] != 3) fail("face " + std::to_string(f) + " is not a triangle");
    for (int32_t i : t)
      if (i < 0 || size_t(i) >= nv) fail("face " + std::to_string(f) + " has vertex " + std::to_string(i));
    s.triangles.push_back(t);
    s.crack.push_back(uint8_t(p[13]));
  }
  return s;
}

}  // namespace

CrackSurface read_crack_mesh(const std::string& path) {
  const std::string bytes = detail::read_file_bytes(path);
  const std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
  if (ext == ".obj") return read_crack_obj(path, bytes);
  if (ext == ".ply") return read_crack_ply(path, bytes);
  throw MeshError(path, "unknown extension (allowed: .obj, .ply)");
}

}  // namespace pd

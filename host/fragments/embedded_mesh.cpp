#include "host/fragments/embedded_mesh.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

namespace pd {

namespace {

int32_t find_root(std::vector<int32_t>& parent, int32_t i) {
  while (parent[size_t(i)] != i) i = parent[size_t(i)] = parent[size_t(parent[size_t(i)])];
  return i;
}

// Is b in a's list (short lists, in any order: grid_adjacency keeps the families' order)?
bool adjacent(const ElementAdjacency& adj, int32_t a, int32_t b) {
  for (int64_t k = adj.offset[size_t(a)]; k < adj.offset[size_t(a) + 1]; ++k)
    if (adj.neighbor[size_t(k)] == b) return true;
  return false;
}

// at = min(at, v), atomically (threads may lower it at once).
void lower_to(int32_t& at, int32_t v) {
  int32_t seen = __atomic_load_n(&at, __ATOMIC_RELAXED);
  while (v < seen && !__atomic_compare_exchange_n(&at, &seen, v, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
  }
}

Vec3d to_vec3d(const Vec3& v) {
  return {double(v.x), double(v.y), double(v.z)};
}

}  // namespace

EmbeddedMesh::EmbeddedMesh(ElementComplex complex, const ElementAdjacency& adjacency, const BondLists& bonds,
                           std::vector<Vec3> rest, std::vector<real> mass)
    : complex_(std::move(complex)), mass_(std::move(mass)), rest_(std::move(rest)) {
  const size_t n = bonds.count.size(), ne = complex_.size(), nv = complex_.vertices.size();
  if (ne != n || rest_.size() != n || mass_.size() != n || adjacency.size() != n)
    throw std::invalid_argument("EmbeddedMesh: " + std::to_string(ne) + " elements, " + std::to_string(n) +
                                " particles in the families, " + std::to_string(rest_.size()) +
                                " positions, " + std::to_string(mass_.size()) +
                                " masses and an adjacency of " + std::to_string(adjacency.size()));
  check(complex_, n);
  for (size_t e = 0; e < ne; ++e)
    if (complex_.particle[e] != int32_t(e))
      throw std::invalid_argument("EmbeddedMesh: element " + std::to_string(e) + " stands for particle " +
                                  std::to_string(complex_.particle[e]) + " (elements in particle order)");

  // Element pairs: faces with an element across, keyed by the sorted pair; equal keys are one pair.
  std::vector<std::pair<uint64_t, int64_t>> key;  // (a << 32 | b, face)
  for (size_t e = 0; e < ne; ++e)
    for (int64_t f = complex_.face_start[e]; f < complex_.face_start[e + 1]; ++f) {
      const int32_t o = complex_.face_other[size_t(f)];
      if (o < 0) continue;
      const uint32_t a = uint32_t(std::min(int32_t(e), o)), b = uint32_t(std::max(int32_t(e), o));
      key.emplace_back(uint64_t(a) << 32 | b, f);
    }
  std::sort(key.begin(), key.end());
  face_pair_.assign(complex_.faces(), -1);
  for (size_t i = 0; i < key.size(); ++i) {
    if (i == 0 || key[i].first != key[i - 1].first)
      pair_element_.push_back({int32_t(key[i].first >> 32), int32_t(key[i].first & 0xffffffffu)});
    face_pair_[size_t(key[i].second)] = int64_t(pair_element_.size() - 1);
  }

  // What holds each pair (face_links.h); pairs that are not adjacent, or that no bond links, are
  // cracks for good.
  const int64_t np = int64_t(pair_element_.size());
  links_ = FaceLinks(pair_element_, bonds);
  pair_state_.assign(size_t(np), 0);
  for (int64_t p = 0; p < np; ++p) {
    const auto [a, b] = pair_element_[size_t(p)];
    if (!adjacent(adjacency, a, b) || !links_.linked(size_t(p))) pair_state_[size_t(p)] = 1;
  }
  slots_ = bonds.neighbor.size();

  // The pairs of each element (counting sort).
  element_pair_start_.assign(ne + 1, 0);
  for (const auto& [a, b] : pair_element_)
    ++element_pair_start_[size_t(a) + 1], ++element_pair_start_[size_t(b) + 1];
  std::partial_sum(element_pair_start_.begin(), element_pair_start_.end(), element_pair_start_.begin());
  element_pair_.resize(size_t(element_pair_start_.back()));
  {
    std::vector<int64_t> fill(element_pair_start_.begin(), element_pair_start_.end() - 1);
    for (int64_t p = 0; p < np; ++p)
      for (int32_t e : pair_element_[size_t(p)]) element_pair_[size_t(fill[size_t(e)]++)] = p;
  }

  // Corners at each vertex (counting sort), and one copy per vertex, used by all of them.
  const size_t nc = complex_.corner_vertex.size();
  corner_element_.resize(nc);
  for (size_t e = 0; e < ne; ++e)
    std::fill(corner_element_.begin() + complex_.corner_start[e],
              corner_element_.begin() + complex_.corner_start[e + 1], int32_t(e));
  incident_start_.assign(nv + 1, 0);
  for (int32_t v : complex_.corner_vertex) ++incident_start_[size_t(v) + 1];
  std::partial_sum(incident_start_.begin(), incident_start_.end(), incident_start_.begin());
  incident_.resize(nc);
  {
    std::vector<int64_t> fill(incident_start_.begin(), incident_start_.end() - 1);
    for (size_t c = 0; c < nc; ++c) incident_[size_t(fill[size_t(complex_.corner_vertex[c])]++)] = int64_t(c);
  }
  incident_element_.resize(nc);
  incident_weight_.resize(nc);
  for (size_t i = 0; i < nc; ++i) {
    const int32_t e = corner_element_[size_t(incident_[i])];
    incident_element_[i] = e;
    incident_weight_[i] = double(mass_[size_t(e)]) / complex_.corners(size_t(e));
  }
  corner_copy_ = complex_.corner_vertex;
  incident_copy_.resize(nc);
  for (size_t i = 0; i < nc; ++i) incident_copy_[i] = corner_copy_[size_t(incident_[i])];
  position_ = complex_.vertices;
  frame_.resize(nv);
  int64_t most = 0;
  for (size_t v = 0; v < nv; ++v) most = std::max(most, incident_start_[v + 1] - incident_start_[v]);
  is_dirty_.assign(nv, 0);
  local_.assign(ne, -1);
  group_parent_.resize(size_t(most));
  group_copy_.resize(size_t(most));

  // Elements around a vertex that are not joined through faces at rest (touching only along an
  // edge, or across a face that never holds) get their own copies from the start.
  for (size_t v = 0; v < nv; ++v) split(int32_t(v));
}

void EmbeddedMesh::update(const BondLists& bonds, const std::vector<Vec3>& position, const Components& c,
                          const std::vector<Fragment>& fits) {
  const size_t n = rest_.size();
  if (position.size() != n || bonds.count.size() != n || bonds.neighbor.size() != slots_ ||
      c.index.size() != n || fits.size() != c.count())
    throw std::invalid_argument("EmbeddedMesh::update: " + std::to_string(position.size()) +
                                " positions, families of " + std::to_string(bonds.count.size()) +
                                " particles, " + std::to_string(c.index.size()) + " component indices and " +
                                std::to_string(fits.size()) + " fits for " + std::to_string(c.count()) +
                                " fragments; the mesh was built for " + std::to_string(n) + " particles");

  // Crack-face set (Chen sec. 5.2): the faces of a pair join it once their bond is broken in either
  // family, and stay (bonds never heal). Only the vertices of faces that joined now can have their
  // elements separated, so only they are examined.
  // (The bond reads are scattered over the families: they run in parallel, then the few pairs that
  // cracked are taken in order.)
  const int64_t np = int64_t(pair_state_.size());
  newly_.resize(size_t(np));
#pragma omp parallel for schedule(static)
  for (int64_t p = 0; p < np; ++p)
    newly_[size_t(p)] = pair_state_[size_t(p)] == 0 && !links_.intact(size_t(p), bonds.neighbor.data());
  for (size_t p = 0; p < pair_state_.size(); ++p) {
    if (!newly_[p]) continue;
    pair_state_[p] = 1;
    ++crack_pairs_;
    for (int32_t e : pair_element_[p])
      for (int64_t f = complex_.face_start[size_t(e)]; f < complex_.face_start[size_t(e) + 1]; ++f) {
        if (face_pair_[size_t(f)] != int64_t(p)) continue;
        for (int64_t k = complex_.face_corner_start[size_t(f)]; k < complex_.face_corner_start[size_t(f) + 1];
             ++k) {
          const int32_t v = complex_.corner_vertex[size_t(complex_.face_corner[size_t(k)])];
          if (!is_dirty_[size_t(v)]) dirty_.push_back(v);
          is_dirty_[size_t(v)] = 1;
        }
      }
  }
  for (int32_t v : dirty_) {
    split(v);
    is_dirty_[size_t(v)] = 0;
  }
  dirty_.clear();

  // Vertex motion. Chen's eqs. 19-21 move a vertex with the mass-weighted mean velocity of the
  // particles of its elements (weights m_p / corners of the element, m_p / 4 for a tet); summed
  // over the steps, the vertex follows the weighted centroid c of those particles: x_v = c(t) +
  // (x_v(0) - c(0)). A piece that turns then drags each vertex off its rigidly turned place by
  // (R - I) (x_v(0) - c(0)), up to twice the distance to that centroid. Here the rest offset
  // turns with the rotation R of the vertex's fragment (its least-squares fit):
  //   x_v = c(t) + R (x_v(0) - c(0)),
  // which is exact for any rigid motion of the fragment and, for R = I, Chen's update. The
  // elements of a copy are joined through faces whose bond holds, so they lie in one fragment.
  // Each copy belongs to one original vertex, so the loop over original vertices writes disjoint
  // copies.
  const int64_t nv = int64_t(original_vertex_count());
  now_.resize(position_.size());
#pragma omp parallel
  {
    std::vector<int32_t> copies;  // the copies of one vertex
#pragma omp for schedule(static)
    for (int64_t v = 0; v < nv; ++v) {
      const int64_t begin = incident_start_[size_t(v)], end = incident_start_[size_t(v) + 1];
      copies.clear();
      for (int64_t i = begin; i < end; ++i) {
        const int32_t copy = incident_copy_[size_t(i)];
        if (std::find(copies.begin(), copies.end(), copy) != copies.end()) continue;
        copies.push_back(copy);
        now_[size_t(copy)] = {0, 0, 0};
      }
      for (int64_t i = begin; i < end; ++i) {
        Vec3d& sum = now_[size_t(incident_copy_[size_t(i)])];
        sum = sum + incident_weight_[size_t(i)] * to_vec3d(position[size_t(incident_element_[size_t(i)])]);
      }
      for (const int32_t copy : copies) {
        const CopyFrame& f = frame_[size_t(copy)];
        const Eigen::Matrix3d& r = fits[size_t(c.index[size_t(f.particle)])].fit.rotation;
        const Eigen::Vector3d turned = r * Eigen::Vector3d(f.offset[0], f.offset[1], f.offset[2]);
        position_[size_t(copy)] =
            f.inv_weight * now_[size_t(copy)] + Vec3d{turned.x(), turned.y(), turned.z()};
      }
    }
  }
}

// The rest frame of each copy of v (for update): the weighted centroid c(0) of its particles, the
// copy's offset x_v(0) - c(0), the inverse weight and one of the particles.
void EmbeddedMesh::place_at_rest(int32_t v) {
  const int64_t begin = incident_start_[size_t(v)], end = incident_start_[size_t(v) + 1];
  claimed_.clear();  // the copies of v
  for (int64_t i = begin; i < end; ++i) {
    const int32_t copy = incident_copy_[size_t(i)];
    if (std::find(claimed_.begin(), claimed_.end(), copy) != claimed_.end()) continue;
    claimed_.push_back(copy);
    frame_[size_t(copy)] = {{0, 0, 0}, 0, -1};
  }
  for (int64_t i = begin; i < end; ++i) {
    CopyFrame& f = frame_[size_t(incident_copy_[size_t(i)])];
    f.offset = f.offset + incident_weight_[size_t(i)] * to_vec3d(rest_[size_t(incident_element_[size_t(i)])]);
    f.inv_weight += incident_weight_[size_t(i)];  // the weight, until inverted below
    f.particle = incident_element_[size_t(i)];
  }
  for (const int32_t copy : claimed_) {
    CopyFrame& f = frame_[size_t(copy)];
    f.inv_weight = 1 / f.inv_weight;
    f.offset = complex_.vertices[size_t(v)] - f.inv_weight * f.offset;
  }
}

// Splits vertex v into one copy per group of its elements: elements sharing a face whose bond
// holds are in one group (two elements at v that share a face share it at v). Groups only refine
// from frame to frame, as crack faces are never removed from the set, so the elements of a group
// all use one copy already: the first group of a copy keeps it, the others get new copies at its
// position (several groups: several copies, Chen's "multiple copies"). Crack faces at v that now
// separate their two elements are the ones this split opened: they leave the crack-face set and
// become surface.
void EmbeddedMesh::split(int32_t v) {
  const int64_t begin = incident_start_[size_t(v)];
  const int32_t m = int32_t(incident_start_[size_t(v) + 1] - begin);
  for (int32_t i = 0; i < m; ++i) {
    local_[size_t(corner_element_[size_t(incident_[size_t(begin + i)])])] = i;
    group_parent_[size_t(i)] = i;
    group_copy_[size_t(i)] = -1;
  }
  // Groups: union-find over the holding pairs at v.
  for (int32_t i = 0; i < m; ++i) {
    const size_t e = size_t(corner_element_[size_t(incident_[size_t(begin + i)])]);
    for (int64_t k = element_pair_start_[e]; k < element_pair_start_[e + 1]; ++k) {
      const int64_t p = element_pair_[size_t(k)];
      if (pair_state_[size_t(p)] != 0) continue;
      const auto& pe = pair_element_[size_t(p)];
      const int32_t other = pe[0] == int32_t(e) ? pe[1] : pe[0];
      const int32_t j = local_[size_t(other)];
      if (j < 0) continue;
      const int32_t a = find_root(group_parent_, i), b = find_root(group_parent_, j);
      if (a != b) group_parent_[size_t(std::max(a, b))] = std::min(a, b);
    }
  }
  // Copies: one per group.
  claimed_.clear();
  bool split_now = false;
  for (int32_t i = 0; i < m; ++i) {
    const int64_t corner = incident_[size_t(begin + i)];
    int32_t& copy = group_copy_[size_t(find_root(group_parent_, i))];
    if (copy < 0) {
      const int32_t old = corner_copy_[size_t(corner)];
      if (std::find(claimed_.begin(), claimed_.end(), old) == claimed_.end()) {
        claimed_.push_back(old);
        copy = old;
      } else {
        copy = int32_t(position_.size());
        position_.push_back(position_[size_t(old)]);
        frame_.push_back(frame_[size_t(old)]);
        split_now = true;
      }
    }
    corner_copy_[size_t(corner)] = copy;
    incident_copy_[size_t(begin + i)] = copy;
  }
  // Crack faces at v that the split opened: both elements at v, now on different copies of it.
  // (Copies change only here, so a face is checked whenever one of its vertices splits.)
  if (split_now)
    for (int32_t i = 0; i < m; ++i) {
      const size_t e = size_t(corner_element_[size_t(incident_[size_t(begin + i)])]);
      for (int64_t k = element_pair_start_[e]; k < element_pair_start_[e + 1]; ++k) {
        const int64_t p = element_pair_[size_t(k)];
        if (pair_state_[size_t(p)] != 1) continue;
        const auto& pe = pair_element_[size_t(p)];
        const int32_t j = local_[size_t(pe[0] == int32_t(e) ? pe[1] : pe[0])];
        if (j < 0 || incident_copy_[size_t(begin + i)] == incident_copy_[size_t(begin + j)]) continue;
        pair_state_[size_t(p)] = 2;
        ++open_pairs_;
      }
    }
  for (int32_t i = 0; i < m; ++i) local_[size_t(corner_element_[size_t(incident_[size_t(begin + i)])])] = -1;
  place_at_rest(v);
}

void EmbeddedMesh::surface(CrackSurface& out) const {
  // Faces on the object's surface, then opened crack faces (each side as its own polygon), outward
  // from their element, as fans owned by the element's particle; vertices numbered in order of
  // first use. (Faces are stored element by element, so the walk over elements is the walk over
  // faces.) The walk runs in parallel over blocks of elements, in four passes that give the serial
  // walk's surface: (1) each block counts its triangles, whose running sum places them; (2) each
  // block writes its triangles with the copies' own numbers and marks, per copy, the first block
  // that uses it; (3) each block numbers the copies it uses first, in the order it meets them, and
  // the blocks' counts in order give the numbers' bases; (4) the triangles are renumbered.
  constexpr size_t kBlock = 1024;  // elements
  const size_t ne = complex_.size(), blocks = (ne + kBlock - 1) / kBlock, units = 2 * blocks;
  // Unit u walks block u % blocks for the original surface (u < blocks) or the opened cracks.
  const auto drawn = [&](size_t u, size_t f) {
    const int64_t p = face_pair_[f];
    return u >= blocks ? p >= 0 && pair_state_[size_t(p)] == 2 : p < 0;
  };
  const auto faces_of = [&](size_t u, auto&& visit) {
    const size_t first = (u % blocks) * kBlock, last = std::min(ne, first + kBlock);
    for (size_t e = first; e < last; ++e)
      for (size_t f = size_t(complex_.face_start[e]); f < size_t(complex_.face_start[e + 1]); ++f)
        if (drawn(u, f)) visit(e, f);
  };
  std::vector<size_t> placed(units + 1, 0);  // (1) each unit's first triangle
#pragma omp parallel for schedule(dynamic, 4)
  for (size_t u = 0; u < units; ++u)
    faces_of(u, [&](size_t, size_t f) {
      placed[u + 1] += size_t(complex_.face_corner_start[f + 1] - complex_.face_corner_start[f] - 2);
    });
  std::partial_sum(placed.begin(), placed.end(), placed.begin());
  const size_t nt = placed[units];
  out.triangles.resize(nt);
  out.crack.resize(nt);
  out.particle.resize(nt);

  // (2) Triangles in copies; each copy's first unit (an atomic minimum).
  std::vector<int32_t> first_unit(position_.size(), std::numeric_limits<int32_t>::max());
#pragma omp parallel for schedule(dynamic, 4)
  for (size_t u = 0; u < units; ++u) {
    size_t t = placed[u];
    const auto use = [&](int64_t corner) {
      const int32_t copy = corner_copy_[size_t(corner)];
      lower_to(first_unit[size_t(copy)], int32_t(u));
      return copy;
    };
    faces_of(u, [&](size_t e, size_t f) {
      const int64_t b = complex_.face_corner_start[f], end = complex_.face_corner_start[f + 1];
      const int32_t first = use(complex_.face_corner[size_t(b)]);
      for (int64_t k = b + 1; k + 1 < end; ++k, ++t) {
        out.triangles[t] = {first, use(complex_.face_corner[size_t(k)]),
                            use(complex_.face_corner[size_t(k + 1)])};
        out.crack[t] = uint8_t(u >= blocks);
        out.particle[t] = complex_.particle[e];
      }
    });
  }

  // (3) Each unit numbers the copies it uses first, in the order of its triangles' corners (the
  // order the serial walk meets them), as -2 - its number until the unit's base is known; only that
  // unit writes those copies' entries (-1: not numbered yet).
  std::vector<int32_t> number(position_.size(), -1);
  std::vector<size_t> numbered(units + 1, 0);
#pragma omp parallel for schedule(dynamic, 4)
  for (size_t u = 0; u < units; ++u)
    for (size_t t = placed[u]; t < placed[u + 1]; ++t)
      for (const int32_t copy : out.triangles[t])
        if (first_unit[size_t(copy)] == int32_t(u) && number[size_t(copy)] == -1)
          number[size_t(copy)] = -2 - int32_t(numbered[u + 1]++);
  std::partial_sum(numbered.begin(), numbered.end(), numbered.begin());
  out.vertices.resize(numbered[units]);
  // (4) The bases added and the vertices placed, then the triangles renumbered.
#pragma omp parallel for schedule(dynamic, 4)
  for (size_t u = 0; u < units; ++u)
    for (size_t t = placed[u]; t < placed[u + 1]; ++t)
      for (const int32_t copy : out.triangles[t])
        if (int32_t& n = number[size_t(copy)]; first_unit[size_t(copy)] == int32_t(u) && n < -1) {
          n = int32_t(numbered[u]) - 2 - n;
          out.vertices[size_t(n)] = position_[size_t(copy)];
        }
#pragma omp parallel for schedule(static)
  for (size_t t = 0; t < nt; ++t)
    for (int32_t& v : out.triangles[t]) v = number[size_t(v)];
}

CrackSurface EmbeddedMesh::surface() const {
  CrackSurface s;
  surface(s);
  return s;
}

}  // namespace pd

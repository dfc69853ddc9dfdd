// Kernel 3 body: Levine eq. 6 quadratic repulsion.
#include <gtest/gtest.h>

#include <limits>

#include <algorithm>
#include <set>
#include <vector>

#include "cuda/kernels/collisions.h"
#include "host/geometry/random.h"

namespace pd {
namespace {

TEST(Collisions, QuadraticRepulsionBelowTheContactDistance) {
  const real rc = real(0.5e-3), kc = real(1e8);
  const Vec3 f = contact_force({real(0.3e-3), 0, 0}, {0, 0, 0}, rc, kc);
  EXPECT_NEAR(f.x, 1e8 * 0.2e-3 * 0.2e-3, 1e-5 * 4);  // K_c (d - rc)^2, pushing i away from j
  EXPECT_EQ(f.y, 0);
  const Vec3 g = contact_force({0, 0, 0}, {real(0.3e-3), 0, 0}, rc, kc);
  EXPECT_FLOAT_EQ(g.x, -f.x);
}

TEST(Collisions, NoForceAtOrBeyondTheContactDistance) {
  EXPECT_EQ(contact_force({real(1e-3), 0, 0}, {0, 0, 0}, real(1e-3), real(1e8)).x, 0);
  EXPECT_EQ(contact_force({real(2e-3), 0, 0}, {0, 0, 0}, real(1e-3), real(1e8)).x, 0);
  EXPECT_EQ(contact_force({0, 0, 0}, {0, 0, 0}, real(1e-3), real(1e8)).x, 0);  // coincident: no direction
}

// The 8-cell search over the sorted records finds every point within half a cell side, like the
// 27-cell search the family build uses, once each; what it visits beyond those 27 cells (bins
// shared with far cells) lies farther than half a cell side.
TEST(Collisions, HalfCellSearchFindsEveryCloseNeighbour) {
  Random rng(17);
  std::vector<Vec3> pts(3000);
  for (auto& p : pts)
    p = {real(rng.uniform() * 2 - 1), real(rng.uniform() * 2 - 1), real(rng.uniform() * 2 - 1)};
  const real cell = real(0.1);
  // Hash by sorting (bin, id), as the engine does.
  HashView h;
  h.bins = 1 << 12;
  h.inv_cell = real(1) / cell;
  std::vector<uint32_t> key(pts.size());
  std::vector<int32_t> sorted(pts.size()), start(h.bins, -1), end(h.bins, -1);
  for (size_t i = 0; i < pts.size(); ++i) key[i] = cell_bin(cell_of(pts[i], h.inv_cell), h.bins);
  for (size_t i = 0; i < pts.size(); ++i) sorted[i] = int32_t(i);
  std::stable_sort(sorted.begin(), sorted.end(), [&](int32_t a, int32_t b) { return key[a] < key[b]; });
  std::vector<uint32_t> sorted_key(pts.size());
  for (size_t s = 0; s < pts.size(); ++s) sorted_key[s] = key[sorted[s]];
  h.key = view_of(sorted_key);
  h.sorted = view_of(sorted);
  h.bin_start = view_of(start);
  h.bin_end = view_of(end);
  for (int32_t s = 0; s < int32_t(pts.size()); ++s) mark_bin_bounds(s, int32_t(pts.size()), h);
  // The sorted records the collisions kernel reads (w: a tag to check the entry).
  std::vector<Vec4> record(pts.size());
  for (size_t s = 0; s < pts.size(); ++s) record[s] = with_w(pts[size_t(sorted[s])], real(sorted[s]));
  h.record = view_of(record);
  auto pos = [&](int32_t j) { return pts[j]; };
  for (size_t i = 0; i < pts.size(); i += 7) {
    std::set<int32_t> from_records, nearby, brute;
    for_each_record_within_half_cell(pts[i], h, [&](int32_t s, Vec4 r) {
      EXPECT_EQ(int32_t(r.w), sorted[size_t(s)]);
      EXPECT_TRUE(from_records.insert(sorted[size_t(s)]).second) << "visited twice";
    });
    for_each_nearby(pts[i], h, pos, [&](int32_t j) { nearby.insert(j); });
    for (size_t j = 0; j < pts.size(); ++j)
      if (length(pts[j] - pts[i]) < real(0.5) * cell) brute.insert(int32_t(j));
    for (int32_t j : brute) EXPECT_TRUE(from_records.count(j)) << i << " misses " << j;
    for (int32_t j : from_records)
      EXPECT_TRUE(nearby.count(j) || length(pts[size_t(j)] - pts[i]) > real(0.5) * cell)
          << i << " visits " << j;
  }
}

// The contact lists of a random cloud, a third of it moving fast (cells twice the reach of two
// particles at rest, as the engine sizes them): each list is every other point within the
// pair's contact distance plus both skins, in ascending order; the lists are symmetric; each
// particle's origin holds its displacement and its skin.
TEST(Collisions, ContactListsHoldEveryPairWithinReachInOrder) {
  Random rng(23);
  const int32_t n = 2000;
  MaterialTable mt;
  mt.count = 2;
  mt.m[0].contact_spacing = real(0.08);  // two contact spacings: quarters 0.02 and 0.01
  mt.m[1].contact_spacing = real(0.04);
  const real quarter_max = real(0.02), rc = real(0.04);
  std::vector<Vec4> rest(static_cast<size_t>(n)), disp(static_cast<size_t>(n));
  std::vector<Vec3> vel(static_cast<size_t>(n), Vec3{0, 0, 0});
  std::vector<uint16_t> material(static_cast<size_t>(n));
  for (int32_t i = 0; i < n; ++i) {
    rest[size_t(i)] = {real(rng.uniform()), real(rng.uniform()), real(rng.uniform()), real(1e-6)};
    disp[size_t(i)] = {real(0.01 * rng.normal()), real(0.01 * rng.normal()), real(0.01 * rng.normal()), 0};
    material[size_t(i)] = uint16_t(rng.uniform() < 0.5 ? 0 : 1);
    if (rng.uniform() < 1.0 / 3)
      vel[size_t(i)] = {real(rng.normal()), real(rng.normal()), real(rng.normal())};
  }
  ParticlesView p;
  p.n = n;
  p.rest = view_of(rest);
  p.disp = view_of(disp);
  p.vel = view_of(vel);
  p.material = view_of(material);
  ContactView c;
  c.n = n;
  c.base = real(kContactRestSkin) * rc;
  c.cap = real(kContactSkinCap) * rc;
  c.per_speed = real(0.02);  // skins up to the cap for speeds above ~3

  HashView h;
  h.bins = 1 << 12;
  h.inv_cell = real(1) / (2 * (rc + 2 * c.base));
  std::vector<uint32_t> key(static_cast<size_t>(n)), sorted_key(static_cast<size_t>(n));
  std::vector<int32_t> sorted(static_cast<size_t>(n)), start(h.bins, -1), end(h.bins, -1);
  for (int32_t i = 0; i < n; ++i) key[size_t(i)] = cell_bin(cell_of(p.position(i), h.inv_cell), h.bins);
  for (int32_t i = 0; i < n; ++i) sorted[size_t(i)] = i;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [&](int32_t a, int32_t b) { return key[size_t(a)] < key[size_t(b)]; });
  std::vector<Vec4> record(static_cast<size_t>(n));
  for (int32_t s = 0; s < n; ++s) {
    const int32_t i = sorted[size_t(s)];
    sorted_key[size_t(s)] = key[size_t(i)];
    record[size_t(s)] = with_w(p.position(i), contact_quarter(i, p, mt));  // as `collection` writes it
  }
  h.key = view_of(sorted_key);
  h.sorted = view_of(sorted);
  h.bin_start = view_of(start);
  h.bin_end = view_of(end);
  h.record = view_of(record);
  for (int32_t s = 0; s < n; ++s) mark_bin_bounds(s, n, h);

  std::vector<Vec4> origin(static_cast<size_t>(n));
  std::vector<int32_t> count(static_cast<size_t>(n));
  c.origin = view_of(origin);
  c.count = view_of(count);
  std::vector<int32_t> partner;
  // Room for 4 partners overflows in this cloud; room for 64 does not.
  for (const int32_t capacity : {4, 64}) {
    c.capacity = capacity;
    partner.assign(size_t(capacity) * size_t(n), -1);
    c.partner = view_of(partner);
    int32_t overflow = 0, pairs = 0;
    for (int32_t s = 0; s < n; ++s) build_contacts(s, p, h, c, &overflow, &pairs);
    for (int32_t i = 0; i < n; ++i) extend_contacts(i, p, h, c, mt, quarter_max, &overflow, &pairs);
    for (int32_t i = 0; i < n; ++i) sort_contacts(i, p, c);
    EXPECT_EQ(overflow, capacity == 4 ? 1 : 0) << "room for " << capacity;
    EXPECT_EQ(pairs, 1);
  }
  auto list_of = [&](int32_t i) {
    std::vector<int32_t> list;
    for (int32_t k = 0; k < count[size_t(i)]; ++k) list.push_back(partner[size_t(c.slot(i, k))]);
    return list;
  };

  int64_t pairs = 0, fast_pairs = 0;
  for (int32_t i = 0; i < n; ++i) {
    const Vec4 ri = with_w(p.position(i), contact_quarter(i, p, mt));
    const real skin_i = contact_skin(vel[size_t(i)], c);
    std::vector<int32_t> brute;
    for (int32_t j = 0; j < n; ++j) {
      const Vec4 rj = with_w(p.position(j), contact_quarter(j, p, mt));
      if (j != i && within_contact_reach(ri, rj, skin_i + contact_skin(vel[size_t(j)], c)))
        brute.push_back(j);
      if (j != i && within_contact_reach(ri, rj, skin_i + contact_skin(vel[size_t(j)], c)) &&
          !within_contact_reach(ri, rj, 2 * c.base))
        ++fast_pairs;
    }
    const std::vector<int32_t> list = list_of(i);
    EXPECT_EQ(list, brute) << "particle " << i;
    for (int32_t j : list) {
      const std::vector<int32_t> back = list_of(j);
      EXPECT_TRUE(std::binary_search(back.begin(), back.end(), i));
    }
    EXPECT_EQ(origin[size_t(i)].x, disp[size_t(i)].x);
    EXPECT_EQ(origin[size_t(i)].w, skin_i);
    pairs += int64_t(list.size());
  }
  EXPECT_GT(pairs, n);           // the cloud is dense enough that most points have partners
  EXPECT_GT(fast_pairs, n / 4);  // and the second pass finds many
}

// A particle leaves its skin past kContactTrigger of it, in any direction; a non-finite
// displacement counts as having left. In a moving frame (contact_frame.h) the distance is taken
// after the frame's shift: a particle that moved with the frame has not left, one that stayed
// behind has.
TEST(Collisions, LeavingTheSkinIsDetected) {
  const real skin = real(1e-4 / kContactTrigger);  // moves up to 1e-4 keep the lists
  const Vec4 origin{real(1e-3), real(-2e-3), 0, skin};
  const Vec3 still{0, 0, 0};
  EXPECT_FALSE(left_contact_skin(origin, origin, still));
  EXPECT_FALSE(left_contact_skin({real(1e-3 + 0.9e-4), real(-2e-3), 0, 0}, origin, still));
  EXPECT_TRUE(left_contact_skin({real(1e-3), real(-2e-3 - 1.1e-4), 0, 0}, origin, still));
  EXPECT_TRUE(left_contact_skin({real(1e-3 + 0.6e-4), real(-2e-3), real(0.9e-4), 0}, origin, still));
  EXPECT_TRUE(left_contact_skin({std::numeric_limits<real>::quiet_NaN(), 0, 0, 0}, origin, still));
  const Vec3 shift{0, real(-5e-3), 0};
  EXPECT_FALSE(left_contact_skin({real(1e-3 + 0.9e-4), real(-7e-3), 0, 0}, origin, shift));
  EXPECT_TRUE(left_contact_skin(origin, origin, shift));
}

// A particle's skin: the rest skin up to the speed that covers it, then proportional to the
// speed, then the cap.
TEST(Collisions, SkinGrowsWithSpeedUpToTheCap) {
  ContactView c;
  c.base = real(1e-4);
  c.per_speed = real(1e-5);
  c.cap = real(4e-4);
  EXPECT_EQ(contact_skin({0, 0, 0}, c), c.base);
  EXPECT_EQ(contact_skin({real(5), 0, 0}, c), c.base);
  EXPECT_FLOAT_EQ(contact_skin({0, real(-20), 0}, c), real(2e-4));
  EXPECT_EQ(contact_skin({real(300), 0, 0}, c), c.cap);
  c.frame_velocity = {0, real(-20), 0};  // the speed relative to the lists' frame counts
  EXPECT_EQ(contact_skin({0, real(-20), 0}, c), c.base);
  EXPECT_FLOAT_EQ(contact_skin({0, 0, 0}, c), real(2e-4));
}

// A block of 4 x 4 x 4 cells, wherever it lies (negative coordinates too), fills 64 consecutive
// bins in Morton order; its neighbouring block starts elsewhere.
TEST(Collisions, CellBinsKeepBlocksOfCellsTogether) {
  const uint32_t bins = 1u << 16;
  for (const Cell origin : {Cell{0, 0, 0}, Cell{-8, 12, -4}, Cell{400, -4000, 36}}) {
    const uint32_t first = cell_bin(origin, bins);
    EXPECT_EQ(first % 64, 0u);
    std::set<uint32_t> seen;
    for (int z = 0; z < 4; ++z)
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
          const uint32_t b = cell_bin({origin.x + x, origin.y + y, origin.z + z}, bins);
          EXPECT_EQ(b - first, uint32_t(x & 1) | uint32_t(y & 1) << 1 | uint32_t(z & 1) << 2 |
                                   uint32_t(x >> 1) << 3 | uint32_t(y >> 1) << 4 | uint32_t(z >> 1) << 5);
          seen.insert(b);
        }
    EXPECT_EQ(seen.size(), 64u);
    EXPECT_NE(cell_bin({origin.x + 4, origin.y, origin.z}, bins), first + 64);
  }
}

// Runaway positions (a blow-up in progress) map to valid cells whose neighbours do not overflow.
TEST(Collisions, CellOfARunawayPositionIsClamped) {
  const real inf = std::numeric_limits<real>::infinity();
  for (real v : {real(1e30), real(-1e30), inf, -inf, std::numeric_limits<real>::quiet_NaN()}) {
    const int32_t c = cell_coord(v, real(1e3));
    EXPECT_LE(c, 1 << 30) << v;
    EXPECT_GE(c, -(1 << 30)) << v;
  }
  EXPECT_EQ(cell_coord(real(2.5e-3), real(1e3)), 2);
  EXPECT_EQ(cell_coord(real(-0.5e-3), real(1e3)), -1);
}

}  // namespace
}  // namespace pd

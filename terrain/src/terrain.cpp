// The soil grid and its per-step pipeline. See terrain.h for the model; the choices made
// where Sumner et al. leave room are written next to the code that makes them.

#include "shore/terrain/terrain.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <unordered_map>
#include <utility>

#include "shore/core/det_math.h"
#include "shore/core/error.h"
#include "shore/core/hash.h"
#include "shore/terrain/bekker.h"
#include "terrain_impl.h"

namespace shore::terrain {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

// 8-neighbour directions, arranged so the opposite of direction d is d ^ 1.
constexpr int kDx[8] = {1, -1, 0, 0, 1, -1, 1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, -1, 1};

}  // namespace

// ---- settings ------------------------------------------------------------------------

void TerrainSettings::validate() const {
  const Check c{"terrain.TerrainSettings"};
  c.positive("cell", cell);
  c.finite("origin_x", origin_x);
  c.finite("origin_y", origin_y);
  if (!(tile_columns >= 4 && tile_columns <= 1024))
    throw InvalidSetting(c.name("tile_columns"), detail::to_text(tile_columns), "must be in [4, 1024]");
  material.validate();
  c.finite("base_height", base_height);
  c.at_least("max_erosion_passes", max_erosion_passes, 0);
  c.at_least("active_margin", active_margin, 1);
  if (!(active_reach > 0.0))  // +infinity allowed: every covered column widens the region
    throw InvalidSetting(c.name("active_reach"), detail::to_text(active_reach), "must be > 0 (+infinity allowed)");
  c.non_negative("contact_tolerance", contact_tolerance);
  c.at_least("threads", threads, 0);
  c.at_least("parallel_min_columns", parallel_min_columns, 0);
}

// ---- tiles ---------------------------------------------------------------------------

Tile::Tile(int n) : height(static_cast<std::size_t>(n) * n), sinkage(height.size(), 0.0), base(height.size()) {}

void Tile::mark_dirty(int li0, int lj0, int li1, int lj1) {
  if (!dirty) {
    dirty = true;
    di0 = li0, dj0 = lj0, di1 = li1, dj1 = lj1;
    return;
  }
  di0 = std::min(di0, li0), dj0 = std::min(dj0, lj0);
  di1 = std::max(di1, li1), dj1 = std::max(dj1, lj1);
}

Terrain::Impl::Impl(TerrainSettings settings) : s(std::move(settings)) {
  s.validate();
  n = s.tile_columns;
  cell_area = s.cell * s.cell;
}

double Terrain::Impl::base_at(std::int64_t i, std::int64_t j) const {
  if (!s.base) return s.base_height;
  return s.base->height(s.origin_x + static_cast<double>(i) * s.cell, s.origin_y + static_cast<double>(j) * s.cell);
}

const Tile* Terrain::Impl::find(TileKey key) const {
  const auto it = tiles.find(key);
  return it == tiles.end() ? nullptr : it->second.get();
}

Tile& Terrain::Impl::tile(TileKey key) {
  auto& slot = tiles[key];
  if (!slot) {
    slot = std::make_unique<Tile>(n);
    // Untouched ground is the base source; sample it once, when the tile is created.
    for (int lj = 0; lj < n; ++lj)
      for (int li = 0; li < n; ++li) {
        const double b = base_at(key.tx * n + li, key.ty * n + lj);
        const std::size_t k = static_cast<std::size_t>(lj) * n + li;
        slot->base[k] = b;
        slot->height[k] = b;
      }
  }
  return *slot;
}

TileKey Terrain::Impl::key_of(std::int64_t i, std::int64_t j) const { return {floor_div(i, n), floor_div(j, n)}; }

std::size_t Terrain::Impl::local(std::int64_t i, std::int64_t j) const {
  return static_cast<std::size_t>((j - floor_div(j, n) * n) * n + (i - floor_div(i, n) * n));
}

std::vector<TileKey> Terrain::Impl::sorted_keys() const {
  std::vector<TileKey> keys;
  keys.reserve(tiles.size());
  for (const auto& [key, tile] : tiles) keys.push_back(key);
  std::sort(keys.begin(), keys.end());
  return keys;
}

int Terrain::Impl::thread_count() const { return s.threads > 0 ? s.threads : omp_get_max_threads(); }

// Calls fn(tile, li, lj, sx, sy, count) for every row piece of the rectangle
// [i0, i0 + w) x [j0, j0 + h) that falls in one tile, creating tiles as needed; (sx, sy)
// is the piece's position in the rectangle.
template <class Fn>
void Terrain::Impl::for_each_piece(std::int64_t i0, std::int64_t j0, int w, int h, Fn&& fn) {
  const std::int64_t tx0 = floor_div(i0, n), tx1 = floor_div(i0 + w - 1, n);
  const std::int64_t ty0 = floor_div(j0, n), ty1 = floor_div(j0 + h - 1, n);
  for (std::int64_t ty = ty0; ty <= ty1; ++ty)
    for (std::int64_t tx = tx0; tx <= tx1; ++tx) {
      Tile& t = tile({tx, ty});
      const std::int64_t ci0 = std::max(i0, tx * n), ci1 = std::min(i0 + w, (tx + 1) * n);
      const std::int64_t cj0 = std::max(j0, ty * n), cj1 = std::min(j0 + h, (ty + 1) * n);
      for (std::int64_t j = cj0; j < cj1; ++j)
        fn(t, static_cast<int>(ci0 - tx * n), static_cast<int>(j - ty * n), static_cast<int>(ci0 - i0),
           static_cast<int>(j - j0), static_cast<int>(ci1 - ci0));
    }
}

// ---- scratch: the active region gathered into dense arrays --------------------------

void Scratch::resize(std::int64_t i0, std::int64_t j0, int width, int height) {
  si0 = i0, sj0 = j0, w = width, h = height;
  const std::size_t size = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  // Every stage writes these before it reads them (gather, rasterize, collide, erode), so
  // they are only sized here, not cleared: clearing 14 arrays each step cost more than
  // the rest of a small step's bookkeeping.
  for (auto* v :
       {&ht, &ht_orig, &sink, &bed, &e_plain, &e_star, &e_coll, &e_true, &e_hold, &disp, &carry, &q, &out, &cap})
    v->resize(size);
  flags.assign(size, 0);  // the halo's flags stay 0: it is neither interior nor covered
  mask.resize(size);
  cover.resize(size);
  contour.resize(size);
}

void Terrain::Impl::gather(Scratch& sc) {
  for_each_piece(sc.si0, sc.sj0, sc.w, sc.h, [&](Tile& t, int li, int lj, int sx, int sy, int count) {
    const std::size_t src = static_cast<std::size_t>(lj) * n + li;
    const std::size_t dst = sc.at(sx, sy);
    std::memcpy(&sc.ht[dst], &t.height[src], sizeof(double) * count);
    std::memcpy(&sc.sink[dst], &t.sinkage[src], sizeof(double) * count);
    for (int k = 0; k < count; ++k) sc.bed[dst + k] = t.base[src + k] - s.material.soil_depth;
  });
  sc.ht_orig = sc.ht;
}

void Terrain::Impl::scatter(const Scratch& sc) {
  for_each_piece(sc.si0, sc.sj0, sc.w, sc.h, [&](Tile& t, int li, int lj, int sx, int sy, int count) {
    const std::size_t src = sc.at(sx, sy);
    const std::size_t dst = static_cast<std::size_t>(lj) * n + li;
    int first = -1, last = -1;
    for (int k = 0; k < count; ++k)
      if (sc.ht[src + k] != sc.ht_orig[src + k]) {
        if (first < 0) first = k;
        last = k;
      }
    std::memcpy(&t.height[dst], &sc.ht[src], sizeof(double) * count);
    std::memcpy(&t.sinkage[dst], &sc.sink[src], sizeof(double) * count);
    if (first >= 0) {
      if (!t.dirty) dirty_keys.push_back(key_of(sc.si0 + sx + first, sc.sj0 + sy));
      t.mark_dirty(li + first, lj, li + last, lj);
    }
  });
}

// ---- the pipeline on one region ------------------------------------------------------

namespace {

template <class Fn>
void for_rows(int first, int last, bool parallel, int threads, Fn&& fn) {
#pragma omp parallel for schedule(static) num_threads(threads) if (parallel)
  for (int y = first; y < last; ++y) fn(y);
}

// The lowest (highest) of the 8 neighbours of *p in rows of w, as a balanced tree: min and
// max are exact, so the order does not change the value, only the dependency chain.
template <class Pick>
double neighbour_extreme(const double* p, std::ptrdiff_t w, Pick pick) {
  const double a = pick(p[-1], p[1]), b = pick(p[-w], p[w]);
  const double c = pick(p[-w - 1], p[w + 1]), d = pick(p[-w + 1], p[w - 1]);
  return pick(pick(a, b), pick(c, d));
}

// to = from grown by one column in each of the 8 directions.
void dilate(const ColumnBits& from, ColumnBits& to) {
  to.reset(from.w, from.h);
  const int words = from.words;
  for (int y = 0; y < from.h; ++y) {
    const std::uint64_t* mid = from.row(y);
    const std::uint64_t* up = y > 0 ? from.row(y - 1) : nullptr;
    const std::uint64_t* down = y + 1 < from.h ? from.row(y + 1) : nullptr;
    std::uint64_t* t = to.row(y);
    for (int i = 0; i < words; ++i) t[i] = mid[i] | (up ? up[i] : 0) | (down ? down[i] : 0);
    std::uint64_t prev = 0;
    for (int i = 0; i < words; ++i) {
      const std::uint64_t cur = t[i], next = i + 1 < words ? t[i + 1] : 0;
      t[i] = cur | (cur << 1) | (prev >> 63) | (cur >> 1) | (next << 63);
      prev = cur;
    }
    t[words - 1] &= from.tail_mask();
  }
}

}  // namespace

// Rasterizes the imprints into the region: e_plain / e_star hold the lowest (offset)
// envelope of plain and star pressing imprints; e_true the lowest of both (soil state);
// e_coll the collision surface (star imprints lowered to their lowest point within +-1
// column); e_hold the lowest envelope of holding imprints (they press nothing).
void Terrain::Impl::rasterize(Scratch& sc, std::span<const Imprint> imprints) const {
  std::fill(sc.e_plain.begin(), sc.e_plain.end(), kInf);
  std::fill(sc.e_star.begin(), sc.e_star.end(), kInf);
  std::fill(sc.e_hold.begin(), sc.e_hold.end(), kInf);
  bool any_star = false;
  for (const Imprint& im : imprints) {
    const EnvelopeRaster& env = *im.envelope;
    const std::int64_t x0 = std::max(env.i0, sc.si0), x1 = std::min(env.i0 + env.nx, sc.si0 + sc.w);
    const std::int64_t y0 = std::max(env.j0, sc.sj0), y1 = std::min(env.j0 + env.ny, sc.sj0 + sc.h);
    std::vector<double>& dst = im.hold ? sc.e_hold : im.star ? sc.e_star : sc.e_plain;
    any_star = any_star || (im.star && !im.hold);
    for (std::int64_t j = y0; j < y1; ++j)
      for (std::int64_t i = x0; i < x1; ++i) {
        const double lower = env.lower[env.index(i, j)];
        if (lower == kInf) continue;
        double& e = dst[sc.at(static_cast<int>(i - sc.si0), static_cast<int>(j - sc.sj0))];
        e = std::min(e, lower - im.offset);
      }
  }
  for (std::size_t k = 0; k < sc.e_true.size(); ++k) sc.e_true[k] = std::min(sc.e_plain[k], sc.e_star[k]);
  if (!any_star) {
    sc.e_coll = sc.e_true;
    return;
  }
  // Lowest star envelope over each 3 x 3 neighbourhood (clipped to the scratch): the
  // minimum along x into e_coll, then along y, then the plain envelope.
  const int w = sc.w, h = sc.h;
  for (int y = 0; y < h; ++y) {
    const double* e = &sc.e_star[sc.at(0, y)];
    double* row = &sc.e_coll[sc.at(0, y)];
    for (int x = 0; x < w; ++x) {
      double lowest = e[x];
      if (x > 0) lowest = std::min(lowest, e[x - 1]);
      if (x + 1 < w) lowest = std::min(lowest, e[x + 1]);
      row[x] = lowest;
    }
  }
  std::vector<double>& across = sc.carry;  // free until displacement
  for (int y = 0; y < h; ++y) {
    const double* mid = &sc.e_coll[sc.at(0, y)];
    const double* up = y > 0 ? &sc.e_coll[sc.at(0, y - 1)] : mid;
    const double* down = y + 1 < h ? &sc.e_coll[sc.at(0, y + 1)] : mid;
    double* out = &across[sc.at(0, y)];
    for (int x = 0; x < w; ++x) out[x] = std::min(mid[x], std::min(up[x], down[x]));
  }
  for (std::size_t k = 0; k < sc.e_coll.size(); ++k) sc.e_coll[k] = std::min(sc.e_plain[k], across[k]);
}

// Collision: push every column whose top lies above the collision surface down to it
// (never below bedrock). Sinkage grows by how far the TRUE envelope pressed the column
// below its previous top, so a star imprint does not stiffen the soil. A holding envelope
// touching a column makes it a contact column without pressing it. A column counts as
// under a body only within active_reach of the envelope above it. Afterwards e_coll is the
// lowest body surface of either kind (erosion fills covered columns up to it at most).
double Terrain::Impl::collide(Scratch& sc, int& contact_count) const {
  const double tol = s.contact_tolerance;
  const double reach = s.active_reach;
  std::vector<double> row_volume(static_cast<std::size_t>(sc.h), 0.0);
  std::vector<int> row_contacts(static_cast<std::size_t>(sc.h), 0);
  for_rows(1, sc.h - 1, sc.parallel, sc.threads, [&](int y) {
    double vol = 0.0;
    int contacts = 0;
    for (int x = 1; x < sc.w - 1; ++x) {
      const std::size_t k = sc.at(x, y);
      sc.disp[k] = 0.0;
      sc.flags[k] = kInterior;
      const double e = sc.e_coll[k], held = sc.e_hold[k];
      const double body = std::min(e, held);
      if (body == kInf) continue;
      sc.e_coll[k] = body;
      const double top = sc.ht[k];
      const bool touching = body <= top + tol;
      if (touching || body - top <= reach) sc.flags[k] |= kCovered;
      if (!touching) continue;
      sc.flags[k] |= kContact;
      if (!(e <= top + tol)) continue;  // held, not pressed
      ++contacts;
      const double target = std::max(e, sc.bed[k]);
      if (target < top) {
        sc.disp[k] = top - target;
        sc.ht[k] = target;
        vol += top - target;
      }
      if (sc.e_true[k] < top) sc.sink[k] += top - std::max(sc.e_true[k], sc.bed[k]);
    }
    row_volume[static_cast<std::size_t>(y)] = vol;
    row_contacts[static_cast<std::size_t>(y)] = contacts;
  });
  double volume = 0.0;  // fixed summation order: rows top to bottom
  contact_count = 0;
  for (int y = 0; y < sc.h; ++y) {
    volume += row_volume[static_cast<std::size_t>(y)];
    contact_count += row_contacts[static_cast<std::size_t>(y)];
  }
  return volume;
}

// Contour map: 8-connected (chessboard) distance, in columns, from each contact column to
// the nearest column not in contact; 0 outside the contact area. Two raster sweeps give the
// exact chessboard distance.
//
// Displaced soil must come out from under the body: a pocket of columns under the body
// that no column in the open can reach through columns out of contact (a gap in the
// contact patch) counts as contact here, so it is passed over, not filled. Otherwise such
// a one-column gap collected the displaced soil of the whole patch around it, rose tens
// of centimetres into the body in one step and was pressed back down the next, its
// recorded sinkage growing by as much each time.
void Terrain::Impl::contour_map(Scratch& sc) const {
  const int big = sc.w + sc.h;
  // Columns out of contact that soil can reach from the open (8-connected): every column
  // not under a body, then by flood fill the columns under a body but out of contact
  // (interior, so their neighbours exist) next to one already reached.
  std::vector<unsigned char>& open = sc.open;
  std::vector<std::size_t>& stack = sc.fill_stack;
  const std::size_t size = sc.flags.size();
  open.resize(size);
  for (std::size_t k = 0; k < size; ++k) open[k] = (sc.flags[k] & (kCovered | kContact)) ? 0 : 1;
  std::size_t off[8];  // neighbour offsets (wrap-around safe: size_t arithmetic modulo 2^64)
  for (int d = 0; d < 8; ++d) off[d] = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(kDy[d]) * sc.w + kDx[d]);
  auto pocket = [&](std::size_t k) { return !open[k] && (sc.flags[k] & (kCovered | kContact)) == kCovered; };
  stack.clear();
  for (std::size_t k = 0; k < size; ++k) {
    if (!pocket(k)) continue;
    for (int d = 0; d < 8; ++d)
      if (open[k + off[d]]) {
        stack.push_back(k);
        break;
      }
  }
  for (std::size_t k : stack) open[k] = 1;
  while (!stack.empty()) {
    const std::size_t k = stack.back();
    stack.pop_back();
    for (int d = 0; d < 8; ++d) {
      const std::size_t nk = k + off[d];
      if (!pocket(nk)) continue;
      open[nk] = 1;
      stack.push_back(nk);
    }
  }
  for (std::size_t k = 0; k < sc.contour.size(); ++k) sc.contour[k] = open[k] ? 0 : big;
  // Only contact columns and pockets relax, and they are interior: their neighbours exist.
  int* c = sc.contour.data();
  const std::ptrdiff_t w = sc.w;
  for (int y = 1; y < sc.h - 1; ++y)
    for (int x = 1; x < sc.w - 1; ++x) {
      int* p = c + y * w + x;
      if (!*p) continue;
      *p = std::min({*p, p[-1] + 1, p[-w - 1] + 1, p[-w] + 1, p[-w + 1] + 1});
    }
  for (int y = sc.h - 2; y >= 1; --y)
    for (int x = sc.w - 2; x >= 1; --x) {
      int* p = c + y * w + x;
      if (!*p) continue;
      *p = std::min({*p, p[1] + 1, p[w + 1] + 1, p[w] + 1, p[w - 1] + 1});
    }
}

// Displacement: the share alpha of each contact column's displaced height is carried
// outward, split equally among the neighbours with a lower contour value, level by level,
// until it lands on the first ring outside the contact area (contour 0), which rises. The
// rest is compacted. Serial in a fixed order (cheap: contact columns only).
double Terrain::Impl::displace(Scratch& sc) const {
  const double alpha = s.material.alpha;
  int top_level = 0;
  for (int c : sc.contour) top_level = std::max(top_level, c);
  if (top_level == 0) return 0.0;
  // Counting sort of contact columns by level, highest first.
  std::vector<int> count(static_cast<std::size_t>(top_level) + 2, 0);
  for (int c : sc.contour)
    if (c > 0) ++count[static_cast<std::size_t>(top_level - c) + 1];
  for (std::size_t l = 1; l < count.size(); ++l) count[l] += count[l - 1];
  std::vector<std::size_t> order(static_cast<std::size_t>(count.back()));
  for (std::size_t k = 0; k < sc.contour.size(); ++k)
    if (sc.contour[k] > 0)
      order[static_cast<std::size_t>(count[static_cast<std::size_t>(top_level - sc.contour[k])]++)] = k;

  std::size_t off[8];  // neighbour offsets (wrap-around safe: size_t arithmetic modulo 2^64)
  for (int d = 0; d < 8; ++d) off[d] = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(kDy[d]) * sc.w + kDx[d]);
  double kept = 0.0;
  for (std::size_t k : order) sc.carry[k] = 0.0;
  for (std::size_t k : order) {
    const double moved = alpha * sc.disp[k];
    kept += sc.disp[k] - moved;
    sc.carry[k] += moved;
  }
  for (std::size_t k : order) {
    const double carry = sc.carry[k];
    if (carry == 0.0) continue;
    const int level = sc.contour[k];
    int lower = 0;
    for (int d = 0; d < 8; ++d)  // contact columns are interior: neighbours exist
      if (sc.contour[k + off[d]] < level) ++lower;
    const double share = carry / lower;
    for (int d = 0; d < 8; ++d) {
      const std::size_t nk = k + off[d];
      if (sc.contour[nk] >= level) continue;
      if (sc.contour[nk] == 0)
        sc.ht[nk] += share;
      else
        sc.carry[nk] += share;
    }
  }
  return kept;
}

// Erosion (Sumner eq. 1-2), Jacobi style so threads never change the result.
// Choices where the paper leaves room:
// - a pair is too steep when h_ij - h_kl exceeds dist * tan(theta) (theta_in if column kl
//   lies under a body, theta_out otherwise); the column moves sigma times the average
//   EXCESS over that limit, shared equally among its too-steep downhill neighbours, so
//   slopes settle at the threshold instead of below it;
// - contact columns are held by the body: they neither give nor receive;
// - a column under a body but not touching it (the body overhangs) receives at most the
//   room between its top and the collision surface, split over this pass's givers;
// - no column gives more than it holds above bedrock;
// - only interior columns give; the one-column halo around the region only receives;
// - passes repeat while material moves and (unless to_rest) some moving pair is steeper
//   than theta_stop, up to max_erosion_passes (tolerances below); a pair whose flow is
//   capped by the body above the lower column does not count (the body holds that slope);
// - after the first pass (unless to_rest), only columns within two of a giver that still
//   had such a steep pair in the last pass give: elsewhere every slope is within the stop
//   tolerance and erosion has ended there, as it would in a region of its own. So a slope
//   does not creep on because a steep pair somewhere else shares its active region.
//
// Work per pass follows the columns that changed. A giver's flow depends only on its own
// height and its neighbours' heights and caps (a cap under a body depends on that
// column's neighbours too), so after the first pass only columns whose inputs changed in
// the last pass are evaluated; any other gives exactly what it gave before: nothing. The sets are bit
// rows built serially, so they never depend on the thread count.
int Terrain::Impl::erode(Scratch& sc, bool to_rest) const {
  const Material& m = s.material;
  const double diag = std::numbers::sqrt2 * s.cell;
  // Moves of less than 1e-3 cell are ignored, so a relaxing slope comes to rest (within
  // 0.06 degrees of its threshold at most) in a finite number of passes.
  const double eps = 1e-3 * s.cell;
  // A moving pair counts as steeper than theta_stop only when it exceeds both theta_stop and
  // its own threshold by 5 % of a cell. Every preset has theta_stop equal to theta_in or
  // theta_out, and the excess over a threshold only decays geometrically, so without the
  // margin the last creeping pair would keep the passes going to the cap.
  const double stop_tolerance = 5e-2 * s.cell;
  // Per direction: [0] toward a column in the open (theta_out), [1] toward one under a body
  // (theta_in): the limit, and the limit a moving pair must exceed to count as steep.
  double thr[8][2], steep_limit[8][2], give_in[8];
  for (int d = 0; d < 8; ++d) {
    const double dist = d < 4 ? s.cell : diag;
    thr[d][0] = dist * det::tan(m.theta_out);
    thr[d][1] = dist * det::tan(m.theta_in);
    const double stop = dist * det::tan(m.theta_stop);
    for (int c = 0; c < 2; ++c) steep_limit[d][c] = std::max(thr[d][c], stop) + stop_tolerance;
    give_in[d] = thr[d][1] + eps;
  }
  // The smallest limits: a column less than these above (below) all its neighbours can
  // neither give nor be given to, so most columns are dismissed without the pair tests.
  double least_give = kInf, least_give_in = kInf;
  for (int d = 0; d < 8; ++d) {
    least_give = std::min({least_give, thr[d][0] + eps, thr[d][1] + eps});
    least_give_in = std::min(least_give_in, give_in[d]);
  }
  const double sigma = m.sigma;
  const int w = sc.w, h = sc.h;
  // Neighbour offsets (wrap-around safe: size_t arithmetic modulo 2^64).
  std::size_t off[8];
  for (int d = 0; d < 8; ++d) off[d] = static_cast<std::size_t>(static_cast<std::ptrdiff_t>(kDy[d]) * w + kDx[d]);

  // Fixed for the whole erosion: who may give, and the caps of columns not under a body.
  ColumnBits& givable = sc.givable;
  ColumnBits& overhang = sc.overhang;
  givable.reset(w, h), overhang.reset(w, h);
  for (int y = 0; y < h; ++y) {
    std::uint64_t* give_row = givable.row(y);
    std::uint64_t* over_row = overhang.row(y);
    for (int x = 0; x < w; ++x) {
      const std::size_t k = sc.at(x, y);
      const unsigned char f = sc.flags[k];
      sc.mask[k] = 0;
      sc.out[k] = 0.0;
      sc.cover[k] = (f & kCovered) ? 1 : 0;
      sc.cap[k] = (f & kContact) ? 0.0 : kInf;  // under a body: set each pass
      const std::uint64_t bit = std::uint64_t{1} << (x & 63);
      // covered columns are interior (see collide)
      if ((f & (kCovered | kContact)) == kCovered) over_row[x >> 6] |= bit;
      if ((f & (kInterior | kContact)) == kInterior) give_row[x >> 6] |= bit;
    }
  }
  ColumnBits& cand = sc.cand;
  ColumnBits& changed = sc.changed;
  ColumnBits& givers = sc.givers;
  ColumnBits& near = sc.near;
  ColumnBits& recap = sc.recap;
  ColumnBits& steep_givers = sc.steep_givers;
  ColumnBits& live = sc.live;
  steep_givers.reset(w, h);
  cand = givable;
  givers.reset(w, h), changed.reset(w, h), near.reset(w, h);
  std::vector<unsigned char>& row_flow = sc.row_flow;
  row_flow.assign(static_cast<std::size_t>(h), 0);

  int passes = 0;
  while (passes < s.max_erosion_passes) {
    // Caps to (re)compute: a cap depends only on the heights around its column, so after
    // the first pass only those next to a changed column. Candidates: the columns whose
    // flow may differ from the last pass, next to a changed column or to a changed cap.
    if (passes == 0) {
      recap = overhang;
    } else {
      dilate(changed, recap);
      recap.keep(overhang);
      near = recap;
      near.add(changed);
      dilate(near, cand);
      cand.keep(givable);
      if (!to_rest) {  // creep far from the last pass's steep pairs has ended
        dilate(steep_givers, live);
        dilate(live, steep_givers);
        cand.keep(steep_givers);
      }
      steep_givers.clear();
    }
    // (a) From the old heights: the cap each column under a body puts on what one
    // neighbour may give it, then each giver's share per too-steep neighbour.
    for_rows(0, h, sc.parallel, sc.threads, [&](int y) {
      recap.for_each_in_row(y, [&](int x) {
        // Under a body: the room up to the collision surface, split over the columns that
        // will give to this one this pass (the same test the givers make), so it fills in
        // one pass instead of creeping up on the body.
        const std::size_t k = sc.at(x, y);
        const double hk = sc.ht[k];
        const double room = sc.e_coll[k] - hk;
        int count = 0;
        const double highest = neighbour_extreme(&sc.ht[k], w, [](double a, double b) { return std::max(a, b); });
        if (room > eps && highest - hk > least_give_in)
#pragma GCC unroll 8
          for (int d = 0; d < 8; ++d) {
            const std::size_t nk = k + off[d];
            if ((sc.flags[nk] & (kInterior | kContact)) != kInterior) continue;
            if (sc.ht[nk] - hk > give_in[d]) ++count;
          }
        sc.cap[k] = count > 0 ? room / count : 0.0;
      });
    });
    for_rows(0, h, sc.parallel, sc.threads, [&](int y) {
      std::uint64_t* giver_row = givers.row(y);
      std::uint64_t* steep_row = steep_givers.row(y);
      bool flow = false;
      cand.for_each_in_row(y, [&](int x) {
        const std::size_t k = sc.at(x, y);
        const double h0 = sc.ht[k];
        const double lowest = neighbour_extreme(&sc.ht[k], w, [](double a, double b) { return std::min(a, b); });
        if (!(h0 - lowest > least_give)) return;
        double excess_sum = 0.0;
        int count = 0;
        unsigned mk = 0, steep_mk = 0;
#pragma GCC unroll 8
        for (int d = 0; d < 8; ++d) {
          const std::size_t nk = k + off[d];  // interior: neighbours exist
          if (sc.cap[nk] == 0.0) continue;
          const double diff = h0 - sc.ht[nk];
          const int c = sc.cover[nk];
          const double t = thr[d][c];
          if (!(diff > t + eps)) continue;
          excess_sum += diff - t;
          ++count;
          mk |= 1u << d;
          if (diff > steep_limit[d][c]) steep_mk |= 1u << d;
        }
        if (count == 0) return;
        double share = sigma * (excess_sum / count) / count;
        share = std::min(share, std::max(0.0, h0 - sc.bed[k]) / count);
        if (!(share > 0.0)) return;
        double total = 0.0;
        bool steep_here = false;
#pragma GCC unroll 8
        for (int d = 0; d < 8; ++d) {
          if (!(mk & (1u << d))) continue;
          const double cap = sc.cap[k + off[d]];
          total += std::min(share, cap);
          // A pair whose flow the body caps (the column under it is full) stays steep: the
          // body holds that slope, erosion cannot relax it.
          steep_here = steep_here || ((steep_mk & (1u << d)) && cap >= share);
        }
        if (!(total > 0.0)) return;
        sc.q[k] = share;
        sc.mask[k] = static_cast<unsigned char>(mk);
        sc.out[k] = total;
        giver_row[x >> 6] |= std::uint64_t{1} << (x & 63);
        flow = true;
        if (steep_here) steep_row[x >> 6] |= std::uint64_t{1} << (x & 63);
      });
      row_flow[static_cast<std::size_t>(y)] = flow;  // only this row's task writes it
    });
    bool flow = false;
    for (int y = 0; y < h; ++y) flow = flow || row_flow[static_cast<std::size_t>(y)];
    const bool steep = steep_givers.any();
    if (!flow) break;
    if (passes > 0 && !steep && !to_rest) break;
    // (b) Every giver and receiver takes what it gave off and gathers what its neighbours
    // gave it. In place: a column's update reads only its own height and the
    // shares, caps and masks fixed in (a).
    // The columns that change: the givers and the neighbours they give to.
    near.clear();
    for (int y = 0; y < h; ++y)
      givers.for_each_in_row(y, [&](int x) {
        near.set(x, y);
        for (unsigned mk = sc.mask[sc.at(x, y)]; mk != 0; mk &= mk - 1) {
          const int d = std::countr_zero(mk);
          near.set(x + kDx[d], y + kDy[d]);
        }
      });
    changed.clear();
    for_rows(0, h, sc.parallel, sc.threads, [&](int y) {
      std::uint64_t* changed_row = changed.row(y);
      const bool edge_row = y == 0 || y == h - 1;
      near.for_each_in_row(y, [&](int x) {
        const std::size_t k = sc.at(x, y);
        const double old = sc.ht[k];
        double hk = old - sc.out[k];
        const double cap = sc.cap[k];
        if (cap > 0.0) {
          if (!edge_row && x > 0 && x < w - 1) {
#pragma GCC unroll 8
            for (int d = 0; d < 8; ++d) {
              const std::size_t nk = k + off[d];
              // neighbour nk gives toward k along the opposite direction
              if (sc.mask[nk] & (1u << (d ^ 1))) hk += std::min(sc.q[nk], cap);
            }
          } else {
#pragma GCC unroll 8
            for (int d = 0; d < 8; ++d) {
              const int nx = x + kDx[d], ny = y + kDy[d];
              if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
              const std::size_t nk = sc.at(nx, ny);
              if (sc.mask[nk] & (1u << (d ^ 1))) hk += std::min(sc.q[nk], cap);
            }
          }
        }
        if (hk != old) {
          sc.ht[k] = hk;
          changed_row[x >> 6] |= std::uint64_t{1} << (x & 63);
        }
      });
    });
    for (int y = 0; y < h; ++y)
      givers.for_each_in_row(y, [&](int x) {
        const std::size_t k = sc.at(x, y);
        sc.mask[k] = 0;
        sc.out[k] = 0.0;
      });
    givers.clear();
    ++passes;
  }
  // Stopped by the cap, not by rest: the givers that were still too steep in the last pass
  // carry on next step. Creep on slopes already within the stop tolerance is not carried:
  // without the cap, the same rule would have stopped it.
  sc.still_flowing = {};
  if (passes == s.max_erosion_passes && passes > 0) {
    sc.still_flowing = steep_givers.bounds();
    sc.still_flowing.i0 += sc.si0, sc.still_flowing.j0 += sc.sj0;
  }
  return passes;
}

void Terrain::Impl::prepare_scratch(Scratch& sc, std::int64_t i0, std::int64_t j0, int w, int h) const {
  sc.resize(i0, j0, w, h);
  sc.threads = thread_count();
  sc.parallel = sc.threads > 1 && static_cast<std::int64_t>(w) * h >= s.parallel_min_columns;
}

// Soil that displacement or erosion lays onto a column is loose: it lowers the column's
// recorded compaction by its height (never below zero). Pressing it back down then adds
// the same amount again, so a body resting in a crater whose walls keep slumping under it
// does not pump its sinkage up without end (seen before this rule: 0.55 m of recorded
// sinkage under a 0.15 m crater). A freshly pressed column keeps its full sinkage.
void Terrain::Impl::loosen_deposits(Scratch& sc) const {
  for (std::size_t k = 0; k < sc.ht.size(); ++k) {
    const double deposit = sc.ht[k] - sc.ht_pressed[k];
    if (deposit > 0.0) sc.sink[k] = std::max(0.0, sc.sink[k] - deposit);
  }
}

StepReport Terrain::Impl::run_region(const ColumnRect& region, std::span<const Imprint> imprints) {
  StepReport report;
  Scratch& sc = scratch;
  prepare_scratch(sc, region.i0 - 1, region.j0 - 1, region.nx + 2, region.ny + 2);
  gather(sc);
  rasterize(sc, imprints);
  int contacts = 0;
  const double displaced = collide(sc, contacts);
  sc.ht_pressed = sc.ht;
  contour_map(sc);
  const double compacted_height = displace(sc);
  report.erosion_passes = erode(sc, false);
  loosen_deposits(sc);
  scatter(sc);
  if (sc.still_flowing.nx > 0) unsettled.push_back(sc.still_flowing);
  report.active_columns = region.nx * region.ny;
  report.contact_columns = contacts;
  report.displaced_volume = displaced * cell_area;
  report.compacted_volume = compacted_height * cell_area;
  compacted += report.compacted_volume;
  return report;
}

// ---- validation of step inputs -------------------------------------------------------

namespace {

void check_envelope(const EnvelopeRaster* env, const std::string& name) {
  if (env == nullptr) throw InvalidSetting(name, "null", "must point to an EnvelopeRaster");
  if (env->nx < 0 || env->ny < 0)
    throw InvalidSetting(name + ".nx/ny", detail::to_text(env->nx) + " x " + detail::to_text(env->ny), "must be >= 0");
  const std::size_t expected = static_cast<std::size_t>(env->nx) * static_cast<std::size_t>(env->ny);
  if (env->lower.size() != expected)
    throw InvalidSetting(name + ".lower.size()", detail::to_text(env->lower.size()),
                         "must equal nx * ny = " + detail::to_text(expected));
  for (std::size_t k = 0; k < expected; ++k) {
    const double v = env->lower[k];
    if (std::isnan(v) || v == -kInf)
      throw InvalidSetting(name + ".lower[" + std::to_string(k) + "]", detail::to_text(v),
                           "must be finite, or +inf where the body does not cover the column");
  }
}

struct Box {
  std::int64_t i0, j0, i1, j1;        // inclusive
  bool touches(const Box& o) const {  // overlapping or adjacent (their halos would overlap)
    return i0 <= o.i1 + 2 && o.i0 <= i1 + 2 && j0 <= o.j1 + 2 && o.j0 <= j1 + 2;
  }
};

}  // namespace

// Bounding box of the columns an imprint covers within active_reach of the soil top; nx =
// 0 if none. Columns the body overhangs by more than that can neither be pressed this step
// nor catch soil that would reach the body, so they need no work.
ColumnRect Terrain::Impl::reach_box(const Imprint& im) {
  const EnvelopeRaster& env = *im.envelope;
  const bool all = std::isinf(s.active_reach);
  if (!all) {
    reach_heights.resize(env.lower.size());
    read_rect({env.i0, env.j0, env.nx, env.ny}, reach_heights, false);
  }
  int x0 = env.nx, y0 = env.ny, x1 = -1, y1 = -1;
  for (int y = 0; y < env.ny; ++y)
    for (int x = 0; x < env.nx; ++x) {
      const std::size_t k =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(env.nx) + static_cast<std::size_t>(x);
      const double lower = env.lower[k];
      if (lower == kInf || (!all && lower - im.offset > reach_heights[k] + s.active_reach)) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x);
      y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (x1 < 0) return {};
  return {env.i0 + x0, env.j0 + y0, x1 - x0 + 1, y1 - y0 + 1};
}

// The active regions of a step: the pressing imprints' reach boxes and the boxes carried
// from the last step, enlarged by active_margin; boxes that touch are merged. Sorted, so
// the processing order never depends on the order of the imprints.
std::vector<ColumnRect> Terrain::Impl::active_regions(std::span<const ColumnRect> reached,
                                                      std::span<const ColumnRect> carried) const {
  std::vector<Box> boxes;
  const std::int64_t m = s.active_margin;
  auto add = [&](const ColumnRect& r) {
    if (r.nx > 0 && r.ny > 0) boxes.push_back({r.i0 - m, r.j0 - m, r.i0 + r.nx - 1 + m, r.j0 + r.ny - 1 + m});
  };
  for (const ColumnRect& r : reached) add(r);
  for (const ColumnRect& r : carried) add(r);
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t a = 0; a < boxes.size() && !merged; ++a)
      for (std::size_t b = a + 1; b < boxes.size() && !merged; ++b)
        if (boxes[a].touches(boxes[b])) {
          boxes[a] = {std::min(boxes[a].i0, boxes[b].i0), std::min(boxes[a].j0, boxes[b].j0),
                      std::max(boxes[a].i1, boxes[b].i1), std::max(boxes[a].j1, boxes[b].j1)};
          boxes.erase(boxes.begin() + static_cast<std::ptrdiff_t>(b));
          merged = true;
        }
  }
  std::sort(boxes.begin(), boxes.end(),
            [](const Box& a, const Box& b) { return std::tie(a.j0, a.i0) < std::tie(b.j0, b.i0); });
  std::vector<ColumnRect> regions;
  for (const Box& b : boxes) {
    const std::int64_t w = b.i1 - b.i0 + 1, h = b.j1 - b.j0 + 1;
    if ((w + 2) * (h + 2) > kMaxRegionColumns)
      throw InvalidSetting("terrain.Imprint.envelope", detail::to_text(w) + " x " + detail::to_text(h) + " columns",
                           "active region must hold at most " + detail::to_text(kMaxRegionColumns) + " columns");
    regions.push_back({b.i0, b.j0, static_cast<int>(w), static_cast<int>(h)});
  }
  return regions;
}

// ---- Terrain -------------------------------------------------------------------------

Terrain::Terrain(TerrainSettings settings) : impl_(std::make_unique<Impl>(std::move(settings))) {}
Terrain::~Terrain() = default;
Terrain::Terrain(Terrain&&) noexcept = default;
Terrain& Terrain::operator=(Terrain&&) noexcept = default;

const TerrainSettings& Terrain::settings() const noexcept { return impl_->s; }

std::int64_t Terrain::column_i(double x) const {
  return static_cast<std::int64_t>(std::llround((x - impl_->s.origin_x) / impl_->s.cell));
}
std::int64_t Terrain::column_j(double y) const {
  return static_cast<std::int64_t>(std::llround((y - impl_->s.origin_y) / impl_->s.cell));
}
double Terrain::column_x(std::int64_t i) const { return impl_->s.origin_x + static_cast<double>(i) * impl_->s.cell; }
double Terrain::column_y(std::int64_t j) const { return impl_->s.origin_y + static_cast<double>(j) * impl_->s.cell; }

double Terrain::height(std::int64_t i, std::int64_t j) const {
  const Tile* t = impl_->find(impl_->key_of(i, j));
  return t ? t->height[impl_->local(i, j)] : impl_->base_at(i, j);
}
void Terrain::heights(const ColumnRect& r, std::span<double> out) const { read_rect(r, out, false); }
void Terrain::base_heights(const ColumnRect& r, std::span<double> out) const { read_rect(r, out, true); }

void Terrain::read_rect(const ColumnRect& r, std::span<double> out, bool base) const {
  if (r.nx < 0 || r.ny < 0 || out.size() != static_cast<std::size_t>(r.nx) * static_cast<std::size_t>(r.ny))
    throw InvalidSetting("terrain.Terrain.heights(out).size", detail::to_text(out.size()),
                         "must be nx * ny of the rectangle");
  impl_->read_rect(r, out, base);
}

void Terrain::Impl::read_rect(const ColumnRect& r, std::span<double> out, bool base) const {
  std::size_t k = 0;
  for (std::int64_t j = r.j0; j < r.j0 + r.ny; ++j)
    for (std::int64_t i = r.i0; i < r.i0 + r.nx;) {
      // One lookup per run of columns inside one tile; the local index then steps by one.
      const TileKey key = key_of(i, j);
      const std::int64_t run_end = std::min<std::int64_t>(r.i0 + r.nx, (key.tx + 1) * n);
      const Tile* t = find(key);
      if (t) {
        const std::vector<double>& field = base ? t->base : t->height;
        std::size_t at = local(i, j);
        for (; i < run_end; ++i) out[k++] = field[at++];
      } else {
        for (; i < run_end; ++i) out[k++] = base_at(i, j);
      }
    }
}

double Terrain::sinkage(std::int64_t i, std::int64_t j) const {
  const Tile* t = impl_->find(impl_->key_of(i, j));
  return t ? t->sinkage[impl_->local(i, j)] : 0.0;
}
double Terrain::base_height(std::int64_t i, std::int64_t j) const {
  const Tile* t = impl_->find(impl_->key_of(i, j));
  return t ? t->base[impl_->local(i, j)] : impl_->base_at(i, j);
}
double Terrain::bedrock(std::int64_t i, std::int64_t j) const {
  return base_height(i, j) - impl_->s.material.soil_depth;
}

void Terrain::set_height(std::int64_t i, std::int64_t j, double h) {
  Check{"terrain.Terrain.set_height"}.finite("h", h);
  const TileKey key = impl_->key_of(i, j);
  Tile& t = impl_->tile(key);
  const std::size_t k = impl_->local(i, j);
  const double value = std::max(h, t.base[k] - impl_->s.material.soil_depth);
  if (value == t.height[k]) return;
  impl_->edited += (value - t.height[k]) * impl_->cell_area;
  t.height[k] = value;
  if (!t.dirty) impl_->dirty_keys.push_back(key);
  const int li = static_cast<int>(k % static_cast<std::size_t>(impl_->n));
  const int lj = static_cast<int>(k / static_cast<std::size_t>(impl_->n));
  t.mark_dirty(li, lj, li, lj);
}

StepReport Terrain::step(std::span<const Imprint> imprints) {
  for (std::size_t b = 0; b < imprints.size(); ++b) {
    const std::string name = "terrain.Imprint[" + std::to_string(b) + "]";
    check_envelope(imprints[b].envelope, name + ".envelope");
    const Check c{name};
    c.non_negative("offset", imprints[b].offset);
    c.finite("vx", imprints[b].vx);
    c.finite("vy", imprints[b].vy);
    c.finite("vz", imprints[b].vz);
  }
  if (impl_->s.material.rigid) return {};
  std::vector<ColumnRect> reached;
  for (const Imprint& im : imprints)
    if (!im.hold)
      if (const ColumnRect r = impl_->reach_box(im); r.nx > 0) reached.push_back(r);
  const std::vector<ColumnRect> carried = std::exchange(impl_->unsettled, {});
  const std::vector<ColumnRect> regions = impl_->active_regions(reached, carried);
  StepReport total;
  for (const ColumnRect& r : regions) {
    const StepReport part = impl_->run_region(r, imprints);
    total.active_columns += part.active_columns;
    total.contact_columns += part.contact_columns;
    total.erosion_passes = std::max(total.erosion_passes, part.erosion_passes);
    total.displaced_volume += part.displaced_volume;
    total.compacted_volume += part.compacted_volume;
  }
  // What the bodies reached this step is eroded once more next step: where a body has
  // lifted or moved away, slopes it held at theta_in relax toward theta_out.
  impl_->unsettled.insert(impl_->unsettled.end(), reached.begin(), reached.end());
  return total;
}

StepReport Terrain::relax(const ColumnRect& region) {
  const Check c{"terrain.Terrain.relax.region"};
  c.at_least("nx", region.nx, 0);
  c.at_least("ny", region.ny, 0);
  if (static_cast<std::int64_t>(region.nx + 2) * (region.ny + 2) > kMaxRegionColumns)
    throw InvalidSetting(c.name("nx * ny"), detail::to_text(static_cast<std::int64_t>(region.nx) * region.ny),
                         "must be at most " + detail::to_text(kMaxRegionColumns));
  StepReport report;
  if (impl_->s.material.rigid || region.nx == 0 || region.ny == 0) return report;
  Scratch& sc = impl_->scratch;
  impl_->prepare_scratch(sc, region.i0 - 1, region.j0 - 1, region.nx + 2, region.ny + 2);
  impl_->gather(sc);
  std::fill(sc.e_coll.begin(), sc.e_coll.end(), kInf);
  for (int y = 1; y < sc.h - 1; ++y)
    for (int x = 1; x < sc.w - 1; ++x) sc.flags[sc.at(x, y)] = kInterior;
  report.erosion_passes = impl_->erode(sc, true);
  impl_->scatter(sc);
  report.active_columns = region.nx * region.ny;
  return report;
}

// ---- bearing -------------------------------------------------------------------------

// Row by row, one tile lookup per run of columns in the same tile. With only_touching, a
// column is kept only if the envelope lowered by `offset` touches it (bearing at one
// offset needs no others).
Terrain::Impl::BearingInput Terrain::Impl::bearing_input(const EnvelopeRaster& env, bool only_touching,
                                                         double offset) const {
  BearingInput in;
  const double depth = s.material.soil_depth, tol = s.contact_tolerance;
  for (int y = 0; y < env.ny; ++y) {
    const std::int64_t j = env.j0 + y;
    const std::int64_t ty = floor_div(j, n);
    const std::size_t row = static_cast<std::size_t>(j - ty * n) * static_cast<std::size_t>(n);
    const double* lower = env.lower.data() + static_cast<std::size_t>(y) * env.nx;
    for (int x = 0; x < env.nx;) {
      const std::int64_t i = env.i0 + x;
      const std::int64_t tx = floor_div(i, n);
      const int run = static_cast<int>(std::min<std::int64_t>(env.nx - x, (tx + 1) * n - i));
      const Tile* t = find({tx, ty});
      for (int r = 0; r < run; ++r) {
        const double e = lower[x + r];
        if (e == kInf) continue;
        BearingColumn c{i + r, j, 0, 0, 0, e};
        if (t) {
          const std::size_t k = row + static_cast<std::size_t>(i + r - tx * n);
          c.top = t->height[k], c.sink = t->sinkage[k], c.bed = t->base[k] - depth;
        } else {
          const double b = base_at(i + r, j);
          c.top = b, c.sink = 0.0, c.bed = b - depth;
        }
        if (only_touching && !(e - offset <= c.top + tol)) continue;
        in.columns.push_back(c);
      }
      x += run;
    }
  }
  return in;
}

// Bekker capacity of the columns the envelope (lowered by offset) touches. A column
// touches when the envelope is within contact_tolerance of its top; its sinkage if pressed
// to the envelope is its plastic sinkage plus how far the envelope lies below its top.
// b is the smaller side of the touching columns' bounding box (each column counts as one
// cell wide). A touched column at bedrock carries anything.
Bearing Terrain::Impl::capacity(const BearingInput& in, double offset, bool with_columns) const {
  Bearing out;
  const double tol = s.contact_tolerance;
  std::int64_t i0 = std::numeric_limits<std::int64_t>::max(), j0 = i0;
  std::int64_t i1 = std::numeric_limits<std::int64_t>::min(), j1 = i1;
  for (const BearingColumn& c : in.columns) {
    if (!(c.lower - offset <= c.top + tol)) continue;
    ++out.contact_columns;
    i0 = std::min(i0, c.i), i1 = std::max(i1, c.i), j0 = std::min(j0, c.j), j1 = std::max(j1, c.j);
  }
  if (out.contact_columns == 0) return out;
  const double b = static_cast<double>(std::min(i1 - i0 + 1, j1 - j0 + 1)) * s.cell;
  out.patch_width = b;
  const bool rigid = s.material.rigid;
  if (with_columns) out.columns.reserve(static_cast<std::size_t>(out.contact_columns));
  for (const BearingColumn& c : in.columns) {
    const double e = c.lower - offset;
    if (!(e <= c.top + tol)) continue;
    double force;
    if (rigid || e <= c.bed || c.top <= c.bed)
      force = kInf;
    else
      force = bekker::pressure(s.material, b, c.sink + std::max(0.0, c.top - e)) * cell_area;
    out.capacity += force;
    if (with_columns) out.columns.push_back({c.i, c.j, force});
  }
  return out;
}

Bearing Terrain::bearing(const EnvelopeRaster& envelope, double offset) const {
  check_envelope(&envelope, "terrain.Terrain.bearing.envelope");
  Check{"terrain.Terrain.bearing"}.non_negative("offset", offset);
  return impl_->capacity(impl_->bearing_input(envelope, true, offset), offset, true);
}

// Solves capacity(offset) = load. Capacity grows with the offset (more columns touch,
// each sinks further), so a bracket [lo, hi] with capacity(lo) < load <= capacity(hi) is
// narrowed by regula falsi (Illinois variant), falling back to bisection, until it is
// 1e-7 m wide; the upper end is returned so the soil carries at least the load.
double Terrain::bearing_offset(const EnvelopeRaster& envelope, double load) const {
  check_envelope(&envelope, "terrain.Terrain.bearing_offset.envelope");
  Check{"terrain.Terrain.bearing_offset"}.non_negative("load", load);
  const Impl::BearingInput in = impl_->bearing_input(envelope, false, 0.0);
  if (in.columns.empty()) return 0.0;  // the body covers no column: nothing to sink into
  auto f = [&](double o) { return impl_->capacity(in, o, false).capacity - load; };
  double f_lo = f(0.0);
  if (f_lo >= 0.0) return 0.0;
  // Every covered column at bedrock bears anything: that offset closes the bracket.
  double limit = 0.0;
  for (const auto& c : in.columns) limit = std::max(limit, c.lower - c.bed);
  double lo = 0.0, hi = std::min(1e-3, limit), f_hi = f(hi);
  while (f_hi < 0.0 && hi < limit) {
    lo = hi, f_lo = f_hi;
    hi = std::min(2.0 * hi, limit);
    f_hi = f(hi);
  }
  if (f_hi < 0.0) return limit;  // unreachable (bedrock carries anything); kept as a guard
  constexpr double kTolerance = 1e-7;
  int side = 0;
  for (int it = 0; it < 200 && hi - lo > kTolerance; ++it) {
    double mid = 0.5 * (lo + hi);
    if (std::isfinite(f_hi)) {
      const double secant = lo - f_lo * (hi - lo) / (f_hi - f_lo);
      if (secant > lo && secant < hi) mid = secant;
    }
    // Keep the step from crawling when one end stalls.
    mid = std::clamp(mid, lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo));
    const double f_mid = f(mid);
    if (f_mid < 0.0) {
      lo = mid, f_lo = f_mid;
      if (side == -1) f_hi *= 0.5;
      side = -1;
    } else {
      hi = mid, f_hi = f_mid;
      if (side == 1) f_lo *= 0.5;
      side = 1;
    }
  }
  return hi;
}

// ---- output --------------------------------------------------------------------------

std::vector<ColumnRect> Terrain::take_changed() {
  std::vector<TileKey>& keys = impl_->dirty_keys;
  std::sort(keys.begin(), keys.end());
  std::vector<ColumnRect> rects;
  rects.reserve(keys.size());
  const int n = impl_->n;
  for (const TileKey& key : keys) {
    const auto it = impl_->tiles.find(key);
    if (it == impl_->tiles.end() || !it->second->dirty) continue;
    Tile& t = *it->second;
    rects.push_back({key.tx * n + t.di0, key.ty * n + t.dj0, t.di1 - t.di0 + 1, t.dj1 - t.dj0 + 1});
    t.dirty = false;
  }
  keys.clear();
  return rects;
}

VolumeTotals Terrain::volume() const {
  VolumeTotals v;
  double ground = 0.0;
  for (const TileKey& key : impl_->sorted_keys()) {
    const Tile& t = *impl_->tiles.at(key);
    double sum = 0.0;
    for (std::size_t k = 0; k < t.height.size(); ++k) sum += t.height[k] - t.base[k];
    ground += sum;
  }
  v.ground = ground * impl_->cell_area;
  v.compacted = impl_->compacted;
  v.airborne = 0.0;
  v.edited = impl_->edited;
  return v;
}

std::uint64_t Terrain::state_hash() const {
  StateHash h;
  h.add(impl_->compacted);
  h.add(impl_->edited);
  for (const TileKey& key : impl_->sorted_keys()) {
    const Tile& t = *impl_->tiles.at(key);
    h.add(key.tx);
    h.add(key.ty);
    h.add(std::span<const double>(t.height));
    h.add(std::span<const double>(t.sinkage));
  }
  return h.value();
}

std::size_t Terrain::tile_count() const { return impl_->tiles.size(); }

std::size_t Terrain::memory_bytes() const {
  const std::size_t per_tile = sizeof(Tile) + 3 * sizeof(double) * static_cast<std::size_t>(impl_->n) * impl_->n +
                               sizeof(TileKey) + 2 * sizeof(void*);
  return sizeof(Impl) + impl_->tiles.bucket_count() * sizeof(void*) + impl_->tiles.size() * per_tile +
         impl_->scratch.bytes() + impl_->dirty_keys.capacity() * sizeof(TileKey);
}

std::size_t Scratch::bytes() const {
  const std::size_t bit_words = givable.bits.capacity() + overhang.bits.capacity() + cand.bits.capacity() +
                                changed.bits.capacity() + givers.bits.capacity() + near.bits.capacity() +
                                recap.bits.capacity() + steep_givers.bits.capacity() + live.bits.capacity();
  return (15 * sizeof(double) + 4 + sizeof(int)) * ht.capacity() + bit_words * sizeof(std::uint64_t) +
         fill_stack.capacity() * sizeof(std::size_t);
}

}  // namespace shore::terrain

#include "stage_imprint.h"

#include <algorithm>

#include "capacity_bytes.h"

namespace shore::terrain {

namespace {
/// Whether a body whose surface lies at `body` covers a column topped at `top`: it touches
/// it (within contact_tolerance) or lies within active_reach above it.
bool covers(double body, double top, double tol, double reach) { return body <= top + tol || body - top <= reach; }
}  // namespace

// plain_ / star_ hold the lowest (offset) envelope of plain and star pressing imprints;
// true_ the lowest of both (soil state); coll_ the collision surface (star imprints lowered
// to their lowest point within +-1 column); hold_ the lowest envelope of holding imprints.
void ImprintStage::rasterize(const Region& region, std::span<const Imprint> imprints) {
  const std::size_t size = region.size();
  stars_ = std::any_of(imprints.begin(), imprints.end(), [](const Imprint& im) { return im.star && !im.hold; });
  // Written in full before they are read (disp_ for every interior column, the only ones
  // read), so they are only sized: clearing them each step costs more than the rest of a
  // small step's bookkeeping. Without star imprints star_, star_low_ and true_ are not
  // used at all (coll_ is the plain envelope, and the true one).
  disp_.resize(size);
  if (stars_) {
    for (auto* v : {&true_, &coll_, &star_low_}) v->resize(size);
    star_.assign(size, kInf);
  }
  plain_.assign(size, kInf);
  hold_.assign(size, kInf);
  flags_.assign(size, 0);  // the halo is not interior; flag_covered_halo marks what a body covers
  for (const Imprint& im : imprints) {
    const EnvelopeRaster& env = *im.envelope;
    const std::int64_t x0 = std::max(env.i0, region.si0), x1 = std::min(env.i0 + env.nx, region.si0 + region.w);
    const std::int64_t y0 = std::max(env.j0, region.sj0), y1 = std::min(env.j0 + env.ny, region.sj0 + region.h);
    std::vector<double>& dst = im.hold ? hold_ : im.star ? star_ : plain_;
    for (std::int64_t j = y0; j < y1; ++j)
      for (std::int64_t i = x0; i < x1; ++i) {
        const double lower = env.lower[env.index(i, j)];
        if (lower == kInf) continue;
        double& e = dst[region.at(static_cast<int>(i - region.si0), static_cast<int>(j - region.sj0))];
        e = std::min(e, lower - im.offset);
      }
  }
  if (!stars_) {
    // The plain envelope is the collision surface: taken over, not copied (plain_ is
    // filled afresh next step).
    std::swap(coll_, plain_);
    return;
  }
  for (std::size_t k = 0; k < size; ++k) true_[k] = std::min(plain_[k], star_[k]);
  lower_star_neighbourhoods(region);
}

// Lowest star envelope over each 3 x 3 neighbourhood (clipped to the region): the minimum
// along x, then along y, then the plain envelope.
void ImprintStage::lower_star_neighbourhoods(const Region& region) {
  const int w = region.w, h = region.h;
  for (int y = 0; y < h; ++y) {
    const double* e = &star_[region.at(0, y)];
    double* row = &star_low_[region.at(0, y)];
    for (int x = 0; x < w; ++x) {
      double lowest = e[x];
      if (x > 0) lowest = std::min(lowest, e[x - 1]);
      if (x + 1 < w) lowest = std::min(lowest, e[x + 1]);
      row[x] = lowest;
    }
  }
  for (int y = 0; y < h; ++y) {
    const double* mid = &star_low_[region.at(0, y)];
    const double* up = y > 0 ? &star_low_[region.at(0, y - 1)] : mid;
    const double* down = y + 1 < h ? &star_low_[region.at(0, y + 1)] : mid;
    const double* plain = &plain_[region.at(0, y)];
    double* out = &coll_[region.at(0, y)];
    for (int x = 0; x < w; ++x) out[x] = std::min(plain[x], std::min(mid[x], std::min(up[x], down[x])));
  }
}

// A column whose top lies above the collision surface is pushed down to it (never below
// bedrock). Sinkage grows by how far the TRUE envelope pressed the column below its
// previous top, so a star imprint does not stiffen the soil. A holding envelope touching a
// column makes it a contact column without pressing it. A column counts as under a body
// only within active_reach of the envelope above it. Afterwards coll_ is the lowest body
// surface of either kind (erosion fills covered columns up to it at most), and
// region.ht_pressed the heights as collision leaves them (recorded here, as each column is
// visited, rather than copied after).
ImprintStage::Collision ImprintStage::collide(Region& region, const TerrainSettings& s) {
  const double tol = s.contact_tolerance;
  const double reach = s.active_reach;
  row_volume_.assign(static_cast<std::size_t>(region.h), 0.0);
  row_contacts_.assign(static_cast<std::size_t>(region.h), 0);
  region.ht_pressed.resize(region.size());
  const auto keep = [&](std::size_t k, std::size_t n) {  // columns collision leaves as they are
    std::copy_n(region.ht.begin() + static_cast<std::ptrdiff_t>(k), n,
                region.ht_pressed.begin() + static_cast<std::ptrdiff_t>(k));
  };
  const auto row = static_cast<std::size_t>(region.w);
  keep(region.at(0, 0), row);  // the halo's rows
  if (region.h > 1) keep(region.at(0, region.h - 1), row);
  region.for_rows(1, region.h - 1, [&](int y) {
    double vol = 0.0;
    int contacts = 0;
    keep(region.at(0, y), 1);  // the halo's columns
    keep(region.at(region.w - 1, y), 1);
    for (int x = 1; x < region.w - 1; ++x) {
      const std::size_t k = region.at(x, y);
      disp_[k] = 0.0;
      flags_[k] = kInterior;
      const double e = coll_[k], held = hold_[k];
      const double body = std::min(e, held);
      const double top = region.ht[k];
      region.ht_pressed[k] = top;
      if (body == kInf) continue;
      coll_[k] = body;
      if (covers(body, top, tol, reach)) flags_[k] |= kCovered;
      const bool touching = body <= top + tol;
      if (!touching) continue;
      flags_[k] |= kContact;
      if (!(e <= top + tol)) continue;  // held, not pressed
      ++contacts;
      const double target = std::max(e, region.bed[k]);
      if (target < top) {
        disp_[k] = top - target;
        region.ht[k] = target;
        region.ht_pressed[k] = target;
        vol += top - target;
      }
      const double pressing = stars_ ? true_[k] : e;  // without stars the true envelope is e
      if (pressing < top) region.sink[k] += top - std::max(pressing, region.bed[k]);
    }
    row_volume_[static_cast<std::size_t>(y)] = vol;
    row_contacts_[static_cast<std::size_t>(y)] = contacts;
  });
  flag_covered_halo(region, s);
  Collision out;  // fixed summation order: rows top to bottom
  for (int y = 0; y < region.h; ++y) {
    out.displaced += row_volume_[static_cast<std::size_t>(y)];
    out.contacts += row_contacts_[static_cast<std::size_t>(y)];
  }
  return out;
}

// A halo column lies outside the region's stages (its neighbours are not all gathered), so
// the caps that keep soil out of a body cannot be computed for it. Under a body (a held
// one: a pressing body's reach box and margin keep its covered columns interior) it
// receives nothing, as a contact column; otherwise the region's erosion would fill it up
// into the body and the scatter would write that back.
void ImprintStage::flag_covered_halo(const Region& region, const TerrainSettings& s) {
  const auto mark = [&](int x, int y) {
    const std::size_t k = region.at(x, y);
    const double body = std::min(coll_[k], hold_[k]);
    if (body != kInf && covers(body, region.ht[k], s.contact_tolerance, s.active_reach)) flags_[k] = kHaloCovered;
  };
  for (int x = 0; x < region.w; ++x) {
    mark(x, 0);
    if (region.h > 1) mark(x, region.h - 1);
  }
  for (int y = 1; y < region.h - 1; ++y) {
    mark(0, y);
    if (region.w > 1) mark(region.w - 1, y);
  }
}

void ImprintStage::no_bodies(const Region& region) {
  coll_.assign(region.size(), kInf);
  flags_.assign(region.size(), 0);
  for (int y = 1; y < region.h - 1; ++y)
    for (int x = 1; x < region.w - 1; ++x) flags_[region.at(x, y)] = kInterior;
}

std::size_t ImprintStage::bytes() const {
  return capacity_bytes(plain_, star_, star_low_, true_, coll_, hold_, disp_, flags_, row_volume_, row_contacts_);
}

}  // namespace shore::terrain

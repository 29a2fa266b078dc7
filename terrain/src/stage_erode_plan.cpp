// Erosion planning: the limits, who may give, which columns each pass visits, when passes
// stop and what carries over to the next step.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

#include "capacity_bytes.h"
#include "flag_lanes.h"
#include "shore/core/det_math.h"
#include "stage_erode.h"
#include "stage_imprint.h"

namespace shore::terrain {

ErosionLimits ErosionLimits::from(const TerrainSettings& s, const Material& m) {
  ErosionLimits lim;
  const double diag = std::numbers::sqrt2 * s.cell;
  // Moves of less than 1e-3 cell are ignored, so a relaxing slope comes to rest (within
  // 0.06 degrees of its threshold at most) in a finite number of passes.
  lim.eps = 1e-3 * s.cell;
  // A moving pair counts as steeper than theta_stop only when it exceeds both theta_stop and
  // its own threshold by 5 % of a cell. Every preset has theta_stop equal to theta_in or
  // theta_out, and the excess over a threshold only decays geometrically, so without the
  // margin the last creeping pair would keep the passes going to the cap.
  const double stop_tolerance = 5e-2 * s.cell;
  // Each angle's tangent once (not per direction): a step computes these per palette entry.
  const double tan_out = det::tan(m.theta_out), tan_in = det::tan(m.theta_in), tan_stop = det::tan(m.theta_stop);
  for (int d = 0; d < 8; ++d) {
    const double dist = d < 4 ? s.cell : diag;
    lim.thr[d][0] = dist * tan_out;
    lim.thr[d][1] = dist * tan_in;
    const double stop = dist * tan_stop;
    for (int c = 0; c < 2; ++c) lim.steep_limit[d][c] = std::max(lim.thr[d][c], stop) + stop_tolerance;
    for (int c = 0; c < 2; ++c) lim.give[d][c] = lim.thr[d][c] + lim.eps;
    lim.give_in[d] = lim.thr[d][1] + lim.eps;
  }
  for (int kind = 0; kind < 2; ++kind) lim.least_give[kind] = kInf, lim.least_give_in[kind] = kInf;
  for (int d = 0; d < 8; ++d) {
    const int kind = d < 4 ? 0 : 1;
    lim.least_give[kind] = std::min({lim.least_give[kind], lim.give[d][0], lim.give[d][1]});
    lim.least_give_in[kind] = std::min(lim.least_give_in[kind], lim.give_in[d]);
  }
  lim.sigma = m.sigma;
  return lim;
}

int ErodeStage::run(Region& region, std::span<const unsigned char> flags, std::span<const double> body,
                    const TerrainSettings& s, std::span<const Material> palette, bool to_rest, bool loosens) {
  set_limits(region, s, palette);
  assign_roles(region, flags);
  map_ = !region.mat.empty();
  if (map_) start_layers(region, palette, loosens);
  int passes = 0;
  while (passes < s.max_erosion_passes) {
    plan_pass(passes, to_rest);
    // From the old heights: the caps, then each giver's shares.
    compute_caps(region, flags, body);
    const bool flow = compute_shares(region);
    const bool steep = steep_givers_.any();
    if (!flow) break;
    if (passes > 0 && !steep && !to_rest) break;
    // Every giver and receiver takes what it gave off and gathers what it was given.
    mark_receivers(region);
    move_soil(region);
    if (map_) track_layers(region);
    clear_givers(region);
    ++passes;
  }
  find_still_flowing(region, passes, s.max_erosion_passes);
  return passes;
}

// The limits, recomputed only when what they are made of changed (the cell, whether there
// is a map, each entry's angles and sigma): a step would otherwise take three tangents per
// palette entry.
void ErodeStage::set_limits(const Region& region, const TerrainSettings& s, std::span<const Material> palette) {
  const bool map = !region.mat.empty();
  const std::size_t entries = map ? palette.size() : 1;
  bool same = limits_set_ && limits_cell_ == s.cell && limits_map_ == map && limits_of_.size() == entries;
  for (std::size_t m = 0; same && m < entries; ++m) same = limits_of_[m] == LimitInputs::of(palette[m]);
  if (same) return;
  limits_set_ = true, limits_cell_ = s.cell, limits_map_ = map;
  limits_of_.clear();
  for (std::size_t m = 0; m < entries; ++m) limits_of_.push_back(LimitInputs::of(palette[m]));
  lims_.clear();
  if (!map) {
    lim_ = ErosionLimits::from(s, palette[0]);
  } else {
    for (const Material& m : palette) lims_.push_back(ErosionLimits::from(s, m));
    lim_ = lims_[0];  // palette[0]'s limits, computed once
    for (const ErosionLimits& l : lims_)
      for (int kind = 0; kind < 2; ++kind) {
        lim_.least_give_in[kind] = std::min(lim_.least_give_in[kind], l.least_give_in[kind]);
        lim_.least_give[kind] = std::min(lim_.least_give[kind], l.least_give[kind]);
      }
  }
}

// Fixed for the whole erosion: who may give, and the caps of columns not under a body.
// Through raw pointers (through the vectors, each byte store may alias their data), and
// the roles' bits eight columns at a time (flag_lanes.h).
void ErodeStage::assign_roles(const Region& region, std::span<const unsigned char> flags) {
  namespace lanes = flag_lanes;
  const int w = region.w, h = region.h;
  const std::size_t size = region.size();
  // q_ is written for every giver before a receiver reads it; the rest is set below.
  for (auto* v : {&q_, &out_, &cap_}) v->resize(size);
  mask_.resize(size);
  cover_.resize(size);
  givable_.reset(w, h), overhang_.reset(w, h);
  const unsigned char* f = flags.data();
  unsigned char* mask = mask_.data();
  unsigned char* cover = cover_.data();
  double* out = out_.data();
  double* cap = cap_.data();
  std::memset(mask, 0, size);
  std::size_t k = 0;
  if constexpr (lanes::kFlagLanes)  // the cover bytes eight at a time
    for (; k + 8 <= size; k += 8) {
      const std::uint64_t covered = (lanes::eight(f + k) >> 1) & lanes::kLowBits;
      std::memcpy(cover + k, &covered, sizeof covered);
    }
  for (; k < size; ++k) cover[k] = (f[k] & kCovered) ? 1 : 0;
  for (k = 0; k < size; ++k) {
    out[k] = 0.0;
    cap[k] = (f[k] & (kContact | kHaloCovered)) ? 0.0 : kInf;  // under a body: set each pass
  }
  for (int y = 0; y < h; ++y) {
    std::uint64_t* give_row = givable_.row(y);
    std::uint64_t* over_row = overhang_.row(y);
    const unsigned char* row = f + region.at(0, y);
    for (int i = 0; i < givable_.words; ++i) {
      std::uint64_t give = 0, over = 0;
      const int x0 = i * 64, x1 = std::min(w, x0 + 64);
      int x = x0;
      if constexpr (lanes::kFlagLanes)
        for (; x + 8 <= x1; x += 8) {
          const std::uint64_t eight = lanes::eight(row + x);
          // covered columns are interior (see ImprintStage::collide)
          over |= lanes::pack(lanes::covered_only(eight)) << (x - x0);
          give |= lanes::pack(lanes::interior_only(eight)) << (x - x0);
        }
      for (; x < x1; ++x) {
        over |= static_cast<std::uint64_t>((row[x] & (kCovered | kContact)) == kCovered) << (x - x0);
        give |= static_cast<std::uint64_t>((row[x] & (kInterior | kContact)) == kInterior) << (x - x0);
      }
      over_row[i] = over, give_row[i] = give;
    }
  }
  steep_givers_.reset(w, h);
  cand_ = givable_;
  givers_.reset(w, h), changed_.reset(w, h), near_.reset(w, h);
  row_flow_.assign(static_cast<std::size_t>(h), 0);
}

// Caps to (re)compute: a cap depends only on the heights around its column, so after the
// first pass only those next to a changed column. Candidates: the columns whose flow may
// differ from the last pass, next to a changed column or to a changed cap.
void ErodeStage::plan_pass(int pass, bool to_rest) {
  if (pass == 0) {
    recap_ = overhang_;
    return;
  }
  dilate(changed_, recap_);
  recap_.keep(overhang_);
  near_ = recap_;
  near_.add(changed_);
  dilate(near_, cand_);
  cand_.keep(givable_);
  if (!to_rest) {  // creep far from the last pass's steep pairs has ended
    dilate(steep_givers_, live_);
    dilate(live_, steep_givers_);
    cand_.keep(steep_givers_);
  }
  steep_givers_.clear();
}

// Stopped by the cap, not by rest: the givers that were still too steep in the last pass
// carry on next step. Creep on slopes already within the stop tolerance is not carried:
// without the cap, the same rule would have stopped it.
void ErodeStage::find_still_flowing(const Region& region, int passes, int max_passes) {
  still_flowing_ = {};
  if (passes == max_passes && passes > 0) {
    still_flowing_ = steep_givers_.bounds();
    still_flowing_.i0 += region.si0, still_flowing_.j0 += region.sj0;
  }
}

std::size_t ErodeStage::bytes() const {
  return capacity_bytes(q_, out_, cap_, mask_, cover_, row_flow_, lims_, limits_of_, kind_, thick_, lower_, spent_,
                        rigid_, row_cross_, retop_) +
         dirty_.bytes() + cross_givers_.bytes() + track_.bytes() + givable_.bytes() + overhang_.bytes() +
         cand_.bytes() + changed_.bytes() + givers_.bytes() + near_.bytes() + recap_.bytes() + steep_givers_.bytes() +
         live_.bytes();
}

}  // namespace shore::terrain

// Erosion with a material map: the moved soil keeps its material, so volume is conserved per
// material (docs/terrain.md, "Erosion across a border"). A column's soil above bedrock is its
// top layer (its painted index, `thick` m down from its top) over its lower layer (the rest),
// or one material where it is not layered; the crust's thickness is its boundary less its
// sinkage (layers.h), so whatever changes the sinkage (pressing, loosening a deposit) and the
// height together keeps the layers, and only what erosion moves needs keeping here:
// - a giver gives only its top layer (its share is bounded by it); a crust given away whole
//   leaves the column its lower material, unlayered;
// - a column takes its own top material onto its top layer (a broken-through column's is its
//   lower one: it stays broken through);
// - an unlayered column also takes soil of another material, which becomes its top layer, of
//   one material per pass: the smallest palette index among its neighbours of another
//   material (decided from the heights and materials as the pass found them, so threads and
//   the order of givers never matter);
// - a layered column takes its lower material too, into its lower layer: the top layer keeps
//   its thickness and rides up on it (two layers are all a column holds, so the deposit
//   cannot lie above a top layer of another material);
// - soil of a third material (neither of a layered column's two) is held at its edge;
// - a rigid column (a road) takes any soil as its own loose soil, and soil it gives lands as
//   the receiver's own, as before: its bedrock is read by its painted index everywhere
//   (bearing, contact), so it can neither hold a top layer of a deforming material nor lay a
//   rigid one. Volume per material is conserved wherever no rigid column gives or takes.

#include <algorithm>
#include <bit>

#include "neighbours.h"
#include "stage_erode.h"

namespace shore::terrain {

void ErodeStage::start_layers(Region& region, std::span<const Material> palette, bool loosens) {
  const std::size_t size = region.size();
  kind_.assign(size, kUnlayered);
  thick_.resize(size);
  lower_.resize(size);
  spent_.resize(size);
  rigid_.clear();
  for (const Material& m : palette) rigid_.push_back(m.rigid ? 1 : 0);
  row_cross_.assign(static_cast<std::size_t>(region.h), 0);
  dirty_.reset(region.w, region.h);
  cross_givers_.reset(region.w, region.h);
  track_.reset(region.w, region.h);
  // Raw pointers: the byte stores (kind, lower) may alias anything, so indexing the
  // vectors would reload their data pointers per column.
  unsigned char* kind = kind_.data();
  std::uint8_t* lower = lower_.data();
  double* thick = thick_.data();
  const double* sink = region.sink.data();
  const double* ht = region.ht.data();
  const double* pressed = region.ht_pressed.data();
  // Erosion reads each column's exposed material from here on; the layered columns' kinds
  // in the same pass (without layers there are none).
  region.expose_layers([&](std::size_t k, const ColumnLayer& l) __attribute__((always_inline)) {
    lower[k] = l.lower;
    if (sink[k] > l.boundary) {
      kind[k] = kBroken;
      thick[k] = l.boundary - sink[k];
    } else {
      // A step loosens what displacement laid on the column after erosion: that soil is the
      // top layer's already (its sinkage will drop by it).
      const double laid = loosens ? std::max(0.0, ht[k] - pressed[k]) : 0.0;
      kind[k] = kCrust;
      thick[k] = l.boundary - (sink[k] - laid);
    }
  });
}

void ErodeStage::track_layers(Region& region) {
  const int w = region.w, h = region.h;
  // The first and last rows with a cross giver: only they and the rows between (and one
  // either side, for the receivers) are walked.
  int first = 0, last = h - 1;
  while (first < h && row_cross_[static_cast<std::size_t>(first)] == 0) ++first;
  if (first == h) return;  // every pair moved soil between unlayered columns of one material
  while (row_cross_[static_cast<std::size_t>(last)] == 0) --last;
  // Only a giver whose soil crosses a border or moves a layer (or that is layered itself),
  // and the columns it gives to, can change a layering: any other column gave and took
  // only its own material, unlayered, which leaves it as it was.
  track_.clear();
  const auto crosses = [&](int y) { return y >= 0 && y < h && row_cross_[static_cast<std::size_t>(y)] != 0; };
  for (int y = first; y <= last; ++y) {
    if (!crosses(y)) continue;  // no cross giver in the row
    cross_givers_.for_each_in_row(y, [&](int x) {
      track_.set(x, y);
      for (unsigned mk = mask_[region.at(x, y)]; mk != 0; mk &= mk - 1) {
        const int d = std::countr_zero(mk);
        track_.set(x + kDx[d], y + kDy[d]);
      }
    });
  }
  cross_givers_.clear();
  retop_.clear();
  const auto off = neighbour_offsets(w);
  for (int y = std::max(0, first - 1); y <= std::min(h - 1, last + 1); ++y) {
    if (!crosses(y - 1) && !crosses(y) && !crosses(y + 1)) continue;  // nothing tracked in the row
    track_.for_each_in_row(y, [&](int x) {
      const std::size_t k = region.at(x, y);
      const std::uint8_t top = region.mat[k];
      // What it took: of its top material, and of another (one material: see takes).
      double same = 0.0, other = 0.0;
      std::uint8_t other_index = top;
      const auto take = [&](std::size_t nk, int d) {
        if (!(mask_[nk] & (1u << (d ^ 1)))) return;
        const double got = std::min(q_[nk], cap_[k]);
        if (region.mat[nk] == top || rigid_[region.mat[nk]]) {  // a road's loose soil lands as the receiver's
          same += got;
        } else {
          other += got;
          other_index = region.mat[nk];
        }
      };
      if (cap_[k] > 0.0) {
        if (x > 0 && y > 0 && x < w - 1 && y < h - 1) {
          // Unrolled: each direction's bit a constant (most neighbours gave it nothing).
#pragma GCC unroll 8
          for (int d = 0; d < 8; ++d) take(k + off[d], d);
        } else {
          for (int d = 0; d < 8; ++d) {
            const int nx = x + kDx[d], ny = y + kDy[d];
            if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
            take(region.at(nx, ny), d);
          }
        }
      }
      const double gave = out_[k];
      if (gave == 0.0 && same == 0.0 && other == 0.0) return;
      switch (kind_[k]) {
        case kCrust: {  // what it took of its lower material went under its top layer
          // (spent_ is this pass's only for a column that gave: out_ is cleared after each pass.)
          const double left = gave > 0.0 && spent_[k] ? 0.0 : thick_[k] - gave;
          thick_[k] = left + same;
          if (!(thick_[k] > 0.0)) {  // its top layer all given away: its lower material, unlayered
            kind_[k] = kUnlayered;
            retop_.push_back({k, lower_[k]});
          }
          dirty_.set(x, y);
          break;
        }
        case kBroken:  // all of it the lower material: only the boundary follows the sinkage
          dirty_.set(x, y);
          break;
        default:
          if (other > 0.0 && !rigid_[top]) {  // a new top layer of the other material
            kind_[k] = kCrust;
            lower_[k] = top;
            thick_[k] = other;
            retop_.push_back({k, other_index});
            dirty_.set(x, y);
          }
      }
    });
  }
  for (const Retop& r : retop_) region.mat[r.k] = r.top;
}

namespace {

// Whether writing c back would leave its tile as gathered: the same painted index, the
// same boundary bits and the same stored lower index (scatter stores 0 for an unlayered
// column). Only a region gathered with layers knows its columns' painted indices.
bool as_gathered(const Region& region, const Region::Relayered& c) {
  if (region.layer.empty()) return false;
  const std::uint8_t lower = c.layer.layered() ? c.layer.lower : std::uint8_t{0};
  return c.index == region.upper[c.k] &&
         std::bit_cast<std::uint64_t>(c.layer.boundary) == std::bit_cast<std::uint64_t>(region.layer.boundary[c.k]) &&
         lower == region.layer.lower[c.k];
}

}  // namespace

void ErodeStage::settle_layers(Region& region) const {
  if (!map_) return;
  for (int y = 0; y < region.h; ++y)
    dirty_.for_each_in_row(y, [&](int x) {
      const std::size_t k = region.at(x, y);
      Region::Relayered c{k, region.mat[k], ColumnLayer{}};
      if (kind_[k] != kUnlayered) {
        // The boundary is where the sinkage meets the top layer's bottom: the sinkage now
        // (after any loosening) plus its thickness.
        c.layer = {region.sink[k] + thick_[k], lower_[k]};
        if (kind_[k] == kBroken) c.index = region.upper[k];
      }
      // A column whose layering came back to what its tile holds is not written, so its
      // tile is not stamped repainted for it (deltas, the renderer and the heightfield's
      // friction skip a tile nothing changed in). On the bench's map 46 % of the columns
      // erosion tracked, nearly all of them crusts whose boundary ended where it was.
      if (!as_gathered(region, c)) region.relayered.push_back(c);
    });
}

}  // namespace shore::terrain

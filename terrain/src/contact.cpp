// The soil's half of a body's contact (shore/terrain/contact.h): bottom elements with
// sub-cell coverage at the footprint's edges, and walls where soil stands beside the body.

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "bedrock_depth.h"
#include "layers.h"
#include "shore/core/det_math.h"
#include "shore/core/error.h"
#include "shore/terrain/bekker.h"
#include "shore/terrain/shear.h"
#include "terrain_impl.h"
#include "validation.h"

namespace shore::terrain {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Bisections of the footprint's edge between a covered and an uncovered column centre: the
// edge to 1/64 of a cell (the midpoint of a 1/32 bracket), so a plate's area does not depend on where its edges fall.
constexpr int kEdgeBisections = 5;
// Underside slopes beyond this (87 degrees: the sides of a ball or a wheel seen from above)
// are capped, so the plan area over the normal's vertical share stays finite.
constexpr double kMaxSlope = 20.0;
// One-sided slopes further apart than half the larger plus this meet at an edge, not on a
// smooth surface (a 0.3 m wheel's slopes at 1 cm differ by 0.03 near its bottom).
constexpr double kCreaseSlope = 0.1;
// ContactElement::pressure_rate: the secant over the next half cell of pressing where a column
// is pressed less than 4 such steps deep, Bekker's tangent beyond (there the two differ by
// less than |n - 1| / 16: 0.6 % for sand's n = 1.1).
constexpr double kRateStep = 0.5;
constexpr double kRateTangentSteps = 4.0;
// The four axis directions: +x, -x, +y, -y.
constexpr int kSx[4] = {1, -1, 0, 0};
constexpr int kSy[4] = {0, 0, 1, -1};

/// Soil state of a rectangle of columns, row-major.
struct SoilWindow {
  GridRect r;
  std::vector<double> top, sink, bed;
  std::vector<std::uint8_t> mat;   ///< palette index; empty with a one-entry palette
  std::vector<ColumnLayer> layer;  ///< layering (layers.h); empty while the terrain has none

  [[nodiscard]] bool inside(std::int64_t i, std::int64_t j) const {
    return i >= r.i0 && j >= r.j0 && i < r.i0 + r.nx && j < r.j0 + r.ny;
  }
  [[nodiscard]] std::size_t at(std::int64_t i, std::int64_t j) const {
    return static_cast<std::size_t>((j - r.j0) * r.nx + (i - r.i0));
  }
};

void read_soil(const TileStore& store, const BedrockDepth& depth, bool with_materials, bool with_layers,
               const GridRect& r, SoilWindow& out) {
  out.r = r;
  const std::size_t size = static_cast<std::size_t>(r.nx) * static_cast<std::size_t>(r.ny);
  out.top.resize(size), out.sink.resize(size), out.bed.resize(size);
  if (with_materials)
    out.mat.assign(size, 0);
  else
    out.mat.clear();
  if (with_layers)
    out.layer.assign(size, ColumnLayer{});
  else
    out.layer.clear();
  store.for_each_run(r, [&](const Tile* t, const TileRun& run) {
    const std::size_t dst = static_cast<std::size_t>(run.y) * static_cast<std::size_t>(r.nx) + run.x;
    if (with_layers && t && t->layered())
      for (int k = 0; k < run.count; ++k) out.layer[dst + k] = t->layer(run.local + k);
    if (with_materials && t && !t->material.empty())
      std::copy_n(t->material.data() + run.local, run.count, out.mat.data() + dst);
    for (int k = 0; k < run.count; ++k) {
      if (t) {
        out.top[dst + k] = t->height[run.local + k];
        out.sink[dst + k] = t->sinkage[run.local + k];
        out.bed[dst + k] = t->base[run.local + k] - depth.at(t->material, run.local + k);
      } else {
        const double b = store.base_at(r.i0 + run.x + k, r.j0 + run.y);
        out.top[dst + k] = b, out.sink[dst + k] = 0.0, out.bed[dst + k] = b - depth.at(0);
      }
    }
  });
}

/// Where the footprint's edge lies between the centre of a covered column (t = 0) and the
/// centre of its uncovered neighbour (t = 1), by bisection with the probe; half way without.
double edge_position(const SurfaceProbe* probe, double x, double y, double dx, double dy) {
  if (probe == nullptr) return 0.5;
  double inside = 0.0, outside = 1.0;
  for (int b = 0; b < kEdgeBisections; ++b) {
    const double mid = 0.5 * (inside + outside);
    (probe->lower_at(x + mid * dx, y + mid * dy) < kInf ? inside : outside) = mid;
  }
  return 0.5 * (inside + outside);
}

/// The body's area over an uncovered column whose cell its footprint enters.
struct Fringe {
  std::int64_t i, j;
  double share;        ///< of the cell
  double cx, cy;       ///< centroid of the covered part, m
  std::size_t source;  ///< raster index of the covered neighbour
};

/// A patch's working arrays, kept between calls (one set per thread) so a body's contact
/// each substep reuses them instead of allocating and zeroing a window's worth again.
struct PatchScratch {
  SoilWindow soil;                                   // the window and a one-column ring
  std::vector<double> fx, fy, loss_lo_x, loss_lo_y;  // per raster column, see cover_footprint
  std::vector<unsigned char> covered;                // the window and its ring, row-major
  std::vector<unsigned char> open_sides;             // per raster column, see mark_covered
  std::vector<unsigned char> touching;               // per raster column
  std::vector<Fringe> fringe;
};

class PatchBuilder {
 public:
  PatchBuilder(const TerrainSettings& s, std::span<const Material> palette, const EnvelopeRaster& env,
               std::span<const double> shear, const SurfaceProbe* probe, PatchScratch& scratch, ContactPatch& out)
      : s_(s),
        palette_(palette),
        env_(env),
        shear_(shear),
        probe_(probe),
        soil_(scratch.soil),
        out_(out),
        fx_(scratch.fx),
        fy_(scratch.fy),
        loss_lo_x_(scratch.loss_lo_x),
        loss_lo_y_(scratch.loss_lo_y),
        covered_(scratch.covered),
        open_sides_(scratch.open_sides),
        touching_(scratch.touching),
        fringe_(scratch.fringe) {
    fringe_.clear();
  }

  void build() {
    find_candidates();
    mark_covered();
    cover_footprint();
    out_.patch_width = patch_width();
    add_bottom_elements();
    add_fringe_elements();
    add_walls();
  }

 private:
  // The box of raster columns that can touch the soil or stand beside a wall: the rest of a
  // body's footprint (a wheel's upper half, say) lies too high above every column of the
  // window to do either, and every later loop skips it. A column touches only where its
  // underside lies at most (top + tolerance) + its sinkage above its own column (the elastic
  // reach is at most the sinkage, see touches), so at most `reach` (that sum's largest value
  // in the window, rounded the same way); a wall needs soil beside it higher than underside +
  // tolerance, so at most the highest top.
  void find_candidates() {
    highest_top_ = -kInf;
    double reach = -kInf;
    for (std::size_t k = 0; k < soil_.top.size(); ++k) {
      highest_top_ = std::max(highest_top_, soil_.top[k]);
      reach = std::max(reach, (soil_.top[k] + s_.contact_tolerance) + std::max(0.0, soil_.sink[k]));
    }
    x0_ = env_.nx, x1_ = 0, y0_ = env_.ny, y1_ = 0;
    for (int y = 0; y < env_.ny; ++y) {
      const double* row = env_.lower.data() + static_cast<std::size_t>(y) * env_.nx;
      int first = -1, last = -1;
      for (int x = 0; x < env_.nx; ++x)
        if (row[x] <= reach || row[x] + s_.contact_tolerance < highest_top_) {
          if (first < 0) first = x;
          last = x;
        }
      if (first < 0) continue;
      x0_ = std::min(x0_, first), x1_ = std::max(x1_, last + 1);
      y0_ = std::min(y0_, y), y1_ = y + 1;
    }
    if (x0_ >= x1_) x0_ = x1_ = y0_ = y1_ = 0;
  }

  /// Calls fn(x, y, k) for every raster column of the candidates' box, row by row (k: its
  /// raster index).
  template <class Fn>
  void for_each_candidate(Fn&& fn) const {
    for (int y = y0_; y < y1_; ++y)
      for (int x = x0_; x < x1_; ++x) fn(x, y, static_cast<std::size_t>(y) * env_.nx + x);
  }

  void mark_covered() {
    const std::size_t stride = static_cast<std::size_t>(env_.nx) + 2;
    covered_.assign(stride * static_cast<std::size_t>(env_.ny + 2), 0);
    if (x0_ >= x1_) return;
    // The candidates and a one-column ring around them (their neighbours' coverage).
    const int rx0 = std::max(0, x0_ - 1), rx1 = std::min(env_.nx, x1_ + 1);
    for (int y = std::max(0, y0_ - 1); y < std::min(env_.ny, y1_ + 1); ++y)
      for (int x = rx0; x < rx1; ++x)
        covered_[static_cast<std::size_t>(y + 1) * stride + static_cast<std::size_t>(x + 1)] =
            env_.lower[static_cast<std::size_t>(y) * env_.nx + x] < kInf ? 1 : 0;
    // Bit d of open_sides_: neighbour d (kSx, kSy) is not covered. Most of a footprint is
    // inside it, and there the edge and wall loops need not look at the neighbours.
    open_sides_.resize(env_.lower.size());
    for (int y = y0_; y < y1_; ++y) {
      // Rows y - 1, y and y + 1 of the window in the ring's frame (column x at index x + 1).
      const unsigned char* below = covered_.data() + static_cast<std::size_t>(y) * stride;
      const unsigned char* row = below + stride;
      const unsigned char* above = row + stride;
      for (int x = x0_; x < x1_; ++x)
        open_sides_[static_cast<std::size_t>(y) * env_.nx + x] = static_cast<unsigned char>(
            (row[x + 2] ? 0 : 1) | (row[x] ? 0 : 2) | (above[x + 1] ? 0 : 4) | (below[x + 1] ? 0 : 8));
    }
  }
  [[nodiscard]] double column_x(std::int64_t i) const { return s_.origin_x + static_cast<double>(i) * s_.cell; }
  [[nodiscard]] double column_y(std::int64_t j) const { return s_.origin_y + static_cast<double>(j) * s_.cell; }
  /// The material of a window column: its own with a map, else the terrain's one.
  [[nodiscard]] const Material& material_of(std::size_t soil_index) const {
    return soil_.mat.empty() ? s_.material : palette_[soil_.mat[soil_index]];
  }
  /// The material a window column shows: its lower layer's once its sinkage is beyond its
  /// crust (broken through), else material_of.
  [[nodiscard]] const Material& exposed_of(std::size_t soil_index) const {
    if (soil_.layer.empty()) return material_of(soil_index);
    return palette_[soil_.layer[soil_index].exposed(soil_.mat[soil_index], soil_.sink[soil_index])];
  }
  [[nodiscard]] bool layered(std::size_t soil_index) const {
    return !soil_.layer.empty() && soil_.layer[soil_index].layered();
  }
  /// Bekker's pressure of a window column at sinkage z (its two-piece law if layered).
  [[nodiscard]] double pressure_at(std::size_t soil_index, double b, double z) const {
    if (!layered(soil_index)) return bekker::pressure(material_of(soil_index), b, z);
    return layered_pressure(soil_.layer[soil_index], soil_.mat[soil_index], z,
                            [&](std::uint8_t m, double zz) { return bekker::pressure(palette_[m], b, zz); });
  }
  [[nodiscard]] bool touches(double lower, std::size_t soil_index) const {
    const double reach = soil_.top[soil_index] + s_.contact_tolerance;
    // The elastic reach (a pow) only where it decides: it is >= 0 and <= the sinkage, and
    // rounding is monotonic, so these two answers are the full test's.
    if (lower <= reach) return true;
    if (lower > reach + soil_.sink[soil_index]) return false;
    return lower <= reach + rebound(soil_index);
  }
  /// How far a relieved column springs back (its elastic reach), m: p_yield(z) / k_u, at
  /// most its sinkage z (see unloading_stiffness), with
  /// Bekker's b bounded by the window (the footprint is not known yet; a wider b lowers
  /// p_yield by k_c / b only). 0 for rigid-plastic soil, fresh columns and bedrock.
  [[nodiscard]] double rebound(std::size_t soil_index) const {
    const Material& m = exposed_of(soil_index);
    const double z = soil_.sink[soil_index];
    if (!(m.unload_modulus > 0.0) || !(z > 0.0) || m.rigid || soil_.top[soil_index] <= soil_.bed[soil_index])
      return 0.0;
    const double b = static_cast<double>(std::min(env_.nx, env_.ny)) * s_.cell;
    return std::min(pressure_at(soil_index, b, z) / (m.unload_modulus * z), z);
  }
  /// Wong's k_u = A_u z, stiffened where it would let the column spring back above the
  /// ground it was pressed from (more than its sinkage z: soft exponents n < 1 at small z).
  [[nodiscard]] static double unloading_stiffness(const Material& m, double z, double pressure) {
    return std::max(m.unload_modulus * z, pressure / z);
  }
  /// Gives `el` (its pressure already set) the elastic unloading branch where the body lies
  /// at or above the column's top.
  void set_unloading(std::size_t soil_index, ContactElement& el) const {
    const Material& m = exposed_of(soil_index);
    const double z = soil_.sink[soil_index], gap = el.point.z - soil_.top[soil_index];
    if (!(m.unload_modulus > 0.0) || !(z > 0.0) || !(gap >= 0.0) || !(el.pressure < kInf)) return;
    el.stiffness = unloading_stiffness(m, z, el.pressure);
    el.preload = std::max(0.0, el.pressure - el.stiffness * gap);
  }
  [[nodiscard]] double shear_at(std::size_t raster_index) const { return shear_.empty() ? 0.0 : shear_[raster_index]; }

  // Touching columns, with the share of their cell the body covers along x and y: whole
  // inside the footprint, less where its edge runs through the cell; the part of an edge
  // that reaches into an uncovered neighbour's cell becomes a fringe.
  void cover_footprint() {
    const std::size_t size = env_.lower.size();
    // Only touching columns' shares are ever read: they are set there, below.
    fx_.resize(size), fy_.resize(size), loss_lo_x_.resize(size), loss_lo_y_.resize(size);
    touching_.assign(size, 0);
    for_each_candidate([&](int x, int y, std::size_t k) {
      const double e = env_.lower[k];
      const std::int64_t i = env_.i0 + x, j = env_.j0 + y;
      if (!(e < kInf) || !touches(e, soil_.at(i, j))) return;
      touching_[k] = 1;
      fx_[k] = fy_[k] = 1.0, loss_lo_x_[k] = loss_lo_y_[k] = 0.0;
      ++out_.touching_columns;
      if (open_sides_[k] == 0) return;
      for (int d = 0; d < 4; ++d) cover_edge(k, i, j, d);
    });
  }

  void cover_edge(std::size_t k, std::int64_t i, std::int64_t j, int d) {
    if (!(open_sides_[k] & (1u << d))) return;  // the neighbour is covered
    const double t = edge_position(probe_, column_x(i), column_y(j), kSx[d] * s_.cell, kSy[d] * s_.cell);
    const double loss = std::max(0.0, 0.5 - t), gain = std::max(0.0, t - 0.5);
    const bool along_x = kSx[d] != 0;
    (along_x ? fx_ : fy_)[k] -= loss;
    if (kSx[d] < 0) loss_lo_x_[k] = loss;
    if (kSy[d] < 0) loss_lo_y_[k] = loss;
    if (gain <= 0.0) return;
    // The covered strip of the neighbour's cell: from its near side, gain of a cell wide.
    const double near = 0.5 * s_.cell * (1.0 - gain);  // centroid, back from the neighbour's centre
    const double cx = column_x(i + kSx[d]) - kSx[d] * near, cy = column_y(j + kSy[d]) - kSy[d] * near;
    fringe_.push_back({i + kSx[d], j + kSy[d], gain, cx, cy, k});
  }

  // Bekker's b: the smaller extent of the touching area, its widest row against its
  // tallest column (exact for a rectangle whatever its edges' offsets).
  double patch_width() const {
    std::vector<double> row(static_cast<std::size_t>(env_.ny), 0.0), col(static_cast<std::size_t>(env_.nx), 0.0);
    for_each_candidate([&](int x, int y, std::size_t k) {
      if (!touching_[k]) return;
      row[static_cast<std::size_t>(y)] += fx_[k];
      col[static_cast<std::size_t>(x)] += fy_[k];
    });
    for (const Fringe& f : fringe_) {
      const auto x = static_cast<std::size_t>(f.source % static_cast<std::size_t>(env_.nx));
      const auto y = static_cast<std::size_t>(f.source / static_cast<std::size_t>(env_.nx));
      (f.j == env_.j0 + static_cast<std::int64_t>(y) ? row[y] : col[x]) += f.share;
    }
    const double widest = *std::max_element(row.begin(), row.end());
    const double tallest = *std::max_element(col.begin(), col.end());
    return std::max(std::min(widest, tallest), 1.0) * s_.cell;
  }

  /// The sinkage a column pressed to `lower` bears at: its own plus how far `lower` lies below its top.
  [[nodiscard]] double sinkage_at(std::size_t soil_index, double lower) const {
    return soil_.sink[soil_index] + std::max(0.0, soil_.top[soil_index] - lower);
  }
  /// Bekker's yield pressure of a column pressed to `lower`, loosened by its shear (shear::loosening).
  [[nodiscard]] double yield_pressure(std::size_t soil_index, double lower, double j) const {
    const double top = soil_.top[soil_index], bed = soil_.bed[soil_index];
    const Material& m = exposed_of(soil_index);
    if (m.rigid || lower <= bed || top <= bed) return kInf;
    return pressure_at(soil_index, out_.patch_width, sinkage_at(soil_index, lower) * shear::loosening(m, j));
  }
  /// Gives `el` (its pressure already set) how fast its pressure grows as the body presses
  /// on: Bekker's tangent n p / z where the column is pressed deeper than a few steps, else
  /// the secant over the next step (at zero sinkage the tangent is 0 or infinite).
  void set_pressure_rate(std::size_t soil_index, double j, ContactElement& el) const {
    if (!(el.pressure < kInf)) return;
    const Material& m = exposed_of(soil_index);
    const double z = sinkage_at(soil_index, el.point.z), step = kRateStep * s_.cell;
    // A layered column takes the tangent only where the next step stays within its crust
    // (there its law is the crust's); near and beyond the boundary the secant, as the
    // tangent jumps there.
    const bool one_piece =
        !layered(soil_index) || (z + step) * shear::loosening(m, j) <= soil_.layer[soil_index].boundary;
    if (z >= kRateTangentSteps * step && one_piece) {
      el.pressure_rate = m.bekker_n * el.pressure / z;
      return;
    }
    const double further = pressure_at(soil_index, out_.patch_width, (z + step) * shear::loosening(m, j));
    el.pressure_rate = std::max(0.0, further - el.pressure) / step;
  }

  /// Unit normal of the underside at raster column (x, y): its slopes from the covered
  /// neighbours (one-sided at the footprint's edge).
  void underside_normal(int x, int y, ContactElement& el) const {
    const std::size_t k = static_cast<std::size_t>(y) * env_.nx + x;
    const double e = env_.lower[k];
    const unsigned open = open_sides_[k];
    // The slope along one axis (step: the raster offset of the next column along it; its
    // open-side bits: up, then down): the central difference where the surface is smooth;
    // where the two one-sided slopes disagree (an edge of a box: the bottom on one side, a
    // face on the other) the gentler one, which belongs to the surface the column touches.
    auto slope = [&](std::size_t step, unsigned up_bit, unsigned down_bit) {
      const bool up = !(open & up_bit), down = !(open & down_bit);
      const double s_up = up ? (env_.lower[k + step] - e) / s_.cell : 0.0;
      const double s_down = down ? (e - env_.lower[k - step]) / s_.cell : 0.0;
      if (up != down) return up ? s_up : s_down;
      if (!up) return 0.0;
      if (std::fabs(s_up - s_down) <= 0.5 * std::max(std::fabs(s_up), std::fabs(s_down)) + kCreaseSlope)
        return 0.5 * (s_up + s_down);
      return std::fabs(s_up) < std::fabs(s_down) ? s_up : s_down;
    };
    const double gx = std::clamp(slope(1, 1, 2), -kMaxSlope, kMaxSlope),
                 gy = std::clamp(slope(static_cast<std::size_t>(env_.nx), 4, 8), -kMaxSlope, kMaxSlope);
    const double norm = std::sqrt(gx * gx + gy * gy + 1.0);
    el.normal.x = -gx / norm, el.normal.y = -gy / norm, el.normal.z = 1.0 / norm;
  }

  void add_bottom_elements() {
    const double cell_area = s_.cell * s_.cell;
    for_each_candidate([&](int x, int y, std::size_t k) {
      if (!touching_[k]) return;
      const std::int64_t i = env_.i0 + x, j = env_.j0 + y;
      ContactElement el;
      el.i = i, el.j = j;
      el.raster_index = static_cast<std::int32_t>(k);
      underside_normal(x, y, el);
      // The body's surface over the covered part of the cell: the plan area over the
      // normal's vertical share, so the soil's push has Bekker's vertical component.
      el.area = std::max(0.0, fx_[k]) * std::max(0.0, fy_[k]) * cell_area / el.normal.z;
      // Centroid of the covered part of the cell.
      el.point.x = column_x(i) + 0.5 * s_.cell * (loss_lo_x_[k] - (1.0 - fx_[k] - loss_lo_x_[k]));
      el.point.y = column_y(j) + 0.5 * s_.cell * (loss_lo_y_[k] - (1.0 - fy_[k] - loss_lo_y_[k]));
      el.point.z = env_.lower[k];
      el.pressure = yield_pressure(soil_.at(i, j), el.point.z, shear_at(k));
      set_pressure_rate(soil_.at(i, j), shear_at(k), el);
      set_unloading(soil_.at(i, j), el);
      out_.area += el.area * el.normal.z;
      out_.elements.push_back(el);
    });
  }

  void add_fringe_elements() {
    const double cell_area = s_.cell * s_.cell;
    for (const Fringe& f : fringe_) {
      const double lower = env_.lower[f.source];
      if (!soil_.inside(f.i, f.j) || !touches(lower, soil_.at(f.i, f.j))) continue;
      const auto sx = static_cast<int>(f.source % static_cast<std::size_t>(env_.nx));
      const auto sy = static_cast<int>(f.source / static_cast<std::size_t>(env_.nx));
      ContactElement el;
      el.i = f.i, el.j = f.j;
      el.raster_index = static_cast<std::int32_t>(f.source);
      // Across the edge the strip is as wide as the covered neighbour's cell.
      const double across = f.j == env_.j0 + sy ? fy_[f.source] : fx_[f.source];
      el.point.x = f.cx, el.point.y = f.cy, el.point.z = lower;
      underside_normal(sx, sy, el);
      el.area = f.share * std::max(0.0, across) * cell_area / el.normal.z;
      el.pressure = yield_pressure(soil_.at(f.i, f.j), lower, shear_at(f.source));
      set_pressure_rate(soil_.at(f.i, f.j), shear_at(f.source), el);
      set_unloading(soil_.at(f.i, f.j), el);
      out_.area += el.area * el.normal.z;
      out_.elements.push_back(el);
    }
  }

  // Soil beside the footprint standing above the underside pushes on the body's side.
  void add_walls() {
    for_each_candidate([&](int x, int y, std::size_t k) {
      const double e = env_.lower[k];
      // No soil beside the body stands above it here (a wheel's upper part, say).
      if (open_sides_[k] == 0 || !(e + s_.contact_tolerance < highest_top_)) return;
      const std::int64_t i = env_.i0 + x, j = env_.j0 + y;
      for (int d = 0; d < 4; ++d) {
        const std::int64_t ui = i + kSx[d], uj = j + kSy[d];
        if (!(open_sides_[k] & (1u << d)) || !soil_.inside(ui, uj)) continue;
        const std::size_t u = soil_.at(ui, uj);
        const double height = soil_.top[u] - e;
        if (!(height > s_.contact_tolerance)) continue;
        const Material& m = material_of(u);  // the wall's soil
        const double k_modulus = m.bekker_kc / out_.patch_width + m.bekker_kphi;
        ContactElement el;
        el.i = ui, el.j = uj;
        el.wall = true;
        el.normal.x = -kSx[d], el.normal.y = -kSy[d], el.normal.z = 0.0;
        el.area = s_.cell * height;
        el.pressure =
            (m.rigid || soil_.bed[u] > e) ? kInf : k_modulus * det::pow(height, m.bekker_n) / (m.bekker_n + 1.0);
        el.point.x = column_x(i) + 0.5 * kSx[d] * s_.cell;
        el.point.y = column_y(j) + 0.5 * kSy[d] * s_.cell;
        el.point.z = e + 0.5 * height;
        out_.elements.push_back(el);
      }
    });
  }

  const TerrainSettings& s_;
  std::span<const Material> palette_;
  const EnvelopeRaster& env_;
  std::span<const double> shear_;
  const SurfaceProbe* probe_;
  const SoilWindow& soil_;
  ContactPatch& out_;
  std::vector<double>&fx_, &fy_, &loss_lo_x_, &loss_lo_y_;
  std::vector<unsigned char>& covered_;     // the window and a one-column ring, row-major
  double highest_top_ = -kInf;              // m, the highest soil top in the window and its ring
  int x0_ = 0, x1_ = 0, y0_ = 0, y1_ = 0;   // raster columns [x0_, x1_) x rows [y0_, y1_): the candidates' box
  std::vector<unsigned char>& open_sides_;  // per raster column, see mark_covered
  std::vector<unsigned char>& touching_;
  std::vector<Fringe>& fringe_;
};

}  // namespace

void Terrain::contact(const EnvelopeRaster& envelope, std::span<const double> shear, const SurfaceProbe* probe,
                      ContactPatch& out) const {
  check_envelope(&envelope, "terrain.Terrain.contact.envelope");
  if (!shear.empty() && shear.size() != envelope.lower.size())
    throw InvalidSetting("terrain.Terrain.contact.shear.size()", detail::to_text(shear.size()),
                         "must be 0 or the envelope's nx * ny = " + detail::to_text(envelope.lower.size()));
  out.clear();
  if (envelope.nx == 0 || envelope.ny == 0) return;
  thread_local PatchScratch scratch;
  // The window and a one-column ring (fringes and walls lie there).
  const bool layered = impl_->tiles.layered();
  read_soil(impl_->tiles, BedrockDepth(impl_->palette, impl_->s.material.soil_depth),
            impl_->palette.size() > 1 || layered, layered,
            {envelope.i0 - 1, envelope.j0 - 1, envelope.nx + 2, envelope.ny + 2}, scratch.soil);
  PatchBuilder(impl_->s, impl_->palette, envelope, shear, probe, scratch, out).build();
}

}  // namespace shore::terrain

// rally: a four-wheel-drive raycast car (Bullet's VehicleDemo set-up: RaycastCar, built as
// Shore's SoilVehicle so its wheels grip as the soil does) driven by a script up a valley of
// rolling sand, through a mud patch and into a ford, where it stalls in the muddy bed with
// its wheels spinning. Its wheels sink and leave ruts (TerrainCoupling::add_vehicle; its rays
// cast with Shore's SoilRaycaster, so they rise onto soil that carries more than their load),
// its chassis and wheels float and drag in the ford (WaterCoupling::add_body, add_vehicle)
// and make a wake. The camera follows the car; the viewer drives it with the arrow keys.
// One terrain with a material map: sand, with mud painted where the valley floor is wet; the
// hollow's mud has dried into a crust 1.5 cm thick (a layer in depth over the wet mud) that the
// car's wheels break through.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "shore/bullet/terrain_coupling.h"
#include "shore/bullet/water_coupling.h"
#include "shore/scenes/film.h"
#include "shore/scenes/raycast_car.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/scene.h"
#include "shore/scenes/soil_cases.h"
#include "shore/scenes/soil_view.h"
#include "shore/scenes/world.h"
#include "shore/terrain/height_source.h"
#include "shore/terrain/material.h"
#include "shore/terrain/terrain.h"
#include "shore/water/surface.h"

namespace shore::scenes {
namespace {

constexpr double kX0 = -8.0, kX1 = 34.0;  // m, the land along the valley
constexpr double kHalfY = 12.0;           // m, the land across it
constexpr double kFordX = 21.0;           // m, centre of the ford
constexpr double kFordRadius = 6.0;       // m
constexpr double kFordDepth = 0.9;        // m the valley floor drops at the ford's centre
constexpr double kWaterLevel = -0.3;      // m, the ford's still water
constexpr double kMudX = 10.0;            // m, centre of the mud patch
constexpr double kMudRadius = 2.0;        // m
constexpr double kCrustDepth = 0.015;     // m of dried mud over the hollow's wet mud
constexpr double kStartX = -4.0;          // m, where the car starts
constexpr double kEngine = 1400.0;        // N per driven wheel, the script's throttle
constexpr double kWheelWidth = 0.3;       // m

double bump(double r, double radius) {  // 1 at the centre, 0 from radius on, smooth (polynomial)
  const double u = std::clamp(1.0 - (r * r) / (radius * radius), 0.0, 1.0);
  return u * u;
}

/// y of the valley floor's line at x: it winds gently.
double floor_line(double x) { return 1.5 * (bump(x - 6.0, 14.0) - bump(x - 26.0, 10.0)); }

/// The valley: its floor winds gently, its sides rise to low hills, lattice noise roughens
/// it, and it dips into a ford. Polynomials and lattice noise only: the same bits on every
/// machine.
class Valley final : public terrain::HeightSource {
 public:
  Valley()
      : noise_(terrain::LatticeNoiseSettings{
            .seed = 7, .spacing = 5.0, .amplitude = 0.35, .mean = 0.0, .octaves = 3, .persistence = 0.45}) {}
  [[nodiscard]] double height(double x, double y) const override {
    return shape(x, y, floor_line(x), noise_.height(x, y));
  }
  /// out[k] = height(x, ys[k]), bit for bit: the noise along y (LatticeNoise::heights_along_y)
  /// and the floor's line once.
  void heights_along_y(double x, std::span<const double> ys, std::span<double> out) const {
    noise_.heights_along_y(x, ys, out);
    const double centre = floor_line(x);
    for (std::size_t k = 0; k < ys.size(); ++k) out[k] = shape(x, ys[k], centre, out[k]);
  }

 private:
  /// The valley at (x, y) from the floor's line there and the noise's height.
  static double shape(double x, double y, double centre, double noise) {
    const double off = (y - centre) / kHalfY;
    const double sides = 2.2 * off * off * (3.0 - 2.0 * std::abs(off));  // low hills each side
    const double floor_calm = 1.0 - 0.75 * bump(y - centre, 3.0);        // a smoother track along the floor
    // Beyond 1.5 radii of the ford's centre its bump is 0 whatever hypot's rounding, and
    // subtracting that 0 changes no bit: hypot (a library call) only near the ford.
    const double dx = x - kFordX, dy = y - centre;
    const double ford =
        dx * dx + dy * dy > 2.25 * kFordRadius * kFordRadius ? 0.0 : kFordDepth * bump(std::hypot(dx, dy), kFordRadius);
    return sides + floor_calm * noise - ford;
  }

  terrain::LatticeNoise noise_;
};

/// The valley's heights at the columns of the land and far around it, worked out once and
/// then looked up. A column's base height is asked again and again: by each heightfield tile
/// and soil tile made over it (soil tiles idle for a while are released and made afresh),
/// and by each grain of spray in flight or landing where no soil tile is yet; the spray's
/// flight bounds read the whole window its grains may reach (the land). Columns
/// are worked out a block of kBlock x kBlock at a time, the first time one of them is asked,
/// a column of the block at once (Valley::heights_along_y: the noise's splines along x shared
/// by the column's points, about 5 times fewer); a block's memory is taken then, so only
/// the blocks asked cost any. Answers bit for bit what Valley does: only a point that is
/// exactly a column's centre (origin + i cell, as the terrain asks) is kept, any other is
/// worked out. Filled as asked, from any thread: a block is published whole (two threads
/// working out the same block get the same values; one copy is kept).
class CachedValley final : public terrain::HeightSource {
 public:
  /// Columns of `cell` m from (origin_x, origin_y) over the land and kMargin around it.
  CachedValley(double cell, double origin_x, double origin_y) : cell_(cell), ox_(origin_x), oy_(origin_y) {
    i0_ = static_cast<std::int64_t>(std::floor((kX0 - kMargin - ox_) / cell_));
    j0_ = static_cast<std::int64_t>(std::floor((-kHalfY - kMargin - oy_) / cell_));
    nx_ = static_cast<std::int64_t>(std::ceil((kX1 + kMargin - ox_) / cell_)) - i0_ + 1;
    ny_ = static_cast<std::int64_t>(std::ceil((kHalfY + kMargin - oy_) / cell_)) - j0_ + 1;
    bx_ = (nx_ + kBlock - 1) / kBlock;
    const std::int64_t blocks = bx_ * ((ny_ + kBlock - 1) / kBlock);
    if (blocks > kMaxBlocks) return;  // so coarse a cell needs no keeping
    blocks_ = std::vector<std::atomic<double*>>(static_cast<std::size_t>(blocks));
    for (std::atomic<double*>& b : blocks_) b.store(nullptr, std::memory_order_relaxed);
  }
  CachedValley(const CachedValley&) = delete;
  CachedValley& operator=(const CachedValley&) = delete;
  ~CachedValley() override {
    for (std::atomic<double*>& b : blocks_) delete[] b.load(std::memory_order_relaxed);
  }
  [[nodiscard]] double height(double x, double y) const override {
    const std::optional<Column> c = column(x, y);
    if (!c) return valley_.height(x, y);
    const double* block = block_of(*c);
    return block[(c->j % kBlock) * kBlock + c->i % kBlock];
  }
  /// A row of this grid's columns copied from the blocks (worked out where not yet); any
  /// other row point by point.
  void row(double origin_x, double cell, std::int64_t i0, double y, std::span<double> out) const override {
    const double v = (y - oy_) / cell_;
    const auto j = static_cast<std::int64_t>(std::floor(v + 0.5));
    if (blocks_.empty() || origin_x != ox_ || cell != cell_ || !(std::abs(v) < 1e15) || j < j0_ || j >= j0_ + ny_ ||
        oy_ + static_cast<double>(j) * cell_ != y) {
      HeightSource::row(origin_x, cell, i0, y, out);
      return;
    }
    const auto count = static_cast<std::int64_t>(out.size());
    for (std::int64_t c = 0; c < count;) {
      const std::int64_t i = i0 + c - i0_;
      if (i < 0 || i >= nx_) {  // beyond the kept columns
        out[static_cast<std::size_t>(c)] = valley_.height(ox_ + static_cast<double>(i0 + c) * cell_, y);
        ++c;
        continue;
      }
      const Column at{i, j - j0_};
      const double* from = block_of(at) + (at.j % kBlock) * kBlock + i % kBlock;
      const std::int64_t run = std::min({count - c, kBlock - i % kBlock, nx_ - i});
      std::copy_n(from, run, out.data() + c);
      c += run;
    }
  }

 private:
  static constexpr double kMargin = 64.0;              // m around the land: spray flies off it
  static constexpr std::int64_t kBlock = 64;           // columns a block side (32 kB)
  static constexpr std::int64_t kMaxBlocks = 1 << 16;  // the table of blocks: 512 kB at most

  struct Column {
    std::int64_t i, j;  ///< relative to (i0_, j0_)
  };

  /// The kept column whose centre is exactly (x, y); none for any other point.
  [[nodiscard]] std::optional<Column> column(double x, double y) const {
    if (blocks_.empty()) return std::nullopt;
    const double u = (x - ox_) / cell_, v = (y - oy_) / cell_;
    if (!(std::abs(u) < 1e15 && std::abs(v) < 1e15)) return std::nullopt;
    // The nearest integers by floor(q + 0.5), inline (llround is a library call): any
    // rounding will do, as only a point whose column gives back exactly x and y is kept.
    const auto i = static_cast<std::int64_t>(std::floor(u + 0.5)), j = static_cast<std::int64_t>(std::floor(v + 0.5));
    if (i < i0_ || i >= i0_ + nx_ || j < j0_ || j >= j0_ + ny_) return std::nullopt;
    if (ox_ + static_cast<double>(i) * cell_ != x || oy_ + static_cast<double>(j) * cell_ != y) return std::nullopt;
    return Column{i - i0_, j - j0_};
  }

  /// The block holding the column, worked out unless that is done: kBlock x kBlock heights,
  /// row-major (columns past the kept area's edge are worked out too, never asked).
  [[nodiscard]] const double* block_of(const Column& c) const {
    std::atomic<double*>& slot = blocks_[static_cast<std::size_t>((c.j / kBlock) * bx_ + c.i / kBlock)];
    if (const double* b = slot.load(std::memory_order_acquire)) return b;
    auto* block = new double[static_cast<std::size_t>(kBlock * kBlock)];
    const std::int64_t bi = i0_ + c.i / kBlock * kBlock, bj = j0_ + c.j / kBlock * kBlock;
    std::array<double, kBlock> ys{}, hs{};
    for (std::int64_t r = 0; r < kBlock; ++r)
      ys[static_cast<std::size_t>(r)] = oy_ + static_cast<double>(bj + r) * cell_;
    for (std::int64_t x = 0; x < kBlock; ++x) {
      valley_.heights_along_y(ox_ + static_cast<double>(bi + x) * cell_, ys, hs);
      for (std::int64_t r = 0; r < kBlock; ++r) block[r * kBlock + x] = hs[static_cast<std::size_t>(r)];
    }
    double* none = nullptr;
    if (slot.compare_exchange_strong(none, block, std::memory_order_acq_rel, std::memory_order_acquire)) return block;
    delete[] block;  // another thread published the same values first
    return none;
  }

  Valley valley_;
  double cell_, ox_, oy_;
  std::int64_t i0_ = 0, j0_ = 0, nx_ = 0, ny_ = 0, bx_ = 0;
  mutable std::vector<std::atomic<double*>> blocks_;  ///< per block, row-major (bx_ a row); null: not yet
};

double land_cell(const SceneOptions& o) { return o.smoke ? std::max(o.cell, 0.08) : o.cell; }

terrain::TerrainSettings land_settings(const SceneOptions& o) {
  terrain::TerrainSettings s = soil_settings(o);
  s.cell = land_cell(o);
  s.material = terrain::Material::sand();
  s.base = std::make_shared<CachedValley>(s.cell, s.origin_x, s.origin_y);
  // Spinning wheels throw sand; each grain in flight asks the valley's height where no soil
  // tile is yet (a noise evaluation where no column is kept): 500 grains at most
  // keep the spray visible and the scene fast.
  s.spray.max_particles = 500;
  // The grains live over the land: one thrown off it is lost (VolumeTotals::lost). Past the
  // land the valley's hills fall away as a cubic (60 m down 36 m from the floor), so a grain
  // thrown over them fell for its whole flight (SpraySettings::max_flight, 10 s) and the
  // flights' landing bounds read the base under a window of 100 m and more.
  s.spray.x_min = kX0, s.spray.x_max = kX1;
  s.spray.y_min = -kHalfY, s.spray.y_max = kHalfY;
  return s;
}

/// Mud dried into a crust: twice as stiff (k_phi) and twice as cohesive as wet mud.
terrain::Material dried_mud() {
  terrain::Material m = terrain::Material::mud();
  m.name = "dried mud";
  m.bekker_kphi *= 2.0;
  m.cohesion *= 2.0;
  return m;
}

water::SurfaceSettings ford_settings(const SceneOptions& o) {
  water::PhysicalParameters phys;
  phys.cell = 2.0 * land_cell(o);
  phys.depth = 0.25;  // the ford's mean depth sets the wave speed
  const double half = kFordRadius + 0.5;
  const int n = static_cast<int>(std::lround(2.0 * half / phys.cell)) + 1;
  water::SurfaceSettings s = water::SurfaceSettings::physical(phys, n, n);
  s.origin_x = kFordX - half;
  s.origin_y = floor_line(kFordX) - half;
  s.rest_height = kWaterLevel;
  s.mode = water::SurfaceMode::vertical_only;
  s.boundary = water::Boundary::vertical_only;
  s.threads = o.threads;
  return s;
}

class Rally final : public Scene {
 public:
  explicit Rally(const SceneOptions& o)
      : o_(o),
        land_(land_settings(o)),
        ford_(ford_settings(o)),
        ground_(world_.world(), land_),
        water_(world_.world(), ford_) {
    land_.set_palette({terrain::Material::sand(), terrain::Material::mud(), dried_mud()});
    land_.paint_disc(kMudX, floor_line(kMudX), kMudRadius, 2);                     // the hollow: dried on top,
    land_.paint_layer_disc(kMudX, floor_line(kMudX), kMudRadius, 1, kCrustDepth);  // wet below
    land_.paint_disc(kFordX, floor_line(kFordX), kFordRadius - 2.0, 1);            // the ford's muddy bed
    water_.fix_shoreline(land_);
    RaycastCarSettings car;
    car.soil_traction = true;  // the wheels grip as the soil does (shore::bullet::SoilVehicle)
    car.four_wheel_drive = true;
    const double start_y = 0.0;
    const double ground = land_.height(land_.column_i(kStartX), land_.column_j(start_y));
    car_ = std::make_unique<RaycastCar>(
        world_, car,
        btVector3(btScalar(kStartX), btScalar(start_y),
                  btScalar(ground + car.suspension_rest + car.wheel_radius - car.connection_height + 0.05)),
        &ground_);  // Shore's SoilRaycaster: the hill's normal under a wheel, and wheels that rise out of a rut
    const std::array<double, 4> widths{kWheelWidth, kWheelWidth, kWheelWidth, kWheelWidth};
    ground_.add_vehicle(&car_->vehicle(), widths, car_->soil_raycaster());
    water_.add_body(car_->chassis());
    water_.add_vehicle(&car_->vehicle(), widths);  // the wheels float, drag and make waves too
    bodies_.push_back(car_->chassis());
    start_ = car_->chassis()->getCenterOfMassPosition();
  }

  void step() override {
    if (!driven_) script();
    world_.step(o_.substep);
    ++k_;
  }

  void observe() override {
    const btVector3 c = car_->chassis()->getCenterOfMassPosition();
    distance_ = std::max(distance_, double(c.x() - start_.x()));
    wheels_down_ += car_->wheels_on_ground();
    if (c.z() < land_.bedrock(land_.column_i(c.x()), land_.column_j(c.y()))) ++fallthrough_;
    in_water_ = std::max(in_water_, water_.submerged_volume(car_->chassis()));
    double wheels = 0.0;
    for (int k = 0; k < 4; ++k) wheels += water_.wheel_water(&car_->vehicle(), k).submerged_volume;
    wheels_in_water_ = std::max(wheels_in_water_, wheels);
  }

  [[nodiscard]] SceneState state() const override {
    return {.soils = {&land_}, .waters = {&ford_}, .bodies = bodies_, .layout = HashLayout::positions};
  }

  void measure(nlohmann::json& m) const override {
    m["distance_m"] = distance_;
    m["mean_speed_mps"] = distance_ / std::max(o_.seconds, o_.substep);
    m["wheels_on_ground_share"] = double(wheels_down_) / (4.0 * std::max(k_, 1));
    m["fallthrough_count"] = fallthrough_ + ground_.stats().rescues;
    m["volume_drift_rel"] = volume_drift_rel(land_);
    m["deepest_rut_m"] = deepest_rut();
    m["crust_broken_m2"] = crust_broken();
    m["chassis_submerged_m3"] = in_water_;
    m["wheels_submerged_m3"] = wheels_in_water_;
    m["water_displaced_m3"] = water_.stats().displaced_volume;
  }

  [[nodiscard]] std::vector<int> film_substeps() const override { return evenly_spread_film(o_.substeps(), o_.smoke); }
  Image film_frame(Painter& painter) override {
    return painter.paint(contents(), {.region = around_car(6.0), .elevation_deg = 30.0, .legend = false, .width = 320});
  }

  SceneContents contents() override {
    SceneContents c{.world = &world_,
                    .soils = {{&land_, &ground_, {}}},
                    .waters = {{&ford_, &water_}},
                    .bounds = {kX0 + 2.0, -kHalfY + 2.0, kX1 - 2.0, kHalfY - 2.0},
                    .focus = car_->chassis(),
                    .clock = &k_,
                    .vehicles = {{&car_->vehicle(), kWheelWidth}}};
    c.drive = [this](double forward, double turn) {
      driven_ = forward != 0.0 || turn != 0.0;
      if (driven_) car_->drive(kEngine * forward, forward == 0.0 ? 200.0 : 0.0, 0.35 * turn);
    };
    return c;
  }

  void draw(Drawing& out) const override {
    const int w = o_.smoke ? 320 : 1280;
    const std::string when = time_label(k_ * o_.substep);
    out.view("view.png", {.region = around_car(9.0),
                          .elevation_deg = 28.0,
                          .azimuth_deg = -150.0,
                          .ground = View::Ground::natural,
                          .width = w,
                          .title = "rally: a raycast car through sand, mud and a ford at " + when});
    out.view("valley.png", {.elevation_deg = 40.0,
                            .ground = View::Ground::natural,
                            .width = w,
                            .title = "rally: the valley, its ruts and the ford at " + when});
    out.view("ruts.png", {.camera = View::Camera::top,
                          .region = {kStartX - 1.0, -4.0, kStartX + std::max(distance_, 4.0) + 2.0, 4.0},
                          .ground = View::Ground::sinkage,
                          .bodies = false,
                          .width = w,
                          .title = "rally: sinkage of the ruts, car removed"});
    out.filmstrip();
  }

 private:
  /// Where the drive happens: a square of half side `half` around the car.
  [[nodiscard]] Bounds around_car(double half) const {
    const btVector3 c = car_->chassis()->getCenterOfMassPosition();
    return {double(c.x()) - half, double(c.y()) - half, double(c.x()) + half, double(c.y()) + half};
  }
  /// Full throttle up the valley, steering gently after its winding floor.
  void script() {
    const btVector3 c = car_->chassis()->getCenterOfMassPosition();
    const double x = c.x(), ahead = x + 4.0;
    const double floor_y = floor_line(ahead);
    const btVector3 heading = car_->chassis()->getWorldTransform().getBasis().getColumn(0);
    const double want = std::atan2(floor_y - double(c.y()), 4.0), have = std::atan2(heading.y(), heading.x());
    car_->drive(kEngine, 0.0, std::clamp(1.5 * (want - have), -0.4, 0.4));
  }
  /// Area of the hollow's crust the wheels broke through (columns pressed past its depth), m^2.
  [[nodiscard]] double crust_broken() const {
    const double cell = land_.settings().cell, y = floor_line(kMudX);
    int broken = 0;
    for (std::int64_t j = land_.column_j(y - kMudRadius); j <= land_.column_j(y + kMudRadius); ++j)
      for (std::int64_t i = land_.column_i(kMudX - kMudRadius); i <= land_.column_i(kMudX + kMudRadius); ++i)
        broken += land_.lower_index(i, j) >= 0 && land_.exposed_index(i, j) == land_.lower_index(i, j) ? 1 : 0;
    return broken * cell * cell;
  }
  [[nodiscard]] double deepest_rut() const {
    double most = 0.0;
    const double x1 = kStartX + distance_ + 2.0;
    for (std::int64_t j = land_.column_j(-4.0); j <= land_.column_j(4.0); ++j)
      for (std::int64_t i = land_.column_i(kStartX); i <= land_.column_i(x1); ++i)
        most = std::max(most, land_.base_height(i, j) - land_.height(i, j));
    return most;
  }

  SceneOptions o_;
  World world_;
  terrain::Terrain land_;
  water::Surface ford_;
  bullet::TerrainCoupling ground_;
  bullet::WaterCoupling water_;
  std::unique_ptr<RaycastCar> car_;
  std::vector<const btRigidBody*> bodies_;
  btVector3 start_{0, 0, 0};
  int k_ = 0;
  bool driven_ = false;
  double distance_ = 0.0, in_water_ = 0.0, wheels_in_water_ = 0.0;
  long wheels_down_ = 0, fallthrough_ = 0;
};

}  // namespace

SceneType rally_scene() {
  return {
      .name = "rally",
      .description =
          "A four-wheel-drive btRaycastVehicle car (800 kg, Bullet's VehicleDemo set-up, built as Shore's SoilVehicle) "
          "is driven up a valley of rolling sand, through a hollow painted mud and into a ford. Its wheels sink as the "
          "soil's bearing needs, grip as its shear strength allows and leave ruts behind; the chassis and the wheels "
          "float and drag in the ford and make waves and a wake. It stalls in the ford's muddy bed, its wheels spin "
          "and "
          "dig in there: deepest_rut_m is that hole, not a rut of the open drive. One terrain with a material "
          "map (sand, mud, and a crust of dried mud over the hollow's wet mud, a layer in depth the wheels break "
          "through). The camera follows the car; in the viewer the arrow keys drive it.",
      // The smoke run (tests, pinned hash) lasts until the car is in the ford, so the pin
      // covers the water coupling's floating wheels and chassis as well as the soil.
      .defaults = {.seconds = 14.0, .substep = 1.0 / 60.0, .material = "sand", .cell = 0.04, .smoke_seconds = 6.0},
      .metric_help =
          {
              {"distance_m", "farthest the car got along the valley, m"},
              {"mean_speed_mps", "distance over the run's time, m/s"},
              {"wheels_on_ground_share", "share of wheel-substeps whose ray found ground"},
              {"fallthrough_count", "times the chassis was below bedrock or a body was lifted back (must be 0)"},
              {"volume_drift_rel", "|ground + compacted + airborne - edited| / moved volume (must be < 1e-6)"},
              {"deepest_rut_m", "largest lowering of the ground below its untouched surface along the track, m"},
              {"crust_broken_m2", "area of the hollow's dried crust the wheels broke through to the wet mud, m^2"},
              {"chassis_submerged_m3", "largest volume of the chassis under water, m^3"},
              {"wheels_submerged_m3", "largest volume of the four wheels under water together, m^3"},
              {"water_displaced_m3", "water the car pushed aside in total (signed), m^3"},
          },
      .create = make_scene<Rally>,
  };
}

}  // namespace shore::scenes

#include "raycast_wheels.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "body_registry.h"
#include "bt_convert.h"
#include "envelope_below.h"
#include "raycast_wheel_grid.h"
#include "shore/core/det_math.h"
#include "shore/core/error.h"
#include "soft_ground.h"

namespace shore::bullet {
inline namespace SHORE_BULLET_ABI {
namespace coupling_detail {

namespace {

constexpr double kMaxWidth = 10.0;  // m: wider is no wheel
// m: the least depth a wheel's envelope is cut to (rasterize_wheel): most presses measure
// a few millimetres (the soil carried the load last substep); a wheel that measured deeper
// last time is cut to twice that.
constexpr double kCutDepthLeast = 0.01;
constexpr double kCutSlack = 1e-6;  // m, against rounding in the comparisons the cut relies on
constexpr double kRolling = 0.05;   // m/s: a wheel slower than this is standing
// The most a wheel may rise above its ray's hit in one substep (rise): searched below
// kRiseLeast, then twice as high while it reaches that, never more than kRiseMost of its radius.
constexpr double kRiseLeast = 0.01;  // m
constexpr double kRiseMost = 0.5;
// m: the floor a wheel presses stays this far above its ray's end (reachable_offset), against
// rounding in Bullet's ray.
constexpr double kRayMargin = 1e-4;
// The rim's clinging soil is stepped every this many soil steps (Imprint::cling_every)
// while each point of the rim stays on the soil that long (rim_stays).
constexpr int kClingEvery = 2;

/// N/m: what Bullet's suspension force gains per metre the ground under the wheel rises
/// (btRaycastVehicle::updateSuspension: stiffness x compression / the contact's cosine,
/// times the chassis' mass); 0 for a chassis of infinite mass.
double suspension_spring(const btWheelInfo& info, const btRigidBody& chassis) {
  const double inverse_mass = double(chassis.getInvMass());
  if (!(inverse_mass > 0.0)) return 0.0;
  return double(info.m_suspensionStiffness) * double(info.m_clippedInvContactDotSuspension) / inverse_mass;
}

}  // namespace

void cast_wheel_rays(btRaycastVehicle& vehicle) {
  for (int k = 0; k < vehicle.getNumWheels(); ++k) {
    vehicle.rayCast(vehicle.getWheelInfo(k));
    vehicle.updateWheelTransform(k, false);
    vehicle.getWheelInfo(k).m_skidInfo = btScalar(1);  // where Bullet's friction starts from: no skid
  }
  vehicle.updateSuspension(btScalar(0));  // its step does not enter the suspension force
}

void check_wheel_widths(const btRaycastVehicle& vehicle, std::span<const double> widths, const std::string& where) {
  const int n = vehicle.getNumWheels();
  if (widths.size() != static_cast<std::size_t>(n))
    throw InvalidSetting(where + "(widths)", std::to_string(widths.size()) + " widths",
                         "must give one width per wheel (" + std::to_string(n) + ")");
  for (int k = 0; k < n; ++k) {
    const double b = widths[static_cast<std::size_t>(k)], r = double(vehicle.getWheelInfo(k).m_wheelsRadius);
    if (!(b > 0.0 && b <= kMaxWidth))
      throw InvalidSetting(where + "(widths[" + std::to_string(k) + "])", detail::to_text(b),
                           "must be a wheel width in (0, 10] m");
    if (!(r > 0.0 && std::isfinite(r)))
      throw InvalidSetting(where + " wheel " + std::to_string(k) + " radius", detail::to_text(r), "must be > 0");
  }
}

btTransform wheel_pose(const btWheelInfo& info) {
  const btVector3 up = -info.m_raycastInfo.m_wheelDirectionWS.normalized();
  btVector3 axle = info.m_raycastInfo.m_wheelAxleWS.rotate(up, info.m_steering);
  axle = (axle - up * axle.dot(up)).normalized();
  const btVector3 forward = up.cross(axle);
  btMatrix3x3 basis(axle.x(), forward.x(), up.x(), axle.y(), forward.y(), up.y(), axle.z(), forward.z(), up.z());
  return btTransform(basis, info.m_raycastInfo.m_contactPointWS + up * info.m_wheelsRadius);
}

namespace {

/// The columns' push on the cylinder's sloped faces, resolved horizontally along `forward`:
/// a column at distance s ahead of the wheel's centre meets the rim at slope s / sqrt(R^2 - s^2).
double compaction_push(const terrain::Bearing& bearing, const ColumnOffsets& from_centre, const btVector3& forward,
                       double radius, double load) {
  if (!(bearing.capacity > 0.0) || !std::isfinite(bearing.capacity)) return 0.0;
  const double share = load / bearing.capacity;  // the load the columns carry, in proportion to their capacity
  double push = 0.0;
  for (const terrain::ColumnForce& c : bearing.columns) {
    const double dx = from_centre.dx(c.i), dy = from_centre.dy(c.j);
    const double s = std::clamp(dx * double(forward.x()) + dy * double(forward.y()), -0.95 * radius, 0.95 * radius);
    push -= share * c.force * s / std::sqrt(radius * radius - s * s);
  }
  return std::clamp(push, -load, load);
}

}  // namespace

GridRect ring_of(const GridRect& window) { return {window.i0 - 1, window.j0 - 1, window.nx + 2, window.ny + 2}; }

const std::vector<double>& WallScratch::ring_heights(const terrain::Terrain& terrain, const GridRect& ring) {
  if (!(read.i0 == ring.i0 && read.j0 == ring.j0 && read.nx == ring.nx && read.ny == ring.ny)) {
    heights.resize(ring.size());
    terrain.heights(ring, heights);
    read = ring;
  }
  return heights;
}

namespace {

/// For each offset a in [0, n) of a row of columns, where the point a + shift falls: the
/// cell to its left (clamped so that the cell and the next one are in the row) and its
/// fraction from there.
void axis_steps(int n, double shift, std::vector<AxisStep>& steps) {
  steps.resize(static_cast<std::size_t>(n));
  for (int a = 0; a < n; ++a) {
    const double u = double(a) + shift;
    const double f = std::clamp(floor_small(u), 0.0, double(n - 2));
    steps[static_cast<std::size_t>(a)] = {static_cast<std::size_t>(f), u - f};
  }
}

/// Most a column's surface tilts across the wheel in the wall push (a 72 degree wall: a rut's
/// wall one cell wide and deeper than three cells reads as this steep).
constexpr double kMaxWallSlope = 3.0;

/// The soil's push across the wheel, N along `across` (the axle's horizontal direction in the
/// ground's coordinates). The loaded soil pushes along its surface's normal, so where the
/// surface slopes across the wheel it pushes the wheel sideways, towards the lower side, by
/// the load there times the slope. A wheel in its own rut has the rut's walls beside both its
/// edges, and they cancel; one that has drifted towards a wall has the higher wall beside one
/// edge (the soil it has not pressed yet) and the rut's floor beside the other, and is pushed
/// back into the rut. The load is taken as even across the wheel in each strip along its
/// heading (the strip's mean column force): a cylinder presses a strip evenly, and the two
/// edges' own column forces differ with how the grid cuts them, which would push the wheel
/// about at random. Bullet already pushes the whole suspension force along the normal its ray
/// found (`ray_normal`, the ground's coordinates), under the wheel's centre line: only the
/// difference is returned, so a wheel on an even slope gets nothing more than Bullet gives it.
double wall_push(const terrain::Terrain& terrain, const terrain::Bearing& bearing, const GridRect& rect,
                 const ColumnOffsets& from_centre, const btVector3& across, const btVector3& ray_normal, double load,
                 double radius, WallScratch& scratch) {
  if (!(bearing.capacity > 0.0) || !std::isfinite(bearing.capacity) || !(ray_normal.z() > 0)) return 0.0;
  const GridRect ring = ring_of(rect);  // each column's neighbours too
  const std::vector<double>& heights = scratch.ring_heights(terrain, ring);
  const double ax = double(across.x()), ay = double(across.y()), cell = terrain.settings().cell;
  // The surface's height one cell along `sign` across from a column's centre, bilinear between
  // the four columns around it: the slope across the wheel itself, not along the grid's axes
  // (a yawed wheel's rut front is a staircase across the grid, level along the wheel's axle).
  // Where a point one cell across falls depends on the column's offset along each axis alone.
  axis_steps(ring.nx, ax, scratch.u_ahead), axis_steps(ring.nx, -ax, scratch.u_behind);
  axis_steps(ring.ny, ay, scratch.v_ahead), axis_steps(ring.ny, -ay, scratch.v_behind);
  const auto nx = static_cast<std::size_t>(ring.nx);
  auto beside = [&](const AxisStep& u, const AxisStep& v) {
    const std::size_t at = v.cell * nx + u.cell, up = at + nx;
    return (1 - v.t) * ((1 - u.t) * heights[at] + u.t * heights[at + 1]) +
           v.t * ((1 - u.t) * heights[up] + u.t * heights[up + 1]);
  };
  // Strips one cell long along the heading (-ay, ax), as the rim's strips.
  const int half = static_cast<int>(std::ceil(radius / cell)) + 1;
  auto strip = [&](const terrain::ColumnForce& c) {
    const double s = from_centre.dy(c.j) * ax - from_centre.dx(c.i) * ay;
    return static_cast<std::size_t>(std::clamp(static_cast<int>(round_half_away(s / cell)), -half, half) + half);
  };
  scratch.force.assign(static_cast<std::size_t>(2 * half + 1), 0.0);
  scratch.slope.assign(scratch.force.size(), 0.0);
  scratch.count.assign(scratch.force.size(), 0);
  for (const terrain::ColumnForce& c : bearing.columns) {
    const std::size_t b = strip(c);
    const auto x = static_cast<std::size_t>(c.i - ring.i0), y = static_cast<std::size_t>(c.j - ring.j0);
    const double ahead = beside(scratch.u_ahead[x], scratch.v_ahead[y]);
    const double slope = (ahead - beside(scratch.u_behind[x], scratch.v_behind[y])) / (2 * cell);
    scratch.force[b] += c.force;
    scratch.slope[b] += std::clamp(slope, -kMaxWallSlope, kMaxWallSlope);
    ++scratch.count[b];
  }
  const double share = load / bearing.capacity;
  double push = 0.0;
  for (std::size_t b = 0; b < scratch.force.size(); ++b)
    if (scratch.count[b] > 0) push -= share * scratch.force[b] / scratch.count[b] * scratch.slope[b];
  push -= load * double(ray_normal.dot(across) / ray_normal.z());  // what Bullet's suspension force gives already
  return std::clamp(push, -load, load);
}

/// The kept columns of a row of n (KeptRun). behind(a) is monotone along the row (a
/// column's distance ahead, dx(a) hx + dy hy, grows with a for hx > 0 and falls for hx < 0:
/// every rounding in it is monotone), so they are one run at one end of the row, found by
/// bisection with the same test.
template <class Behind>
KeptRun kept_run(std::size_t n, double hx, const Behind& behind) {
  if (n == 0) return {};
  if (!(hx > 0.0) && !(hx < 0.0)) return behind(0) ? KeptRun{0, 0} : KeptRun{0, n};  // level across the row
  // The first column whose test differs from column 0's (n if none).
  const bool at_first = behind(0);
  std::size_t lo = 0, hi = n;  // behind(lo) == at_first; the answer in (lo, hi]
  while (hi - lo > 1) {
    const std::size_t mid = lo + (hi - lo) / 2;
    (behind(mid) == at_first ? lo : hi) = mid;
  }
  return at_first ? KeptRun{hi, n} : KeptRun{0, hi};
}

/// `envelope`'s columns at and ahead of the wheel's lowest point along `heading` into
/// `front`, the others left uncovered: a rolling wheel bears on its front arc (Bekker's
/// rolling wheel); the soil behind it unloads as the rim rises away. Only `lower` is kept
/// (the bearing reads nothing else), over the kept columns' bounding box: those that read
/// it (the bearing's columns, the loosening's weights) skip no rear half, and the kept
/// columns come in the same order as over the whole window (row by row), so the same sums.
/// Each row's kept run is found first (`runs`, scratch), then the box is written once.
void keep_front(const ColumnOffsets& from_centre, const btVector3& heading, const EnvelopeRaster& envelope,
                EnvelopeRaster& front, std::vector<KeptRun>& runs) {
  static_cast<GridRect&>(front) = envelope;
  front.upper.clear();
  const double hx = double(heading.x()), hy = double(heading.y());
  const auto nx = static_cast<std::size_t>(envelope.nx);
  runs.resize(static_cast<std::size_t>(envelope.ny));
  std::size_t a0 = nx, a1 = 0;  // the kept covered columns' bounding box, [a0, a1) x [b0, b1)
  int b0 = envelope.ny, b1 = 0;
  for (int b = 0; b < envelope.ny; ++b) {
    const double along_y = from_centre.dy(envelope.j0 + b) * hy;
    const double* in = envelope.lower.data() + static_cast<std::size_t>(b) * nx;
    KeptRun run = kept_run(nx, hx, [&](std::size_t a) {
      return from_centre.dx(envelope.i0 + static_cast<std::int64_t>(a)) * hx + along_y < 0.0;
    });
    while (run.first < run.last && in[run.first] == EnvelopeRaster::kNoLower) ++run.first;  // covered only
    while (run.first < run.last && in[run.last - 1] == EnvelopeRaster::kNoLower) --run.last;
    runs[static_cast<std::size_t>(b)] = run;
    if (run.first < run.last)
      a0 = std::min(a0, run.first), a1 = std::max(a1, run.last), b0 = std::min(b0, b), b1 = b + 1;
  }
  if (b0 >= b1) {  // nothing ahead: the whole window, uncovered
    front.lower.assign(envelope.lower.size(), EnvelopeRaster::kNoLower);
    return;
  }
  const std::size_t width = a1 - a0;
  static_cast<GridRect&>(front) =
      GridRect{envelope.i0 + static_cast<std::int64_t>(a0), envelope.j0 + b0, static_cast<int>(width), b1 - b0};
  front.lower.resize(front.size());
  for (int b = b0; b < b1; ++b) {
    const KeptRun run = runs[static_cast<std::size_t>(b)];
    double* out = front.lower.data() + static_cast<std::size_t>(b - b0) * width;
    // An empty run writes the whole row uncovered.
    const std::size_t from = run.first < run.last ? run.first : a1, to = run.first < run.last ? run.last : a1;
    std::fill(out, out + (from - a0), EnvelopeRaster::kNoLower);
    std::copy(envelope.lower.data() + static_cast<std::size_t>(b) * nx + from,
              envelope.lower.data() + static_cast<std::size_t>(b) * nx + to, out + (from - a0));
    std::fill(out + (to - a0), out + width, EnvelopeRaster::kNoLower);
  }
}

struct RimSpan {
  double entry = 0.0, exit = 0.0;  ///< rad, the rim's front and rear edges in contact
};

/// The rim in contact as strips one cell long along `forward`: each loaded column's shear
/// strength, (c A + F tan phi) over the rim's slope there, summed into its strip.
RimSpan rim_strips(const terrain::Terrain& terrain, const terrain::Bearing& bearing, const ColumnOffsets& from_centre,
                   const btVector3& forward, double radius, double share, std::vector<RimStrip>& rim) {
  const double cell = terrain.settings().cell, area = cell * cell, reach = 0.95 * radius;
  const int half = static_cast<int>(std::ceil(reach / cell));
  rim.assign(static_cast<std::size_t>(2 * half + 1), RimStrip{});
  const terrain::Material* last = nullptr;
  double tan_phi = 0.0;
  // One material: no column needs looking up (material_at finds the column's tile).
  const std::span<const terrain::Material> palette = terrain.palette();
  const bool one_material = palette.size() == 1;
  int front = -half - 1, back = half + 1;
  for (const terrain::ColumnForce& c : bearing.columns) {
    if (!(c.force > 0.0)) continue;
    const double dx = from_centre.dx(c.i), dy = from_centre.dy(c.j);
    const double s = std::clamp(dx * double(forward.x()) + dy * double(forward.y()), -reach, reach);
    const int b = std::clamp(static_cast<int>(round_half_away(s / cell)), -half, half);
    const terrain::Material& m = one_material ? palette[0] : terrain.exposed_material(c.i, c.j);
    if (&m != last) last = &m, tan_phi = det::tan(m.friction_angle);
    rim[static_cast<std::size_t>(b + half)].strength += m.cohesion * area + share * c.force * tan_phi;
    front = std::max(front, b), back = std::min(back, b);
  }
  if (front < back) {
    rim.clear();
    return {};
  }
  auto angle = [&](double s) { return rim_angle(s, radius); };
  std::size_t kept = 0;  // compacted in place: strip b is read before any later write reaches it
  for (int b = back; b <= front; ++b) {
    RimStrip strip = rim[static_cast<std::size_t>(b + half)];
    if (!(strip.strength > 0.0)) continue;
    strip.theta = angle(b * cell);
    strip.sin_theta = det::sin(strip.theta);
    strip.cos_theta = det::cos(strip.theta);
    strip.strength /= strip.cos_theta;  // the rim's area over the strip's plan area
    rim[kept++] = strip;
  }
  rim.resize(kept);
  return {angle((front + 0.5) * cell), angle((back - 0.5) * cell)};
}

/// Whether each point of a rim spinning at `spin` (rad/s) stays on the soil for `seconds` or
/// more: it is in contact over `contact_angle` (rad) of its turn. The soil clinging to the
/// rim is then stepped that seldom without missing a piece: a piece loads when a clinging
/// step finds it touching the soil, and loads no more for being found again (Cling::touch).
bool rim_stays(double contact_angle, double spin, double seconds) {
  return contact_angle > 0.0 && std::abs(spin) * seconds <= contact_angle;
}

/// An impulse (N s) that opposes the contact's velocity along its direction, limited to what
/// stops the chassis there (`denominator`: Bullet's impulse denominator at the contact, as
/// Bullet's own side friction takes it); one that does not oppose it is left as it is.
double stopping(double impulse, double speed, double denominator) {
  if (impulse * speed >= 0.0 || !(denominator > 0.0)) return impulse;
  const double most = std::fabs(speed) / denominator;
  return std::clamp(impulse, -most, most);
}

/// m, how far the wheel's envelope may be lowered and keep its lowest point above its ray's
/// end (`ray_end`, the ground frame's height; kRayMargin kept): pressed deeper, the wheel would
/// find no ground in the next substep, its suspension would carry nothing, and the next touch
/// would press again. On snow, where a few hundred newtons sink a wheel 20 cm, a car set down
/// on its wheels fell onto its chassis. The soil yields no faster than the chassis follows.
double reachable_offset(const EnvelopeRaster& envelope, double ray_end) {
  double lowest = EnvelopeRaster::kNoLower;
  for (const double z : envelope.lower) lowest = std::min(lowest, z);
  return std::isfinite(lowest) ? std::max(lowest - ray_end - kRayMargin, 0.0) : 0.0;
}

/// Names wheel k of a vehicle from step to step for the spray (the soil clinging to it, its
/// random numbers): above every body's key (a broadphase id, below 2^31), from the
/// chassis' id and the wheel's index.
std::uint64_t wheel_key(const btCollisionObject& chassis, int k) {
  const auto id = static_cast<std::uint64_t>(chassis.getBroadphaseHandle()->m_uniqueId);
  return (std::uint64_t{1} << 48) | (id << 8) | static_cast<std::uint64_t>(k & 0xff);
}

}  // namespace

void RaycastWheels::add(btRaycastVehicle* vehicle, std::span<const double> widths, double cell,
                        const EnvelopeOptions& options, bool rises) {
  const std::string where = "bullet.TerrainCoupling.add_vehicle";
  if (vehicle == nullptr) throw InvalidSetting(where + "(vehicle)", "null", "must be a btRaycastVehicle");
  for (const Vehicle& v : vehicles_)
    if (v.vehicle == vehicle) throw InvalidSetting(where + "(vehicle)", "added already", "must be added once");
  check_wheel_widths(*vehicle, widths, where);
  const int n = vehicle->getNumWheels();
  Vehicle v{vehicle, dynamic_cast<SoilVehicle*>(vehicle), vehicle->getRigidBody(), {}, rises};
  v.wheels.reserve(widths.size());
  for (int k = 0; k < n; ++k) {
    const double b = widths[static_cast<std::size_t>(k)], r = double(vehicle->getWheelInfo(k).m_wheelsRadius);
    Wheel w;
    w.shape = std::make_unique<btCylinderShapeX>(btVector3(btScalar(b / 2), btScalar(r), btScalar(r)));
    w.shape->setMargin(btScalar(0));
    w.reach = check_rasterizable(*w.shape, cell, options);
    v.wheels.push_back(std::move(w));
  }
  if (v.soil != nullptr) v.soil->grounds_.push_back(ground_);
  cast_wheel_rays(*vehicle);
  vehicles_.push_back(std::move(v));
}

RaycastWheels::RaycastWheels() : ground_(std::make_shared<SoftGround>()) {}
RaycastWheels::~RaycastWheels() = default;

void RaycastWheels::set_ground(std::function<bool(const btVector3&)> holds) { ground_->holds = std::move(holds); }

void RaycastWheels::remove(const btRaycastVehicle* vehicle) {
  std::erase_if(vehicles_, [&](const Vehicle& v) {
    if (v.vehicle != vehicle) return false;
    if (v.soil != nullptr)  // a vehicle the user removes is alive: it forgets this ground
      std::erase_if(v.soil->grounds_, [&](const std::weak_ptr<const SoftGround>& g) { return g.lock() == ground_; });
    return true;
  });
}

const RaycastWheels::Wheel* RaycastWheels::find(const btRaycastVehicle* vehicle, int k) const {
  for (const Vehicle& v : vehicles_)
    if (v.vehicle == vehicle && k >= 0 && static_cast<std::size_t>(k) < v.wheels.size())
      return &v.wheels[static_cast<std::size_t>(k)];
  return nullptr;
}

double RaycastWheels::push(const btRaycastVehicle* vehicle, int k) const {
  const Wheel* w = find(vehicle, k);
  return w != nullptr ? w->push : 0.0;
}

double RaycastWheels::side_push(const btRaycastVehicle* vehicle, int k) const {
  const Wheel* w = find(vehicle, k);
  return w != nullptr ? w->wall_push : 0.0;
}

int RaycastWheels::forget_lost(const btCollisionWorld& world) {
  if (vehicles_.empty()) return 0;
  const HeldObjects held(world);
  return static_cast<int>(std::erase_if(vehicles_, [&](const Vehicle& v) { return !held.holds(v.chassis); }));
}

void RaycastWheels::serve(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, double h, bool deforms,
                          std::vector<terrain::Imprint>& imprints) {
  for (Vehicle& v : vehicles_)
    for (int k = 0; k < static_cast<int>(v.wheels.size()); ++k) {
      Wheel& wheel = v.wheels[static_cast<std::size_t>(k)];
      wheel.push = 0.0;
      wheel.wall_push = 0.0;
      if (v.soil != nullptr) {
        // Where its spin search starts (grip): read from the vehicle's own record, which a
        // checkpoint keeps, so a restored run searches from the same spin.
        const WheelTraction& last = v.soil->soil(k).last;
        wheel.last_spin = last.on_soil ? last.spin : std::numeric_limits<double>::quiet_NaN();
        v.soil->soil(k).last = WheelTraction{};
      }
      const btWheelInfo& info = v.vehicle->getWheelInfo(k);
      if (!info.m_raycastInfo.m_isInContact || !ground_->holds(info.m_raycastInfo.m_contactPointWS)) continue;
      if (const terrain::Imprint* im = press(terrain, rasterizer, h, deforms, v, k)) imprints.push_back(*im);
    }
}

const terrain::Imprint* RaycastWheels::press(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, double h,
                                             bool deforms, Vehicle& vehicle, int k) {
  Wheel& wheel = vehicle.wheels[static_cast<std::size_t>(k)];
  wheel.contact_angle = 0.0;  // this substep's grip's, if it grips: nothing kept across substeps
  const btWheelInfo& info = vehicle.vehicle->getWheelInfo(k);
  Pressed p;
  p.load = info.m_wheelsSuspensionForce;
  p.radius = info.m_wheelsRadius;
  p.world_pose = wheel_pose(info);
  p.pose = framed_ ? to_ground_ * p.world_pose : p.world_pose;  // in the terrain's coordinates
  if (!(p.load > 0.0) || !pose_rasterizable(p.pose, wheel.reach, rasterizer.grid())) return nullptr;
  if (rasterize_wheel(terrain, rasterizer, wheel, p.pose, false) == 0) return nullptr;
  const btVector3 forward = p.pose.getBasis().getColumn(1), world_forward = p.world_pose.getBasis().getColumn(1);
  btRigidBody* chassis = vehicle.vehicle->getRigidBody();
  p.at = info.m_raycastInfo.m_contactPointWS - chassis->getCenterOfMassPosition();
  const btVector3 world_velocity = chassis->getVelocityInLocalPoint(p.at);
  const double speed = double(world_velocity.dot(world_forward));
  read_bearing(terrain, wheel, p, speed);
  // One solve for both loads below: the second re-measures no offset the first measured.
  double offset = wheel.solve.offset(p.load);
  if (!cut_ok(wheel)) offset = press_whole(terrain, rasterizer, wheel, p, speed);
  // Soil that carries more than the load where the ray hit lifts the wheel (rise): the
  // suspension gains what the ground raised that far would give, at the wheel's contact.
  const double suspension_force = p.load;
  double risen = 0.0;
  if (offset == 0.0 && vehicle.rises) {
    const double carried = wheel.solve.bearing(0.0).capacity, spring = suspension_spring(info, *chassis);
    const double most = std::min(double(info.m_maxSuspensionForce) - p.load, spring * kRiseMost * p.radius);
    if (carried > p.load && std::isfinite(carried) && spring > 0.0 && most > 0.0) {
      // Searched below kRiseLeast first, the bound doubled while the wheel rises to it: no
      // memory of the last substep's rise, so a restored checkpoint continues bit for bit.
      const double highest = most / spring, plain_offset = offset;
      const Pressed plain = p;
      for (double bound = std::min(kRiseLeast, highest);; bound = std::min(2.0 * bound, highest)) {
        p = plain, offset = plain_offset;
        risen = rise(terrain, rasterizer, wheel, p, speed, spring, bound, offset);
        if (risen < bound || bound >= highest) break;
      }
      const btVector3& normal = info.m_raycastInfo.m_contactNormalWS;
      chassis->applyImpulse(normal * btScalar((p.load - suspension_force) * h), p.at);
    }
  }
  const btVector3 ray_end =
      info.m_raycastInfo.m_hardPointWS +
      info.m_raycastInfo.m_wheelDirectionWS * (info.getSuspensionRestLength() + info.m_wheelsRadius);
  p.ray_end = double((framed_ ? to_ground_ * ray_end : ray_end).z());
  offset = std::min(offset, reachable_offset(wheel.envelope, p.ray_end));
  const terrain::Bearing* bearing = &wheel.solve.measure(offset);
  if (vehicle.soil != nullptr) {
    // Its traction; the soil it shears bears less, each strip by its own shear (loosen).
    const terrain::Material& m =
        terrain.exposed_material(terrain.column_i(p.pose.getOrigin().x()), terrain.column_j(p.pose.getOrigin().y()));
    const RimShear shear = grip(terrain, *bearing, m, h, vehicle, k, p);
    if (shear.radius > 0.0) {
      offset = loosen(terrain, m, shear, wheel, p);
      if (!cut_ok(wheel)) {  // the loosened soil let it sink deeper than the cut allows
        (void)press_whole(terrain, rasterizer, wheel, p, speed);  // the offsets the loosened solve brackets from
        offset = loosen(terrain, m, shear, wheel, p);
      }
      bearing = &wheel.loosened;
    }
  }
  wheel.last_deepest = wheel.solve.deepest();
  const double push = compaction_push(*bearing, wheel.from_centre, forward, p.radius, p.load);
  chassis->applyImpulse(world_forward * btScalar(push * h), p.at);
  steer_by_walls(terrain, *bearing, vehicle, k, p, h);
  wheel.push = push;
  if (vehicle.soil != nullptr) vehicle.soil->soil(k).last.resistance = push;
  if (!deforms) return nullptr;
  wheel.imprint = terrain::Imprint{&wheel.envelope, offset};
  wheel.imprint.margin = margin_;
  const btVector3 velocity = chassis->getVelocityInLocalPoint(p.at);  // after the push
  wheel.imprint.velocity = to_vec3(framed_ ? to_ground_.getBasis() * velocity : velocity);
  wheel.imprint.centre = to_vec3(p.pose.getOrigin());
  // A SoilVehicle's wheel has a spin: the spray reads its rim's motion, v + w x (p - c), so a
  // wheel spinning in the soil throws it. A stock wheel's spin is Bullet's guess from the
  // chassis' speed: it sprays nothing.
  wheel.imprint.spray = vehicle.soil != nullptr;
  if (wheel.imprint.spray) {
    const btVector3 axle = p.pose.getBasis().getColumn(0);
    const double spin = vehicle.soil->soil(k).last.spin;
    wheel.imprint.angular_velocity = to_vec3(axle * btScalar(-spin));  // rolling forward turns about -axle
    const btVector3 hub =
        chassis->getVelocityInLocalPoint(p.world_pose.getOrigin() - chassis->getCenterOfMassPosition());
    wheel.imprint.velocity = to_vec3(framed_ ? to_ground_.getBasis() * hub : hub);  // at the centre it turns about
    const btQuaternion q = p.pose.getRotation() * btQuaternion(btVector3(1, 0, 0), -info.m_rotation);
    wheel.imprint.orientation = {q.w(), q.x(), q.y(), q.z()};
    wheel.imprint.spray = chassis->getBroadphaseHandle() != nullptr;
    if (wheel.imprint.spray) wheel.imprint.key = wheel_key(*chassis, k);
    wheel.imprint.cling_every = rim_stays(wheel.contact_angle, spin, kClingEvery * soil_step_) ? kClingEvery : 1;
  }
  return &wheel.imprint;
}

int RaycastWheels::rasterize_wheel(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, Wheel& wheel,
                                   const btTransform& pose, bool whole) {
  wheel.cut_depth = 0.0;
  wheel.window = rasterizer.window_of(*wheel.shape, pose);
  wheel.wall.forget();  // the terrain may have changed since the last press
  const terrain::TerrainSettings& s = terrain.settings();
  if (whole || !std::isfinite(s.active_reach)) return rasterizer.rasterize(*wheel.shape, pose, wheel.envelope);
  // A column whose lowest point, lowered by the solve's deepest offset, stays above every
  // ground column under the cylinder by more than the reach (and the contact tolerance)
  // changes nothing: it bears nothing at any offset the solve measured, is in no active
  // region, is under the body for no stage and holds no clinging soil. Only columns reaching
  // that and a depth more are rasterized (twice the deepest offset the wheel's last solve
  // measured, at least kCutDepthLeast); a solve that goes deeper is redone whole.
  // Read with the ring around it, which the rut walls' push reads too (wall_push): once a
  // press, the terrain being unchanged until the soil step.
  const GridRect& all = wheel.window;
  const std::vector<double>& ring = wheel.wall.ring_heights(terrain, ring_of(all));
  double highest = -std::numeric_limits<double>::infinity();
  const auto ring_nx = static_cast<std::size_t>(all.nx) + 2;
  for (std::size_t b = 1; b <= static_cast<std::size_t>(all.ny); ++b) {
    const double* row = ring.data() + b * ring_nx + 1;
    for (std::size_t a = 0; a < static_cast<std::size_t>(all.nx); ++a) highest = std::max(highest, row[a]);
  }
  const double depth = std::max(kCutDepthLeast, 2.0 * wheel.last_deepest);
  const double z_top = highest + std::max(s.active_reach, s.contact_tolerance) + depth;
  const btVector3 axle = pose.getBasis().getColumn(0);  // btCylinderShapeX: along local x
  const GridRect cut = cylinder_window_below(rasterizer.grid(), all, to_vec3(pose.getOrigin()), to_vec3(axle),
                                             double(wheel.shape->getHalfExtentsWithMargin().x()),
                                             double(wheel.shape->getRadius()), z_top);
  if (cut.empty() || (cut.nx == all.nx && cut.ny == all.ny))
    return rasterizer.rasterize(*wheel.shape, pose, wheel.envelope);
  const int covered = rasterizer.rasterize(*wheel.shape, pose, cut, wheel.envelope);
  if (covered == 0) return rasterizer.rasterize(*wheel.shape, pose, wheel.envelope);
  wheel.cut_depth = depth;
  return covered;
}

void RaycastWheels::read_bearing(const terrain::Terrain& terrain, Wheel& wheel, const Pressed& p, double speed) {
  const btVector3 forward = p.pose.getBasis().getColumn(1);
  wheel.from_centre.read(terrain, wheel.envelope, double(p.pose.getOrigin().x()), double(p.pose.getOrigin().y()));
  // Rolling (faster than kRolling along its heading): the front arc bears; at rest, both.
  if (std::abs(speed) > kRolling)
    keep_front(wheel.from_centre, speed > 0 ? forward : -forward, wheel.envelope, wheel.bearing_part, wheel.front_runs);
  else
    wheel.bearing_part = wheel.envelope;
  wheel.solve.reset(terrain, wheel.bearing_part);
}

double RaycastWheels::press_whole(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, Wheel& wheel,
                                  const Pressed& p, double speed) {
  rasterize_wheel(terrain, rasterizer, wheel, p.pose, true);
  read_bearing(terrain, wheel, p, speed);
  return wheel.solve.offset(p.load);
}

double RaycastWheels::rise(const terrain::Terrain& terrain, EnvelopeRasterizer& rasterizer, Wheel& wheel, Pressed& p,
                           double speed, double spring, double bound, double& offset) {
  const btVector3 up = p.pose.getBasis().getColumn(2), world_up = p.world_pose.getBasis().getColumn(2);
  Pressed raised = p;
  raised.pose.getOrigin() += up * btScalar(bound);
  rasterize_wheel(terrain, rasterizer, wheel, raised.pose, true);  // whole: the cut is for the plain pose
  read_bearing(terrain, wheel, raised, speed);
  // The raised envelope sunk by o is the wheel risen d = D - o, its suspension giving
  // F + k (D - o): the soil's capacity meets that at one offset (it grows with o, the load
  // falls), found in one search on the offset (BearingSolve::offset_under_spring).
  const double force = p.load;
  offset = wheel.solve.offset_under_spring(force + spring * bound, spring);
  // Sunk past the bound: the soil at the hit does not carry F after all, the wheel stays
  // there, pressed by F alone.
  if (offset > bound) offset = wheel.solve.offset(force);
  const double d = std::clamp(bound - offset, 0.0, bound);
  p.pose.getOrigin() += up * btScalar(d);
  p.world_pose.getOrigin() += world_up * btScalar(d);
  p.load = force + spring * d;
  return d;
}

bool RaycastWheels::cut_ok(const Wheel& wheel) {
  if (wheel.cut_depth == 0.0) return true;
  // Below the bedrock offset the bracket grew as on the whole envelope (bedrock_offset).
  const double deepest = wheel.solve.deepest();
  return deepest < wheel.solve.bedrock_offset() && deepest <= wheel.cut_depth - kCutSlack;
}

void RaycastWheels::steer_by_walls(const terrain::Terrain& terrain, const terrain::Bearing& bearing, Vehicle& vehicle,
                                   int k, const Pressed& p, double h) {
  Wheel& wheel = vehicle.wheels[static_cast<std::size_t>(k)];
  const btWheelInfo& info = vehicle.vehicle->getWheelInfo(k);
  btVector3 across = p.pose.getBasis().getColumn(0);  // the axle, flattened onto the ground's plane
  across.setZ(0);
  if (!(across.length2() > btScalar(1e-6))) return;  // an axle standing upright: no across
  across.normalize();
  const btVector3 ray_normal =
      framed_ ? to_ground_.getBasis() * info.m_raycastInfo.m_contactNormalWS : info.m_raycastInfo.m_contactNormalWS;
  const double push =
      wall_push(terrain, bearing, wheel.window, wheel.from_centre, across, ray_normal, p.load, p.radius, wheel.wall);
  wheel.wall_push = push;
  if (push == 0.0) return;
  btRigidBody* chassis = vehicle.vehicle->getRigidBody();
  const btVector3 world_across = framed_ ? to_ground_.getBasis().transpose() * across : across;
  // At the height the vehicle's roll influence sets, as Bullet's own side impulse.
  const btVector3 up = chassis->getCenterOfMassTransform().getBasis().getColumn(vehicle.vehicle->getUpAxis());
  const btVector3 side_at = p.at - up * (up.dot(p.at) * (btScalar(1) - info.m_rollInfluence));
  chassis->applyImpulse(world_across * btScalar(push * h), side_at);
}

double RaycastWheels::loosen(const terrain::Terrain& terrain, const terrain::Material& m, const RimShear& shear,
                             Wheel& wheel, const Pressed& p) {
  wheel.loosening.build(terrain.settings().cell, wheel.bearing_part, wheel.from_centre, p.pose.getBasis().getColumn(1),
                        p.radius, shear, m);
  const double offset =
      std::min(wheel.solve.offset(p.load, [&](const terrain::Bearing& b) { return wheel.loosening.capacity(b); }),
               reachable_offset(wheel.envelope, p.ray_end));
  wheel.loosening.apply(wheel.solve.measure(offset), wheel.loosened);
  return offset;
}

RimShear RaycastWheels::grip(const terrain::Terrain& terrain, const terrain::Bearing& bearing,
                             const terrain::Material& m, double h, Vehicle& vehicle, int k, const Pressed& p) {
  if (!(bearing.capacity > 0.0) || !std::isfinite(bearing.capacity)) return {};
  Wheel& wheel = vehicle.wheels[static_cast<std::size_t>(k)];
  const double r = p.radius;
  const btVector3 forward = p.pose.getBasis().getColumn(1);
  const RimSpan span =
      rim_strips(terrain, bearing, wheel.from_centre, forward, r, p.load / bearing.capacity, wheel.rim);
  if (wheel.rim.empty()) return {};
  wheel.contact_angle = span.entry - span.exit;
  btWheelInfo& info = vehicle.vehicle->getWheelInfo(k);
  btRigidBody* chassis = vehicle.vehicle->getRigidBody();
  const btVector3 world_forward = p.world_pose.getBasis().getColumn(1),
                  world_axle = p.world_pose.getBasis().getColumn(0);
  const btVector3 velocity = chassis->getVelocityInLocalPoint(p.at);
  TractionInput in;
  in.radius = r;
  in.entry_angle = span.entry;
  in.exit_angle = span.exit;
  in.shear_modulus = m.shear_modulus;
  in.remould_shear_ratio = m.remould_shear_ratio;
  in.remould_length = m.remould_length;
  in.forward_speed = velocity.dot(world_forward);
  in.side_speed = velocity.dot(world_axle);
  in.drive = info.m_engineForce;
  in.brake = std::max(double(info.m_brake), 0.0) / h;  // Bullet's brake: an impulse per substep
  const double held = vehicle.soil->soil(k).held_spin;
  in.hold = !std::isnan(held);
  in.held_spin = in.hold ? held : 0.0;
  in.last_spin = wheel.last_spin;
  const Traction t = soil_traction(wheel.rim, in);
  // Against the motion, no more than stops the chassis at the contact: a brake's or a
  // resistance's. A wheel turning in its thrust's direction drives, and may reverse the
  // motion: clipped, a car at rest that rolls back by a rounding's worth would get only the
  // push that stops it, substep after substep, and never start.
  const btVector3 contact = chassis->getCenterOfMassPosition() + p.at;
  const bool drives = t.spin * t.forward > 0.0;
  const double along =
      drives ? t.forward * h
             : stopping(t.forward * h, in.forward_speed, chassis->computeImpulseDenominator(contact, world_forward));
  const double across = stopping(t.side * h, in.side_speed, chassis->computeImpulseDenominator(contact, world_axle));
  chassis->applyImpulse(world_forward * btScalar(along), p.at);
  // Sideways at the height the vehicle's roll influence sets, as Bullet's own side impulse.
  const btVector3 up = chassis->getCenterOfMassTransform().getBasis().getColumn(vehicle.vehicle->getUpAxis());
  const btVector3 side_at = p.at - up * (up.dot(p.at) * (btScalar(1) - info.m_rollInfluence));
  chassis->applyImpulse(world_axle * btScalar(across), side_at);
  info.m_rotation += btScalar((t.spin - in.forward_speed / r) * h);  // Bullet turned it as if it rolled
  info.m_deltaRotation = btScalar(t.spin * h);
  vehicle.soil->soil(k).last = WheelTraction{true, t.spin, t.slip, along / h, across / h, t.torque, 0.0};
  return t.shear;
}

}  // namespace coupling_detail
}  // namespace SHORE_BULLET_ABI
}  // namespace shore::bullet

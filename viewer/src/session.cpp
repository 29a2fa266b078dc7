#include "session.h"

#include <algorithm>
#include <cmath>

#include <btBulletDynamicsCommon.h>

#include "shore/bullet/debug_draw.h"
#include "shore/core/error.h"
#include "shore/render/painter.h"
#include "shore/scenes/runner.h"
#include "shore/scenes/world.h"

namespace shore::viewer {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

std::unique_ptr<btCollisionShape> make_shape(const std::string& shape, double size) {
  const auto s = btScalar(size);
  if (shape == "sphere") return std::make_unique<btSphereShape>(s);
  if (shape == "box") return std::make_unique<btBoxShape>(btVector3(s, s, s));
  if (shape == "cylinder") return std::make_unique<btCylinderShapeZ>(btVector3(s, s, s));
  if (shape == "capsule") return std::make_unique<btCapsuleShapeZ>(s, s);
  throw InvalidSetting("viewer.drop.shape", shape, "sphere, box, cylinder or capsule");
}

double volume_of(const std::string& shape, double s) {
  constexpr double pi = 3.14159265358979323846;
  if (shape == "sphere") return 4.0 / 3.0 * pi * s * s * s;
  if (shape == "box") return 8.0 * s * s * s;
  if (shape == "cylinder") return pi * s * s * 2.0 * s;
  return pi * s * s * 2.0 * s + 4.0 / 3.0 * pi * s * s * s;  // capsule: radius s, half height s
}

}  // namespace

Session::Session(const std::string& scene, bool smoke) : smoke_(smoke) { open(scene); }

Session::~Session() {
  if (renderer_) renderer_->clear();
}

void Session::open(const std::string& name, double substep) {
  const scenes::SceneType* type = scenes::find_scene(name);
  if (type == nullptr) throw InvalidSetting("viewer.scene", name, "one of the scenes (shore-demo --help)");
  if (renderer_) renderer_->clear();
  scene_.reset();
  scenes::Overrides o;
  o.smoke = smoke_;
  o.write_files = false;
  o.threads = 1;
  o.substep = substep;
  options_ = scenes::resolve(*type, o);
  options_.seconds = 1e6;  // the viewer runs until closed
  scene_ = type->create(options_);
  contents_ = scene_->contents();
  name_ = name;
  frame_ = 0;
  substeps_ = 0;
  next_action_ = 0;
  camera = render::OrbitCamera::framing(contents_.bounds);
  if (contents_.focus != nullptr) {
    const Eigen::Vector3d c = focus_point();
    focus_offset_ = Eigen::Vector3d(0, 0, 0);
    camera.target = c;
    camera.distance = std::min(camera.distance, 6.0);
  }
  if (renderer_) renderer_->set_contents(contents_);
}

void Session::attach_renderer() {
  renderer_ = std::make_unique<render::Renderer>();
  renderer_->set_contents(contents_);
}

void Session::substep() {
  if (contents_.drive) contents_.drive(forward, turn);
  const auto t0 = Clock::now();
  scene_->step();
  times_.total = ms_since(t0);
  scene_->observe();
  ++substeps_;
  PartTimes t{};
  t.total = times_.total;
  for (const scenes::SoilContents& s : contents_.soils)
    if (s.coupling != nullptr) {
      const bullet::TerrainCouplingStats& c = s.coupling->stats();
      t.envelopes += 1e3 * c.envelope_seconds;
      t.reaction += 1e3 * c.reaction_seconds;
      t.terrain += 1e3 * c.terrain_seconds;
      t.push += 1e3 * c.push_seconds;
    }
  for (const scenes::WaterContents& w : contents_.waters)
    if (w.coupling != nullptr) {
      t.water_coupling += 1e3 * w.coupling->stats().coupling_seconds;
      t.water += 1e3 * w.coupling->stats().water_seconds;
    }
  t.bullet = std::max(0.0, t.total - t.envelopes - t.reaction - t.terrain - t.push - t.water_coupling - t.water);
  times_ = t;
}

void Session::single_step() { substep(); }

Eigen::Vector3d Session::focus_point() const {
  // The camera looks at the ground's coordinates (the renderer draws in them).
  btVector3 c = contents_.focus->getWorldTransform().getOrigin();
  if (contents_.world != nullptr && !contents_.world->ground().identity()) c = contents_.world->ground().to_ground()(c);
  return {c.x(), c.y(), c.z()};
}

void Session::advance() {
  while (next_action_ < script_.size() && script_[next_action_].frame <= frame_) apply(script_[next_action_++]);
  if (playing) {
    const int n = std::max(1, static_cast<int>(std::lround(frame_seconds * time_scale / options_.substep)));
    for (int k = 0; k < n; ++k) substep();
  }
  if (follow && contents_.focus != nullptr) camera.target = focus_point() + focus_offset_;
  ++frame_;
}

void Session::collect_lines() {
  lines_.clear();
  const int soil_mode = (overlays.contacts ? bullet::debug_draw::kContactBits : 0) |
                        (overlays.reactions ? bullet::debug_draw::kForceBits : 0) |
                        (overlays.tiles ? bullet::debug_draw::kOutlineBits : 0);
  lines_.setDebugMode(soil_mode);
  for (const scenes::SoilContents& s : contents_.soils)
    if (s.coupling != nullptr) s.coupling->debugDraw(&lines_);
  lines_.setDebugMode(overlays.buoyancy ? bullet::debug_draw::kContactBits | bullet::debug_draw::kForceBits : 0);
  for (const scenes::WaterContents& w : contents_.waters)
    if (w.coupling != nullptr) w.coupling->debugDraw(&lines_);
  if (overlays.spray) render::spray_lines(contents_, contents_.bounds, 0.004, lines_);
}

void Session::draw(int width, int height) {
  const auto t0 = Clock::now();
  collect_lines();
  settings.soil_tile_borders = overlays.soil_tiles;
  settings.mesh_edges = overlays.mesh_edges;
  renderer_->draw(camera, width, height, settings, &lines_);
  draw_ms_ = ms_since(t0);
}

void Session::drop(const std::string& shape, double x, double y) {
  if (contents_.world == nullptr) return;
  const std::optional<Eigen::Vector3d> hit =
      renderer_ ? renderer_->pick(Eigen::Vector3d(x, y, 50.0), Eigen::Vector3d(0, 0, -1)) : std::nullopt;
  const double z = (hit ? hit->z() : 0.0) + 1.0 + drop_size;
  const double mass = drop_density * volume_of(shape, drop_size);
  btRigidBody* body =
      contents_.world->add_body(make_shape(shape, drop_size), mass, btVector3(btScalar(x), btScalar(y), btScalar(z)));
  body->setActivationState(DISABLE_DEACTIVATION);
  for (const scenes::SoilContents& s : contents_.soils)
    if (s.coupling != nullptr) s.coupling->add_body(body);
  for (const scenes::WaterContents& w : contents_.waters)
    if (w.coupling != nullptr) w.coupling->add_body(body);
}

bool Session::click(const std::string& shape, double px, double py, int width, int height) {
  const double aspect = double(width) / double(height);
  const Eigen::Vector3d dir = camera.ray(2.0 * px / width - 1.0, 1.0 - 2.0 * py / height, aspect);
  const std::optional<Eigen::Vector3d> hit = renderer_->pick(camera.eye(), dir);
  if (!hit) return false;
  drop(shape, hit->x(), hit->y());
  return true;
}

void Session::set_material(const terrain::Material& material) {
  for (const scenes::SoilContents& s : contents_.soils) {
    terrain::Material m = material;
    m.soil_depth = s.soil->settings().material.soil_depth;
    m.rigid = s.soil->settings().material.rigid;
    s.soil->set_material(m);
  }
}

void Session::screenshot(const std::filesystem::path& file) const { scenes::write_png(file, renderer_->read_image()); }

std::vector<std::filesystem::path> Session::save_soils(const std::filesystem::path& stem) const {
  std::vector<std::filesystem::path> files;
  for (std::size_t k = 0; k < contents_.soils.size(); ++k) {
    const std::filesystem::path f = stem.string() + "_" + std::to_string(k) + ".shore";
    contents_.soils[k].soil->save(f);
    files.push_back(f);
  }
  return files;
}

long Session::active_columns() const {
  long n = 0;
  for (const scenes::SoilContents& s : contents_.soils)
    if (s.coupling != nullptr) n += s.coupling->stats().active_columns;
  return n;
}

long Session::tiles() const {
  long n = 0;
  for (const scenes::SoilContents& s : contents_.soils) n += static_cast<long>(s.soil->tile_count());
  return n;
}

std::size_t Session::soil_memory_bytes() const {
  std::size_t n = 0;
  for (const scenes::SoilContents& s : contents_.soils) n += s.soil->memory_bytes();
  return n;
}

Eigen::Vector2d Session::project(const Eigen::Vector3d& p, int width, int height) const {
  const Eigen::Vector4f c = camera.projection(double(width) / height) * camera.view() *
                            Eigen::Vector4f(float(p.x()), float(p.y()), float(p.z()), 1.0f);
  if (c.w() <= 0) return {-1, -1};
  return {(c.x() / c.w() * 0.5 + 0.5) * width, (0.5 - c.y() / c.w() * 0.5) * height};
}

void Session::apply(const ScriptAction& a) {
  auto on = [&](const std::string& w) { return w == "on" || w == "press"; };
  if (a.verb == "key") {
    const double v = on(a.args[1]) ? 1.0 : 0.0;
    if (a.args[0] == "up")
      forward = v;
    else if (a.args[0] == "down")
      forward = -v;
    else if (a.args[0] == "left")
      turn = v;
    else if (a.args[0] == "right")
      turn = -v;
    else
      throw InvalidSetting("viewer.script line " + std::to_string(a.line), a.args[0], "up, down, left or right");
  } else if (a.verb == "drop") {
    drop(a.args[0], std::stod(a.args[1]), std::stod(a.args[2]));
  } else if (a.verb == "click") {
    // Pixels of the default 1280 x 720 view the script was written for.
    click(a.args[0], std::stod(a.args[1]), std::stod(a.args[2]), 1280, 720);
  } else if (a.verb == "pause") {
    playing = false;
  } else if (a.verb == "play") {
    playing = true;
  } else if (a.verb == "step") {
    single_step();
  } else if (a.verb == "ground") {
    const std::string& m = a.args[0];
    settings.ground = m == "deformation" ? render::GroundColour::deformation
                      : m == "sinkage"   ? render::GroundColour::sinkage
                      : m == "height"    ? render::GroundColour::height
                                         : render::GroundColour::natural;
  } else if (a.verb == "water") {
    const std::string& m = a.args[0];
    settings.water = m == "height"     ? render::WaterColour::height
                     : m == "velocity" ? render::WaterColour::velocity
                                       : render::WaterColour::natural;
  } else if (a.verb == "overlay") {
    const bool v = on(a.args[1]);
    const std::string& n = a.args[0];
    if (n == "contacts")
      overlays.contacts = v;
    else if (n == "reactions")
      overlays.reactions = v;
    else if (n == "buoyancy")
      overlays.buoyancy = v;
    else if (n == "tiles")
      overlays.tiles = v;
    else if (n == "soil_tiles")
      overlays.soil_tiles = v;
    else if (n == "spray")
      overlays.spray = v;
    else if (n == "mesh")
      overlays.mesh_edges = v;
    else
      throw InvalidSetting("viewer.script line " + std::to_string(a.line), n,
                           "contacts, reactions, buoyancy, tiles, soil_tiles, spray, mesh");
  }
}

}  // namespace shore::viewer

#include "shore/scenes/recording.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include <BulletDynamics/Vehicle/btRaycastVehicle.h>

#include "shore/bullet/body_state.h"
#include "shore/bullet/recording_file.h"
#include "shore/core/byte_io.h"
#include "shore/core/checkpoint_file.h"
#include "shore/core/error.h"
#include "shore/core/file_bytes.h"
#include "shore/core/hash.h"
#include "shore/scenes/checkpoint.h"
#include "shore/scenes/contents.h"
#include "shore/scenes/film.h"
#include "shore/scenes/multibody_state.h"
#include "shore/scenes/world.h"
#include "shore/terrain/soil_delta.h"

namespace shore::scenes {
namespace {

using bullet::Recording;

/// Every body of the world in the order the scene added them (scenes::World::bodies()), not
/// the dynamics world's collision-object order, which changes as the couplings add and
/// remove their heightfield tiles during a run: per body its world transform (basis rows,
/// origin) and linear and angular velocity, as btScalars (what the state hash and the
/// pictures read).
void put_bodies(ByteWriter& w, const World& world) {
  for (const btRigidBody* b : world.bodies()) {
    const btTransform& t = b->getWorldTransform();
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a) w.put(t.getBasis()[r][a]);
    for (int a = 0; a < 3; ++a) w.put(t.getOrigin()[a]);
    for (int a = 0; a < 3; ++a) w.put(b->getLinearVelocity()[a]);
    for (int a = 0; a < 3; ++a) w.put(b->getAngularVelocity()[a]);
  }
}

/// Sets the recorded states (already checked finite and of the scene's count).
void apply_bodies(const std::vector<btScalar>& v, World& world) {
  for (std::size_t k = 0; k < world.bodies().size(); ++k) {
    const btScalar* p = v.data() + k * Recording::kBodyScalars;
    btRigidBody& b = *world.bodies()[k];
    const btTransform t(btMatrix3x3(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8]),
                        btVector3(p[9], p[10], p[11]));
    b.setWorldTransform(t);
    b.setInterpolationWorldTransform(t);
    if (btMotionState* m = b.getMotionState()) m->setWorldTransform(t);
    b.setLinearVelocity(btVector3(p[12], p[13], p[14]));
    b.setAngularVelocity(btVector3(p[15], p[16], p[17]));
  }
}

/// A world transform as 12 btScalars: basis rows, origin (Recording::kTransformScalars).
void put_transform(ByteWriter& w, const btTransform& t) {
  for (int r = 0; r < 3; ++r)
    for (int a = 0; a < 3; ++a) w.put(t.getBasis()[r][a]);
  for (int a = 0; a < 3; ++a) w.put(t.getOrigin()[a]);
}

/// The transform put_transform wrote at p.
btTransform take_transform(const btScalar* p) {
  return btTransform(btMatrix3x3(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8]), btVector3(p[9], p[10], p[11]));
}

/// The collider of a multibody's part (0: the base, k: link k - 1), or null.
const btMultiBodyLinkCollider* collider_of(const btMultiBody& m, std::size_t part) {
  return part == 0 ? m.getBaseCollider() : m.getLinkCollider(static_cast<int>(part) - 1);
}

/// What each frame holds of a multibody: its links, state values and which parts have a
/// collider (Recording::MultiBodyLayout).
Recording::MultiBodyLayout layout_of(const btMultiBody& m) {
  Recording::MultiBodyLayout l;
  l.links = static_cast<std::uint32_t>(m.getNumLinks());
  l.values = static_cast<std::uint32_t>(multibody_state(m).size());
  for (std::size_t part = 0; part <= l.links; ++part) l.colliders.push_back(collider_of(m, part) != nullptr ? 1 : 0);
  return l;
}

/// Every multibody of the world in the order the scene added them: its state (what the state
/// hash covers: multibody_state.h), then each of its colliders' world transforms (basis rows,
/// origin: what the pictures and the viewer draw), as btScalars. The colliders are recorded
/// rather than recomputed from the state on replay, so that what a replay draws is the run's
/// whatever Bullet's forward kinematics caches between steps.
void put_multibodies(ByteWriter& w, const World& world) {
  for (const btMultiBody* m : world.multibodies()) {
    for (const btScalar v : multibody_state(*m)) w.put(v);
    for (std::size_t part = 0; part <= static_cast<std::size_t>(m->getNumLinks()); ++part)
      if (const btMultiBodyLinkCollider* c = collider_of(*m, part)) put_transform(w, c->getWorldTransform());
  }
}

/// Every raycast wheel of the scene's vehicles, in order: its world transform (basis rows,
/// origin), as Bullet's vehicle left it and the pictures draw it.
void put_wheels(ByteWriter& w, const SceneContents& c) {
  for (const VehicleContents& v : c.vehicles)
    for (int k = 0; k < v.vehicle->getNumWheels(); ++k) put_transform(w, v.vehicle->getWheelInfo(k).m_worldTransform);
}

/// Places the scene's raycast wheels: as recorded (`wheels`, checked finite and of the scene's
/// counts), or, from a recording without wheels (empty), on the replayed chassis at the
/// suspension length the replaying vehicle last had.
void apply_wheels(const std::vector<btScalar>& wheels, const SceneContents& c) {
  const btScalar* p = wheels.data();
  for (const VehicleContents& v : c.vehicles)
    for (int k = 0; k < v.vehicle->getNumWheels(); ++k) {
      if (wheels.empty()) {
        v.vehicle->updateWheelTransform(k, false);
        continue;
      }
      v.vehicle->getWheelInfo(k).m_worldTransform = take_transform(p);
      p += Recording::kWheelScalars;
    }
}

/// Sets the recorded multibody states and collider transforms (already checked finite and of
/// the scene's layouts).
void apply_multibodies(const std::vector<btScalar>& v, World& world) {
  const btScalar* p = v.data();
  for (btMultiBody* m : world.multibodies()) {
    const std::size_t values = multibody_state(*m).size();
    set_multibody_state(*m, {p, values});
    p += values;
    for (std::size_t part = 0; part <= static_cast<std::size_t>(m->getNumLinks()); ++part) {
      btMultiBodyLinkCollider* c = part == 0 ? m->getBaseCollider() : m->getLinkCollider(static_cast<int>(part) - 1);
      if (c == nullptr) continue;
      const btTransform t = take_transform(p);
      c->setWorldTransform(t);
      c->setInterpolationWorldTransform(t);
      p += Recording::kTransformScalars;
    }
  }
}

/// The scene's contents, refused (InvalidSetting) if they cannot be recorded: no world, or
/// water surfaces that the state hash covers but the contents do not give (so a replay
/// could not write them).
SceneContents recordable(Scene& scene, const std::string& name) {
  SceneContents c = scene.contents();
  const std::string field = "scenes.Recorder(scene " + name + ")";
  if (c.world == nullptr) throw InvalidSetting(field, "no world", "a recorded scene must show its world");
  const std::vector<const water::Surface*> hashed = scene.state().waters;
  bool same = hashed.size() == c.waters.size();
  for (std::size_t k = 0; same && k < hashed.size(); ++k) same = hashed[k] == c.waters[k].surface;
  if (!same)
    throw InvalidSetting(field, std::to_string(hashed.size()) + " hashed water surfaces",
                         "the scene's contents must give the same surfaces, in the same order, to be recorded");
  return c;
}

}  // namespace

// ---- recording ---------------------------------------------------------------------------

struct Recorder::Impl {
  std::filesystem::path file;
  Recording rec;
  std::vector<unsigned char> initial;
  std::vector<std::vector<unsigned char>> owned;  // the frames' bytes, which rec's spans point into
  std::vector<std::uint64_t> sent;                // per soil: the generation its last delta brought
  std::vector<bullet::StateChain> water;          // per water: the last recorded state
  std::vector<int> film;
  int per_frame = 1;
  bool begun = false;
};

Recorder::Recorder(std::filesystem::path file) : impl_(std::make_unique<Impl>()) { impl_->file = std::move(file); }
Recorder::~Recorder() = default;

void Recorder::begin(const SceneType& type, const SceneOptions& options, Scene& scene) {
  Impl& im = *impl_;
  if (im.begun)
    throw InvalidSetting("scenes.Recorder.begin", type.name, "a recorder records one run (make one per run)");
  const SceneContents c = recordable(scene, type.name);
  im.begun = true;
  Recording& rec = im.rec;
  rec.scene = type.name;
  rec.seconds = options.seconds, rec.substep = options.substep, rec.cell = options.cell;
  rec.material = options.material;
  rec.smoke = options.smoke;
  rec.substeps = options.substeps();
  im.per_frame = std::max(1, static_cast<int>(std::lround(1.0 / (kFramesPerSecond * options.substep))));
  im.film = scene.film_substeps();
  im.initial = save_checkpoint(scene).bytes();
  rec.initial = im.initial;
  sizes_.initial = im.initial.size();
  for (const SoilContents& s : c.soils) {
    im.sent.push_back(s.soil->generation());
    rec.terrain_generations.push_back(im.sent.back());
  }
  rec.waters = static_cast<std::uint32_t>(c.waters.size());
  im.water.resize(c.waters.size());
  for (const btMultiBody* m : c.world->multibodies()) rec.multibodies.push_back(layout_of(*m));
  for (const VehicleContents& v : c.vehicles)
    rec.vehicle_wheels.push_back(static_cast<std::uint32_t>(v.vehicle->getNumWheels()));
}

void Recorder::after_substep(Scene& scene, int k) {
  Impl& im = *impl_;
  const bool film = std::find(im.film.begin(), im.film.end(), k) != im.film.end();
  if (k % im.per_frame != 0 && !film && k != im.rec.substeps) return;
  const SceneContents c = scene.contents();
  terrain::DeltaSettings exact;
  exact.quantum = 0.0;  // bit-identical columns, bookkeeping and spray (soil_delta.h)
  Recording::Frame f;
  f.substep = k;
  auto keep = [&](std::vector<unsigned char> bytes) {
    im.owned.push_back(std::move(bytes));
    return std::span<const unsigned char>(im.owned.back());
  };
  for (std::size_t s = 0; s < c.soils.size(); ++s) {
    f.terrain_deltas.push_back(keep(terrain::SoilDelta::encode(*c.soils[s].soil, im.sent[s], exact)));
    sizes_.terrain_deltas += f.terrain_deltas.back().size();
    im.sent[s] = c.soils[s].soil->generation();
  }
  ByteWriter bodies;
  put_bodies(bodies, *c.world);
  f.body_count = static_cast<std::uint32_t>(c.world->bodies().size());
  sizes_.bodies += bodies.bytes.size();
  f.bodies = keep(std::move(bodies.bytes));
  ByteWriter multibodies;
  put_multibodies(multibodies, *c.world);
  sizes_.multibodies += multibodies.bytes.size();
  f.multibodies = keep(std::move(multibodies.bytes));
  ByteWriter wheels;
  put_wheels(wheels, c);
  sizes_.wheels += wheels.bytes.size();
  f.wheels = keep(std::move(wheels.bytes));
  for (std::size_t w = 0; w < c.waters.size(); ++w) {
    f.water_diffs.push_back(keep(im.water[w].encode(c.waters[w].surface->save_state())));
    sizes_.water_states += f.water_diffs.back().size();
  }
  im.rec.frames.push_back(std::move(f));
}

void Recorder::finish(std::uint64_t state_hash) {
  Impl& im = *impl_;
  im.rec.state_hash = state_hash;
  const std::vector<unsigned char> bytes = [&] {
    try {
      return bullet::write_recording(im.rec);
    } catch (const FileError& e) {
      throw FileError(im.file.string() + ": " + e.what());
    }
  }();
  write_file_atomically(im.file, bytes, "recording");
  sizes_.file = bytes.size();
  // Measured: what the water frames take after the outer compression (the others' bytes
  // compressed alike would not add up to the file: zstd finds matches across them).
  if (im.rec.waters > 0) {
    Recording without = bullet::Recording();
    without.scene = im.rec.scene, without.material = im.rec.material;
    without.seconds = im.rec.seconds, without.substep = im.rec.substep, without.cell = im.rec.cell;
    without.smoke = im.rec.smoke, without.substeps = im.rec.substeps, without.state_hash = state_hash;
    without.initial = im.rec.initial, without.terrain_generations = im.rec.terrain_generations;
    without.multibodies = im.rec.multibodies;
    without.vehicle_wheels = im.rec.vehicle_wheels;
    for (const Recording::Frame& f : im.rec.frames) {
      Recording::Frame g;
      g.substep = f.substep, g.terrain_deltas = f.terrain_deltas, g.bodies = f.bodies, g.body_count = f.body_count;
      g.multibodies = f.multibodies;
      g.wheels = f.wheels;
      without.frames.push_back(std::move(g));
    }
    sizes_.water_compressed = bytes.size() - std::min(bytes.size(), bullet::write_recording(without).size());
  }
}

// ---- replaying ---------------------------------------------------------------------------

namespace {

/// The run's options as recorded; out_dir = out_root / scene.
SceneOptions read_options(const Recording& rec, const std::filesystem::path& out_root, const std::string& source) {
  SceneOptions o;
  o.out_dir = out_root / rec.scene;
  o.threads = 1;
  o.seconds = rec.seconds, o.substep = rec.substep, o.cell = rec.cell;
  o.material = rec.material;
  o.smoke = rec.smoke;
  try {
    o.validate();
  } catch (const InvalidSetting& e) {
    throw FileError(source + ": corrupt options (" + e.what() + ")");
  }
  if (rec.substeps != o.substeps()) throw FileError(source + ": corrupt (substeps do not match the options)");
  return o;
}

/// FileError naming the recording and the field if its multibodies are not the scene's: a
/// version 2 file (none recorded) of a scene with multibodies, another count, or a
/// multibody of other links, state values or colliders.
void check_multibodies(const Recording& rec, const World& world, const std::string& source) {
  const std::vector<btMultiBody*>& scene = world.multibodies();
  if (rec.version < 3 && !scene.empty())
    throw FileError(source + ": recording version " + std::to_string(rec.version) +
                    " (written before recordings held multibodies) of a scene with " + std::to_string(scene.size()) +
                    " multibodies: its replay could not move them, record the run again");
  if (rec.multibodies.size() != scene.size())
    throw FileError(source + ": holds " + std::to_string(rec.multibodies.size()) + " multibodies, the scene has " +
                    std::to_string(scene.size()));
  for (std::size_t m = 0; m < scene.size(); ++m) {
    const Recording::MultiBodyLayout& have = rec.multibodies[m];
    const Recording::MultiBodyLayout want = layout_of(*scene[m]);
    const std::string which = source + ", multibody " + std::to_string(m) + ": ";
    if (have.links != want.links)
      throw FileError(which + "link count " + std::to_string(have.links) + ", the scene's has " +
                      std::to_string(want.links));
    if (have.values != want.values)
      throw FileError(which + "state value count " + std::to_string(have.values) + ", the scene's has " +
                      std::to_string(want.values));
    for (std::size_t part = 0; part < want.colliders.size(); ++part)
      if (have.colliders[part] != want.colliders[part])
        throw FileError(
            which + (part == 0 ? std::string("the base") : "link " + std::to_string(part - 1)) +
            (have.colliders[part] ? " has a collider, the scene's has none" : " has no collider, the scene's has one"));
  }
}

/// FileError naming the recording if its vehicles are not the scene's: another count, or a
/// vehicle of another wheel count. A recording without wheels (before version 4) fits any.
void check_vehicles(const Recording& rec, const SceneContents& c, const std::string& source) {
  if (rec.version < 4) return;
  if (rec.vehicle_wheels.size() != c.vehicles.size())
    throw FileError(source + ": holds " + std::to_string(rec.vehicle_wheels.size()) + " vehicles, the scene has " +
                    std::to_string(c.vehicles.size()));
  for (std::size_t v = 0; v < c.vehicles.size(); ++v)
    if (rec.vehicle_wheels[v] != static_cast<std::uint32_t>(c.vehicles[v].vehicle->getNumWheels()))
      throw FileError(source + ", vehicle " + std::to_string(v) + ": holds " + std::to_string(rec.vehicle_wheels[v]) +
                      " wheels, the scene's has " + std::to_string(c.vehicles[v].vehicle->getNumWheels()));
}

/// Applies one frame's soil deltas, bodies, multibodies and water states to the replaying scene.
void apply_frame(const Recording& rec, const Recording::Frame& f, const SceneContents& c,
                 std::vector<std::uint64_t>& at, std::vector<bullet::StateChain>& water, const std::string& source) {
  const std::string where = source + ", frame at substep " + std::to_string(f.substep);
  for (std::size_t s = 0; s < c.soils.size(); ++s) {
    try {
      at[s] = terrain::SoilDelta::apply(*c.soils[s].soil, f.terrain_deltas[s], at[s]);
    } catch (const std::exception& e) {  // FileError or InvalidSetting: the delta does not fit
      throw FileError(where + ", soil " + std::to_string(s) + ": " + e.what());
    }
  }
  if (f.body_count != c.world->bodies().size())
    throw FileError(where + ": holds " + std::to_string(f.body_count) + " bodies, the scene has " +
                    std::to_string(c.world->bodies().size()));
  const std::vector<btScalar> bodies = rec.body_scalars(f, source);
  const std::vector<btScalar> multibodies = rec.multibody_scalars(f, source);
  const std::vector<btScalar> wheels = rec.wheel_scalars(f, source);
  for (std::size_t w = 0; w < c.waters.size(); ++w) {
    const std::string what = where + ", water " + std::to_string(w);
    const std::vector<unsigned char>& state = water[w].next(f.water_diffs[w]);
    c.waters[w].surface->restore_state(state, what);  // FileError naming `what`, the surface unchanged
  }
  apply_bodies(bodies, *c.world);
  apply_multibodies(multibodies, *c.world);
  apply_wheels(wheels, c);
  if (c.clock) *c.clock = f.substep;
}

/// metrics.json of a replay, listed last in res.files.
void write_replay_metrics(ReplayResult& res, const SceneOptions& opt, const std::vector<std::string>& skipped) {
  nlohmann::json m = {{"scene", res.scene},
                      {"replay", true},
                      {"frames", res.frames},
                      {"sim_seconds", res.sim_seconds},
                      {"wall_seconds", res.wall_seconds},
                      {"recording_bytes", res.file_bytes},
                      {"state_hash", to_hex(res.state_hash)},
                      {"recorded_state_hash", to_hex(res.recorded_state_hash)},
                      {"pictures_skipped", skipped}};
  nlohmann::json files = nlohmann::json::array();
  for (const auto& f : res.files) files.push_back(f.filename().string());
  files.push_back("metrics.json");
  m["files"] = files;
  const std::string text = m.dump(2) + "\n";
  write_file_atomically(opt.file("metrics.json"),
                        std::span(reinterpret_cast<const unsigned char*>(text.data()), text.size()), "replay metrics");
  res.files.push_back(opt.file("metrics.json"));
}

}  // namespace

ReplayResult replay(const std::filesystem::path& file, const std::filesystem::path& out_root, bool write_files,
                    Painter* painter, ProgressMode progress_mode, const FrameHook& after_frame) {
  const auto t0 = std::chrono::steady_clock::now();
  ReplayResult res;
  const std::string source = "recording " + file.string();
  const Recording rec = [&] {
    const std::vector<unsigned char> bytes = read_file_bytes(file, "recording");
    res.file_bytes = bytes.size();
    return bullet::read_recording(bytes, source);
  }();
  res.scene = rec.scene;
  const SceneType* type = find_scene(res.scene);
  if (type == nullptr) throw FileError(source + ": names no scene of this build (" + res.scene + ")");
  SceneOptions opt = read_options(rec, out_root, source);
  opt.write_files = write_files;
  const int substeps = rec.substeps;
  res.recorded_state_hash = rec.state_hash;

  const std::unique_ptr<Scene> scene = type->create(opt);
  restore_checkpoint(*scene, CheckpointReader({rec.initial.begin(), rec.initial.end()},
                                              file.string() + " (initial state)", bullet::scalar_bytes()));
  const SceneContents c = recordable(*scene, res.scene);
  if (rec.terrain_generations.size() != c.soils.size())
    throw FileError(source + ": holds " + std::to_string(rec.terrain_generations.size()) + " soils, the scene has " +
                    std::to_string(c.soils.size()));
  if (rec.waters != c.waters.size())
    throw FileError(source + ": holds " + std::to_string(rec.waters) + " water surfaces, the scene has " +
                    std::to_string(c.waters.size()));
  check_multibodies(rec, *c.world, source);
  check_vehicles(rec, c, source);
  std::vector<std::uint64_t> at = rec.terrain_generations;
  std::vector<bullet::StateChain> water(c.waters.size());

  const bool film = write_files && painter != nullptr;
  const std::vector<int> film_at = film ? scene->film_substeps() : std::vector<int>{};
  std::vector<Image> frames;
  std::vector<std::string> labels;
  double picture_seconds = 0.0;
  auto take_film = [&](int k) {
    if (std::find(film_at.begin(), film_at.end(), k) == film_at.end()) return;
    const auto p0 = std::chrono::steady_clock::now();
    frames.push_back(scene->film_frame(*painter));
    labels.push_back(time_label(k * opt.substep));
    picture_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - p0).count();
  };
  take_film(0);
  Progress progress(res.scene + " replay", progress_mode);
  res.frames = static_cast<int>(rec.frames.size());
  for (const Recording::Frame& f : rec.frames) {
    apply_frame(rec, f, c, at, water, source);
    if (after_frame) after_frame(*scene, f.substep);
    take_film(f.substep);
    progress.update(static_cast<double>(f.substep) / substeps);
  }
  res.sim_seconds = substeps * opt.substep;
  res.state_hash = state_hash(scene->state());
  res.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() - picture_seconds;
  if (write_files) {
    std::filesystem::create_directories(opt.out_dir);
    Drawing drawing(opt, frames.empty() ? Image() : scenes::filmstrip(frames, labels, 3), painter, scene->contents());
    scene->draw(drawing);
    res.files = drawing.files();
    write_replay_metrics(res, opt, drawing.skipped());
  }
  return res;
}

}  // namespace shore::scenes

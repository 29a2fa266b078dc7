#include "shore/scenes/recording.h"

#include <zstd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "shore/bullet/body_state.h"
#include "shore/core/byte_io.h"
#include "shore/core/checkpoint_file.h"
#include "shore/core/error.h"
#include "shore/core/file_bytes.h"
#include "shore/core/hash.h"
#include "shore/scenes/checkpoint.h"
#include "shore/scenes/contents.h"
#include "shore/scenes/film.h"
#include "shore/scenes/world.h"
#include "shore/terrain/soil_delta.h"

namespace shore::scenes {
namespace {

constexpr char kMagic[8] = {'S', 'H', 'O', 'R', 'E', 'R', 'E', 'C'};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint32_t kByteOrderMark = 0x01020304u;
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 4 + 8 + 8;
constexpr std::uint64_t kMaxRawBytes = std::uint64_t{1} << 36;
constexpr int kCompressionLevel = 3;

std::uint64_t checksum(const unsigned char* data, std::size_t size) {
  StateHash h;
  h.add_bytes(data, size);
  return h.value();
}

void put_string(ByteWriter& w, const std::string& s) {
  w.put(static_cast<std::uint32_t>(s.size()));
  w.bytes.insert(w.bytes.end(), s.begin(), s.end());
}
void put_bytes(ByteWriter& w, const std::vector<unsigned char>& b) {
  w.put(static_cast<std::uint64_t>(b.size()));
  w.bytes.insert(w.bytes.end(), b.begin(), b.end());
}

/// Reads the raw (decompressed) bytes of a recording, naming it in every error.
class RecordReader : public ByteReader {
 public:
  RecordReader(std::span<const unsigned char> raw, const std::string& source) : ByteReader(raw, source), raw_(raw) {}
  std::string string(const char* what) {
    const auto size = get<std::uint32_t>(what);
    if (size > remaining()) fail(std::string("truncated (ends inside ") + what + ")");
    return {reinterpret_cast<const char*>(take(size).data()), size};
  }
  std::span<const unsigned char> bytes(const char* what) {
    const auto size = get<std::uint64_t>(what);
    if (size > remaining()) fail(std::string("truncated (ends inside ") + what + ")");
    return take(size);
  }

 private:
  std::span<const unsigned char> take(std::size_t size) {
    const std::span<const unsigned char> out = raw_.subspan(raw_.size() - remaining(), size);
    skip(size, "bytes");
    return out;
  }
  std::span<const unsigned char> raw_;
};

// A body's recorded state: its world transform (basis rows, origin) and its linear and
// angular velocity, as btScalars: what the state hash and the pictures read.
constexpr int kBodyScalars = 18;

/// Every body of the world in the order the scene added them (scenes::World::bodies()), not
/// the dynamics world's collision-object order, which changes as the couplings add and
/// remove their heightfield tiles during a run.
void put_bodies(ByteWriter& w, const World& world) {
  w.put(static_cast<std::uint32_t>(world.bodies().size()));
  for (const btRigidBody* b : world.bodies()) {
    const btTransform& t = b->getWorldTransform();
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a) w.put(t.getBasis()[r][a]);
    for (int a = 0; a < 3; ++a) w.put(t.getOrigin()[a]);
    for (int a = 0; a < 3; ++a) w.put(b->getLinearVelocity()[a]);
    for (int a = 0; a < 3; ++a) w.put(b->getAngularVelocity()[a]);
  }
}

/// Reads them all, checks them, then sets them (the world untouched on an error).
void apply_bodies(ByteReader& r, World& world) {
  const auto count = r.get<std::uint32_t>("the body count");
  if (count != world.bodies().size())
    r.fail("holds " + std::to_string(count) + " bodies, the scene has " + std::to_string(world.bodies().size()));
  std::vector<btScalar> v(static_cast<std::size_t>(count) * kBodyScalars);
  for (btScalar& x : v)
    if (!std::isfinite(static_cast<double>(x = r.get<btScalar>("a body")))) r.fail("corrupt (a non-finite body state)");
  for (std::uint32_t k = 0; k < count; ++k) {
    const btScalar* p = v.data() + static_cast<std::size_t>(k) * kBodyScalars;
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

/// The scene's contents, refused (InvalidSetting) if they cannot be recorded.
SceneContents recordable(Scene& scene, const std::string& name) {
  SceneContents c = scene.contents();
  const std::string field = "scenes.Recorder(scene " + name + ")";
  if (c.world == nullptr) throw InvalidSetting(field, "no world", "a recorded scene must show its world");
  if (!c.waters.empty() || !scene.state().waters.empty())
    throw InvalidSetting(field, "has water",
                         "scenes with water are not recorded: water gets no deltas and a replay re-simulates nothing");
  return c;
}

}  // namespace

// ---- recording ---------------------------------------------------------------------------

struct Recorder::Impl {
  std::filesystem::path file;
  ByteWriter head;    // everything before the frames
  ByteWriter frames;  // the frames
  std::uint32_t frame_count = 0;
  std::vector<std::uint64_t> sent;  // per soil: the generation its last delta brought
  std::vector<int> film;
  int substeps = 0, per_frame = 1;
  std::size_t hash_at = 0;  // where in `head` the final state hash goes
};

Recorder::Recorder(std::filesystem::path file) : impl_(std::make_unique<Impl>()) { impl_->file = std::move(file); }
Recorder::~Recorder() = default;

void Recorder::begin(const SceneType& type, const SceneOptions& options, Scene& scene) {
  Impl& im = *impl_;
  if (!im.head.bytes.empty())
    throw InvalidSetting("scenes.Recorder.begin", type.name, "a recorder records one run (make one per run)");
  const SceneContents c = recordable(scene, type.name);
  im.substeps = options.substeps();
  im.per_frame = std::max(1, static_cast<int>(std::lround(1.0 / (kFramesPerSecond * options.substep))));
  im.film = scene.film_substeps();
  ByteWriter& w = im.head;
  put_string(w, type.name);
  w.put(options.seconds), w.put(options.substep), w.put(options.cell);
  put_string(w, options.material);
  w.put(static_cast<std::uint8_t>(options.smoke ? 1 : 0));
  w.put(static_cast<std::int32_t>(im.substeps));
  im.hash_at = w.bytes.size();  // the final state hash, written at finish()
  w.put(std::uint64_t{0});
  const std::vector<unsigned char> initial = save_checkpoint(scene).bytes();
  sizes_.initial = initial.size();
  put_bytes(w, initial);
  w.put(static_cast<std::uint32_t>(c.soils.size()));
  for (const SoilContents& s : c.soils) {
    im.sent.push_back(s.soil->generation());
    w.put(im.sent.back());
  }
}

void Recorder::after_substep(Scene& scene, int k) {
  Impl& im = *impl_;
  const bool film = std::find(im.film.begin(), im.film.end(), k) != im.film.end();
  if (k % im.per_frame != 0 && !film && k != im.substeps) return;
  const SceneContents c = scene.contents();
  terrain::DeltaSettings exact;
  exact.quantum = 0.0;  // bit-identical columns, bookkeeping and spray (soil_delta.h)
  im.frames.put(static_cast<std::int32_t>(k));
  for (std::size_t s = 0; s < c.soils.size(); ++s) {
    const std::vector<unsigned char> delta = terrain::SoilDelta::encode(*c.soils[s].soil, im.sent[s], exact);
    sizes_.soil_deltas += delta.size();
    put_bytes(im.frames, delta);
    im.sent[s] = c.soils[s].soil->generation();
  }
  const std::size_t before = im.frames.bytes.size();
  put_bodies(im.frames, *c.world);
  sizes_.bodies += im.frames.bytes.size() - before;
  ++im.frame_count;
}

void Recorder::finish(std::uint64_t state_hash) {
  Impl& im = *impl_;
  ByteWriter raw = std::move(im.head);
  std::memcpy(raw.bytes.data() + im.hash_at, &state_hash, sizeof state_hash);
  raw.put(im.frame_count);
  raw.bytes.insert(raw.bytes.end(), im.frames.bytes.begin(), im.frames.bytes.end());

  ByteWriter out;
  for (char ch : kMagic) out.put(ch);
  out.put(kVersion), out.put(kByteOrderMark), out.put(bullet::scalar_bytes());
  out.put(static_cast<std::uint64_t>(raw.bytes.size()));
  const std::size_t frame_at = out.bytes.size() + 8;
  out.bytes.resize(frame_at + ZSTD_compressBound(raw.bytes.size()));
  const std::size_t frame = ZSTD_compress(out.bytes.data() + frame_at, out.bytes.size() - frame_at, raw.bytes.data(),
                                          raw.bytes.size(), kCompressionLevel);
  if (ZSTD_isError(frame) != 0)
    throw FileError("recording " + im.file.string() + ": zstd failed (" + ZSTD_getErrorName(frame) + ")");
  out.bytes.resize(frame_at + frame);
  const auto frame_size = static_cast<std::uint64_t>(frame);
  std::memcpy(out.bytes.data() + frame_at - 8, &frame_size, sizeof frame_size);
  out.put(checksum(out.bytes.data(), out.bytes.size()));
  write_file_atomically(im.file, out.bytes, "recording");
  sizes_.file = out.bytes.size();
}

// ---- replaying ---------------------------------------------------------------------------

namespace {

/// The checked, decompressed raw bytes of a recording file.
std::vector<unsigned char> read_recording(const std::filesystem::path& file, std::size_t& file_bytes) {
  const std::vector<unsigned char> bytes = read_file_bytes(file, "recording");
  file_bytes = bytes.size();
  ByteReader r(bytes, "recording " + file.string());
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    r.fail("not a Shore recording (magic \"SHOREREC\" missing)");
  if (bytes.size() < kHeaderBytes + 8) r.fail("truncated (" + std::to_string(bytes.size()) + " bytes)");
  for (std::size_t k = 0; k < sizeof kMagic; ++k) (void)r.get<char>("magic");
  const auto version = r.get<std::uint32_t>("version");
  if (version != kVersion)
    r.fail("unsupported recording version " + std::to_string(version) + " (this build reads " +
           std::to_string(kVersion) + ")");
  if (r.get<std::uint32_t>("byte-order mark") != kByteOrderMark) r.fail("written with the other byte order");
  const auto scalar = r.get<std::uint32_t>("precision");
  const auto raw_size = r.get<std::uint64_t>("header"), frame_size = r.get<std::uint64_t>("header");
  if (frame_size != bytes.size() - kHeaderBytes - 8)
    r.fail("truncated or padded (a compressed body of " + std::to_string(frame_size) + " bytes in a file of " +
           std::to_string(bytes.size()) + ")");
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, sizeof stored);
  if (stored != checksum(bytes.data(), bytes.size() - 8)) r.fail("checksum mismatch (corrupt)");
  if (scalar != bullet::scalar_bytes())
    r.fail("written by a build with " + std::to_string(8 * scalar) + "-bit Bullet scalars, this one uses " +
           std::to_string(8 * bullet::scalar_bytes()) + "-bit (SHORE_DOUBLE_PRECISION differs)");
  if (raw_size > kMaxRawBytes) r.fail("corrupt header (raw size " + std::to_string(raw_size) + ")");
  std::vector<unsigned char> raw(raw_size);
  const std::size_t got = ZSTD_decompress(raw.data(), raw.size(), bytes.data() + kHeaderBytes, frame_size);
  if (ZSTD_isError(got) != 0) r.fail(std::string("zstd: ") + ZSTD_getErrorName(got));
  if (got != raw.size()) r.fail("corrupt (decompressed size differs from the header's)");
  return raw;
}

/// The run's options as recorded; out_dir = out_root / scene.
SceneOptions read_options(RecordReader& r, const std::filesystem::path& out_root, const std::string& scene) {
  SceneOptions o;
  o.out_dir = out_root / scene;
  o.threads = 1;
  o.seconds = r.get<double>("options"), o.substep = r.get<double>("options"), o.cell = r.get<double>("options");
  o.material = r.string("options");
  o.smoke = r.get<std::uint8_t>("options") != 0;
  try {
    o.validate();
  } catch (const InvalidSetting& e) {
    r.fail(std::string("corrupt options (") + e.what() + ")");
  }
  return o;
}

/// Applies one frame's soil deltas and bodies to the replaying scene.
void apply_frame(RecordReader& r, const SceneContents& c, std::vector<std::uint64_t>& at, int k,
                 const std::string& source) {
  const std::string where = source + ", frame at substep " + std::to_string(k);
  for (std::size_t s = 0; s < c.soils.size(); ++s) {
    const std::span<const unsigned char> delta = r.bytes("a soil delta");
    try {
      at[s] = terrain::SoilDelta::apply(*c.soils[s].soil, delta, at[s]);
    } catch (const std::exception& e) {  // FileError or InvalidSetting: the delta does not fit
      throw FileError(where + ", soil " + std::to_string(s) + ": " + e.what());
    }
  }
  apply_bodies(r, *c.world);
  if (c.clock) *c.clock = k;
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
                    Painter* painter, ProgressMode progress_mode) {
  const auto t0 = std::chrono::steady_clock::now();
  ReplayResult res;
  const std::vector<unsigned char> raw = read_recording(file, res.file_bytes);
  const std::string source = "recording " + file.string();
  RecordReader r(raw, source);
  res.scene = r.string("the scene name");
  const SceneType* type = find_scene(res.scene);
  if (type == nullptr) r.fail("names no scene of this build (" + res.scene + ")");
  SceneOptions opt = read_options(r, out_root, res.scene);
  opt.write_files = write_files;
  const auto substeps = r.get<std::int32_t>("substeps");
  if (substeps != opt.substeps()) r.fail("corrupt (substeps do not match the options)");
  res.recorded_state_hash = r.get<std::uint64_t>("the final state hash");
  const std::span<const unsigned char> initial = r.bytes("the initial checkpoint");

  const std::unique_ptr<Scene> scene = type->create(opt);
  restore_checkpoint(*scene, CheckpointReader({initial.begin(), initial.end()}, file.string() + " (initial state)",
                                              bullet::scalar_bytes()));
  const SceneContents c = recordable(*scene, res.scene);
  const auto soils = r.get<std::uint32_t>("soil count");
  if (soils != c.soils.size())
    r.fail("holds " + std::to_string(soils) + " soils, the scene has " + std::to_string(c.soils.size()));
  std::vector<std::uint64_t> at(soils);
  for (auto& g : at) g = r.get<std::uint64_t>("a soil's generation");

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
  res.frames = static_cast<int>(r.get<std::uint32_t>("frame count"));
  int last = 0;
  for (int f = 0; f < res.frames; ++f) {
    const auto k = r.get<std::int32_t>("a frame's substep");
    if (k <= last || k > substeps)
      r.fail("corrupt (frame at substep " + std::to_string(k) + " after " + std::to_string(last) + ")");
    apply_frame(r, c, at, k, source);
    take_film(last = k);
    progress.update(static_cast<double>(k) / substeps);
  }
  if (r.remaining() != 0) r.fail("corrupt (bytes after the last frame)");
  if (last != substeps)
    r.fail("truncated (the last frame is at substep " + std::to_string(last) + " of " + std::to_string(substeps) + ")");
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
